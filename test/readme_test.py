"""The README's commands and examples run as written.

Run by `scripts/test.sh` through catkin's run_tests with RRR_BUILD_DIR set to
the build folder (the `rrr` program must be built there).
"""
import os
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
BUILD = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
RRR = BUILD / "devel" / "lib" / "rrr_slam" / "rrr"


def example_commands():
    """The commands of the README's example block (between the
    readme-example markers), comments dropped."""
    text = README.read_text()
    match = re.search(r"<!-- readme-example -->\n(.*?)<!-- /readme-example -->", text, re.S)
    assert match, f"{README}: no block between <!-- readme-example --> and <!-- /readme-example -->"
    lines = [line.strip() for line in match.group(1).splitlines()]
    return [line for line in lines if line and not line.startswith("#")]


def test_the_readme_starts_with_exactly_two_commands_for_a_fresh_machine():
    blocks = re.findall(r"((?:^    \S.*\n)+)", README.read_text(), re.M)
    first = [line.split("#")[0].strip() for line in blocks[0].splitlines()]
    assert first == ["bash scripts/setup.sh && bash scripts/demo.sh",
                     "bash scripts/setup.sh && bash scripts/test.sh"], first
    for script in ("setup.sh", "demo.sh", "test.sh"):
        assert (ROOT / "scripts" / script).is_file(), f"README names scripts/{script}, which is missing"


def test_every_file_the_readme_links_exists():
    for target in re.findall(r"\]\(([^)#:]+)\)", README.read_text()):
        assert (ROOT / target).exists(), f"README links {target}, which does not exist"


def test_the_readme_is_short():
    lines = len(README.read_text().splitlines())
    assert lines <= 400, f"README.md has {lines} lines (at most 400: longer material goes to doc/)"


@pytest.mark.skipif(not RRR.is_file(), reason=f"{RRR} is not built")
def test_the_cli_examples_run_as_written(tmp_path):
    commands = example_commands()
    assert len(commands) >= 8 and all(c.startswith("rrr ") for c in commands), commands
    outputs = []
    for command in commands:
        result = subprocess.run(str(RRR) + command[len("rrr"):], shell=True, cwd=tmp_path,
                                capture_output=True, text=True, timeout=600)
        assert result.returncode == 0, f"`{command}` exited {result.returncode}:\n{result.stderr}"
        outputs.append(result.stdout)
        for name in re.findall(r"--(?:output|report|truth|ground-truth) (\S+)", command):
            assert (tmp_path / name).stat().st_size > 0, f"`{command}` wrote no {name}"
    # evaluate prints the scores of the map verify wrote: precision and recall.
    evaluate = next(o for c, o in zip(commands, outputs) if c.startswith("rrr evaluate"))
    assert re.search(r"precision\s*[=:]?\s*1\.0", evaluate), evaluate
