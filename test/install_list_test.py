"""The install list (scripts/debian_packages.sh: package.xml through
scripts/debian_packages.yaml) covers everything the package uses.

Run by `scripts/test.sh` through catkin's run_tests with RRR_BUILD_DIR set to
the build folder; the last test needs a finished build in it.
"""
import ast
import os
import pathlib
import re
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
TABLE = ROOT / "scripts" / "debian_packages.yaml"


def table():
    """key -> {"debian": [...], "cmake": [...], "python": [...]}, read from
    the one-line-per-key table."""
    entries = {}
    for number, line in enumerate(TABLE.read_text().splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        match = re.fullmatch(r"([\w.+-]+): \{(.*)\}", line)
        assert match, f"{TABLE}:{number}: not `key: {{debian: [...], ...}}`"
        fields = dict(re.findall(r"(\w+): \[([^]]*)\]", match.group(2)))
        entries[match.group(1)] = {
            name: [v.strip() for v in fields.get(name, "").split(",") if v.strip()]
            for name in ("debian", "cmake", "python")
        }
    return entries


def dependency_keys():
    root = ElementTree.parse(ROOT / "package.xml").getroot()
    return {e.text.strip() for e in root if e.tag.endswith("depend")}


def derived_list(*flags):
    result = subprocess.run(["bash", str(ROOT / "scripts" / "debian_packages.sh"), *flags],
                            capture_output=True, text=True)
    return result


def provided(kind):
    """Names of `kind` ("cmake" or "python") -> the key that provides them."""
    names = {}
    for key, entry in table().items():
        for name in entry[kind]:
            names[name] = key
    return names


def test_every_dependency_key_has_debian_packages():
    result = derived_list("--doc")
    assert result.returncode == 0, result.stderr
    assert "libroscpp-dev" in result.stdout.split()


def copy_with_extra_key(tmp_path, debian_packages=None):
    """A copy of the package's scripts and package.xml with one more
    dependency key, no_such_key, that the table maps to `debian_packages`
    (no entry when None)."""
    (tmp_path / "scripts").mkdir()
    for name in ("setup.sh", "debian_packages.sh", "debian_packages.yaml"):
        (tmp_path / "scripts" / name).write_text((ROOT / "scripts" / name).read_text())
    if debian_packages is not None:
        with open(tmp_path / "scripts" / "debian_packages.yaml", "a") as table_file:
            table_file.write(f"no_such_key: {{debian: [{', '.join(debian_packages)}]}}\n")
    xml = (ROOT / "package.xml").read_text().replace(
        "<depend>roscpp</depend>", "<depend>roscpp</depend><depend>no_such_key</depend>")
    (tmp_path / "package.xml").write_text(xml)
    return tmp_path


def test_a_key_missing_from_the_table_is_named(tmp_path):
    # The script, run on a copy of the package whose package.xml has a key
    # the table lacks, must fail and name it.
    package = copy_with_extra_key(tmp_path)
    result = subprocess.run(["bash", str(package / "scripts" / "debian_packages.sh")],
                            capture_output=True, text=True)
    assert result.returncode != 0
    assert "no_such_key" in result.stderr


def setup_with_commands(package, commands):
    """scripts/setup.sh of `package`, run with a PATH of only the tools it
    needs before the build, and `commands` (name -> shell script) in place
    of the real ones of those names."""
    tools = package / "bin"
    tools.mkdir()
    for name in ("bash", "dirname", "grep", "sed", "sort", "tr", "dpkg-query", "id", "env",
                 "apt-get"):
        if name not in commands:
            (tools / name).symlink_to(subprocess.run(
                ["bash", "-c", f"command -v {name}"], capture_output=True, text=True,
                check=True).stdout.strip())
    for name, script in commands.items():
        (tools / name).write_text("#!/bin/sh\n" + script + "\n")
        (tools / name).chmod(0o755)
    return subprocess.run(["bash", str(package / "scripts" / "setup.sh")], capture_output=True,
                          text=True, env={"PATH": str(tools), "HOME": str(package)})


def test_setup_without_root_or_sudo_names_what_it_cannot_install(tmp_path):
    # A user who is not root on a machine without sudo: setup must stop
    # before apt-get, naming the missing package and what to do.
    package = copy_with_extra_key(tmp_path, ["rrr-no-such-package"])
    result = setup_with_commands(package, {"id": "echo 1000",
                                           "apt-get": "echo apt-get was run >&2; exit 3"})
    assert result.returncode == 1, result.stderr
    assert "rrr-no-such-package" in result.stderr
    assert "root" in result.stderr and "sudo" in result.stderr
    assert "apt-get was run" not in result.stderr


def test_setup_fails_when_apt_leaves_a_package_missing(tmp_path):
    # An apt-get that reports success without installing everything must
    # not let setup go on to a build that fails far from the cause.
    package = copy_with_extra_key(tmp_path, ["rrr-no-such-package"])
    result = setup_with_commands(package, {"id": "echo 0", "apt-get": "exit 0"})
    assert result.returncode == 1, result.stderr
    assert "not installed: rrr-no-such-package" in result.stderr


def test_every_table_entry_names_debian_packages():
    for key, entry in table().items():
        assert entry["debian"], f"{TABLE}: '{key}' lists no Debian package"


def cmake_names():
    """Every package name find_package() asks for in CMakeLists.txt, with
    catkin's COMPONENTS and the variables they use expanded."""
    text = re.sub(r"#.*", "", (ROOT / "CMakeLists.txt").read_text())
    variables = {m.group(1): m.group(2).split()
                 for m in re.finditer(r"set\((\w+)\s+([^)]*)\)", text)}
    names = set()
    for call in re.finditer(r"find_package\(([^)]*)\)", text):
        words = []
        for word in call.group(1).split():
            expansion = re.fullmatch(r"\$\{(\w+)\}", word)
            words += variables.get(expansion.group(1), []) if expansion else [word]
        names.add(words[0])
        if "COMPONENTS" in words:
            names.update(w for w in words[words.index("COMPONENTS") + 1:]
                         if not w.isupper())
    return names


def test_every_find_package_name_is_a_dependency():
    keys = dependency_keys()
    aliases = provided("cmake")
    names = cmake_names()
    assert {"catkin", "roscpp", "Eigen3"} <= names
    missing = sorted(n for n in names if aliases.get(n, n) not in keys)
    assert not missing, (f"find_package names with no package.xml dependency "
                         f"(add the key, and its cmake name to {TABLE.name}): {missing}")


def python_files():
    return [p for d in ("scripts", "bench", "test", "src") for p in (ROOT / d).rglob("*.py")]


def test_every_python_import_is_a_dependency():
    keys = dependency_keys()
    aliases = provided("python")
    # The scripts' own modules, and this package's generated messages.
    own_name = ElementTree.parse(ROOT / "package.xml").getroot().findtext("name")
    local = {p.stem for p in python_files()} | {own_name}
    missing = set()
    for path in python_files():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                modules = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                modules = [node.module]
            else:
                continue
            for module in (m.split(".")[0] for m in modules):
                if module in sys.stdlib_module_names or module in local:
                    continue
                if aliases.get(module) not in keys:
                    missing.add(f"{path.relative_to(ROOT)}: {module}")
    assert not missing, f"Python imports with no package.xml dependency: {sorted(missing)}"


def dependency_closure(packages):
    """The installed packages that `packages` depend on, recursively."""
    output = subprocess.run(
        ["apt-cache", "depends", "--recurse", "--installed", "--no-recommends",
         "--no-suggests", "--no-conflicts", "--no-breaks", "--no-replaces",
         "--no-enhances", *packages], capture_output=True, text=True, check=True).stdout
    return {line.split(":")[0] for line in output.splitlines()
            if line and not line.startswith((" ", "<"))}


def owners(paths):
    """path -> the Debian packages that own it (empty if none). A path under
    /usr/lib may be registered without /usr (merged /usr)."""
    def query(candidates):
        result = subprocess.run(["dpkg-query", "-S", *candidates],
                                capture_output=True, text=True)
        owned = {}
        for line in result.stdout.splitlines():
            pkgs, path = line.rsplit(": ", 1)
            owned[path] = {p.strip().split(":")[0] for p in pkgs.split(",")}
        return owned

    found = query(paths)
    rest = [p for p in paths if p not in found]
    alternatives = {}
    for path in rest:
        for other in {os.path.realpath(path), re.sub(r"^/usr/lib/", "/lib/", path)} - {path}:
            alternatives[other] = path
    for other, pkgs in query(sorted(alternatives)).items():
        found.setdefault(alternatives[other], set()).update(pkgs)
    return {path: found.get(path, set()) for path in paths}


def files_the_build_used(build):
    """System headers the compiler read and libraries the linker was given."""
    used = set()
    for depfile in build.rglob("*.o.d"):
        for word in depfile.read_text().replace("\\\n", " ").split():
            if word.startswith("/usr/"):
                used.add(os.path.normpath(word))
    for link in build.rglob("link.txt"):
        for word in link.read_text().split():
            if word.startswith("/usr/") and (".so" in word or word.endswith(".a")):
                used.add(os.path.normpath(word))
    return used


def test_every_file_the_build_used_comes_from_the_list():
    build = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
    if not any(build.rglob("*.o.d")):
        pytest.skip(f"no build in {build}")
    result = derived_list()
    assert result.returncode == 0, result.stderr
    closure = dependency_closure(result.stdout.split())
    used = files_the_build_used(build)
    assert len(used) > 100
    outside = {path: pkgs for path, pkgs in owners(sorted(used)).items()
               if not pkgs & closure}
    assert not outside, ("files the build used that the install list does not "
                         f"bring (path: owning packages): {outside}")


def test_every_python_module_imported_comes_from_the_list():
    result = derived_list()
    closure = dependency_closure(result.stdout.split())
    for module in sorted(provided("python")):
        if table()[provided("python")[module]]["debian"][0] not in result.stdout.split():
            continue
        spec = subprocess.run([sys.executable, "-c", f"import {module}; print({module}.__file__)"],
                              capture_output=True, text=True)
        assert spec.returncode == 0, f"{module} does not import: {spec.stderr}"
        path = spec.stdout.strip()
        pkgs = owners([path])[path]
        assert pkgs & closure, f"{module} ({path}) comes from {pkgs or 'no package'}"
