"""Shared helpers of the benchmark scripts: where things are, running rrr."""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
import ros_processes  # noqa: E402

# The rrr tool of the package's build, or the one RRR_BIN names (to keep a
# long benchmark on one build while the package is rebuilt).
RRR = pathlib.Path(os.environ.get("RRR_BIN", ROOT / "_build" / "devel" / "lib" / "rrr_slam" / "rrr"))


def datasets_dir():
    """RRR_DATASETS, else ../shared/datasets beside the repository; exits with
    a clear message when it is missing."""
    path = pathlib.Path(os.environ.get("RRR_DATASETS", ROOT.parent / "shared" / "datasets"))
    if not path.is_dir():
        sys.exit(f"datasets not found at {path}: set RRR_DATASETS to the datasets folder")
    return path


def dataset_path(name):
    """The g2o file of dataset NAME: synthetic/NAME.g2o, else more/NAME.g2o
    (the first that exists; the synthetic one, to be named as missing, if
    neither does)."""
    for folder in ("synthetic", "more"):
        path = datasets_dir() / folder / f"{name}.g2o"
        if path.exists():
            return path
    return datasets_dir() / "synthetic" / f"{name}.g2o"


def require_rrr():
    if not RRR.exists():
        sys.exit(f"{RRR} not built: run scripts/setup.sh first")


def run(*args):
    """Runs rrr with `args`; returns stdout, exits on failure."""
    return run_measured(*args)[0]


def run_measured(*args, timeout=None):
    """Runs rrr with `args`; returns (stdout, peak resident memory in MB of
    that process), exits on failure; raises subprocess.TimeoutExpired (the
    process killed) after `timeout` seconds if given."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        process = subprocess.Popen([str(RRR), *map(str, args)], stdout=out, stderr=err)
        start = time.time()
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG if timeout else 0)
            if pid:
                break
            if time.time() - start > timeout:
                process.kill()
                os.wait4(process.pid, 0)
                raise subprocess.TimeoutExpired([str(RRR), *map(str, args)], timeout)
            time.sleep(0.2)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(), err.read().decode()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"rrr {' '.join(map(str, args))} failed:\n{stdout}{stderr}")
    return stdout, usage.ru_maxrss / 1024.0


def read_json(path):
    with open(path) as f:
        return json.load(f)


def verify(graph, window, out_dir, repeat=1, extra=()):
    """Runs rrr verify `repeat` times; returns (report, median seconds, map
    path); the report gains "peak_rss_mb", the largest over the runs."""
    out_dir = pathlib.Path(out_dir)
    out_map, report = out_dir / "verified.g2o", out_dir / "report.json"
    seconds, peaks = [], []
    for _ in range(repeat):
        _, peak = run_measured("verify", graph, "--window", window, "--output", out_map,
                               "--report", report, *extra)
        seconds.append(read_json(report)["seconds"])
        peaks.append(peak)
    result = read_json(report)
    result["peak_rss_mb"] = max(peaks)
    return result, statistics.median(seconds), out_map


def add_verify_arguments(parser):
    """The rrr verify options every benchmark script passes on."""
    parser.add_argument("--method", default="rrr", choices=["rrr", "dcs", "gnc", "pcm"],
                        help="pass --method to rrr verify (the other robust back-ends)")
    parser.add_argument("--procedure", default="map", choices=["map", "published"],
                        help="pass --procedure to rrr verify")
    parser.add_argument("--span-gate", action="store_true",
                        help="pass --span-gate to rrr verify (published procedure)")
    parser.add_argument("--trust-region", action="store_true",
                        help="pass --trust-region to rrr verify (published procedure)")
    parser.add_argument("--threads", type=int,
                        help="pass --threads to rrr verify (default: rrr's, every core)")
    parser.add_argument("--noise-margin", type=float,
                        help="pass --noise-margin to rrr verify (map procedure)")
    parser.add_argument("--noise-scale", type=float,
                        help="pass --noise-scale to rrr verify (map procedure; 0 estimates it)")


def verify_flags(args):
    """rrr verify flags for a script's add_verify_arguments options."""
    flags = ["--method", args.method, "--procedure", args.procedure]
    if args.span_gate:
        flags.append("--span-gate")
    if args.trust_region:
        flags.append("--trust-region")
    if args.threads:
        flags += ["--threads", args.threads]
    if args.noise_margin is not None:
        flags += ["--noise-margin", args.noise_margin]
    if args.noise_scale is not None:
        flags += ["--noise-scale", args.noise_scale]
    return flags


def evaluate(report_path, *args):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        run("evaluate", report_path, "--json", f.name, *args)
        return read_json(f.name)


def loop_lines(path):
    """The g2o lines of `path` split into (header/odometry lines, {(i, j): line})."""
    keep, loops = [], []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if fields and fields[0].startswith("EDGE") and abs(int(fields[1]) - int(fields[2])) > 1:
                loops.append(((int(fields[1]), int(fields[2])), line))
            else:
                keep.append(line)
    return keep, loops


def write_with_loops(src, dst, wanted):
    """Copies g2o `src` to `dst` keeping only the loops whose (i, j) is in `wanted`."""
    keep, loops = loop_lines(src)
    with open(dst, "w") as f:
        f.writelines(keep)
        f.writelines(line for key, line in loops if key in wanted)


def write_results(out, rows, columns, cells):
    """Writes `rows` (dicts) to OUT/results.json and as a Markdown table to
    OUT/table.md: `columns` its header, `cells(row)` a row's cells as text."""
    with open(out / "results.json", "w") as f:
        json.dump(rows, f, indent=1)
    with open(out / "table.md", "w") as f:
        f.write("| " + " | ".join(columns) + " |\n")
        f.write("|" + "---|" * len(columns) + "\n")
        for r in rows:
            f.write("| " + " | ".join(cells(r)) + " |\n")
    print(f"wrote {out / 'table.md'}")


def ros_env(port):
    """The environment of the package's devel space with a master on `port`."""
    return ros_processes.ros_env(ROOT / "_build", port)


service = ros_processes.service


def graph_size(path):
    """{"poses": vertices, "candidates": loop edges} of g2o file `path`."""
    keep, loops = loop_lines(path)
    poses = sum(1 for line in keep if line.startswith("VERTEX"))
    return {"poses": poses, "candidates": len(loops)}


def spoil_flags(kind, group):
    """rrr spoil flags of a kind of false loops (SPOIL_KINDS)."""
    return {"random": [], "local": ["--local"], "look-alike": ["--look-alike"],
            "grouped": ["--group", group]}[kind]


SPOIL_KINDS = ["random", "local", "look-alike", "grouped"]


def add_between_chains_arguments(parser, outliers, out_name):
    """The options of the scripts that spoil the loops between two chains
    (meet_once.py, never_meet.py): false loops per set, their kinds, the
    group size, seed, window, methods compared and the output folder
    (bench/out/OUT_NAME)."""
    parser.add_argument("--outliers", nargs="*", type=int, default=outliers)
    parser.add_argument("--kinds", nargs="*", default=["random", "look-alike", "grouped"], choices=SPOIL_KINDS)
    parser.add_argument("--group", type=int, default=10, help="group size of the grouped kind")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--methods", nargs="*", default=["rrr", "pcm", "dcs", "gnc"],
                        choices=["rrr", "dcs", "gnc", "pcm"])
    parser.add_argument("--out", default=str(ROOT / "bench" / "out" / out_name))


def spoiled_sets(args, out):
    """Makes every spoiled set of args.datasets × kinds × outliers × seeds
    (rrr spoil into OUT/NAME_KIND_N_SEED/) and yields a dict with its name,
    kind, outliers, seed, folder, spoiled file, list of false loops and the
    optimum of the dataset without false loops. Missing datasets are named
    and skipped."""
    for name in args.datasets:
        clean = dataset_path(name)
        if not clean.exists():
            print(f"{name}: {clean} not found, skipped", flush=True)
            continue
        optimum = out / f"{name}_optimum.g2o"
        if not optimum.exists():
            run("optimize", clean, "--output", optimum)
        for kind in args.kinds:
            for n in args.outliers:
                for seed in args.seeds:
                    folder = out / f"{name}_{kind}_{n}_{seed}"
                    folder.mkdir(exist_ok=True)
                    spoiled, false_list = folder / "spoiled.g2o", folder / "false.txt"
                    extra = spoil_flags(kind, args.group)
                    run("spoil", clean, "--outliers", n, "--seed", seed, *extra,
                        "--reference", optimum, "--output", spoiled, "--truth", false_list)
                    yield dict(name=name, kind=kind, outliers=n, seed=seed, folder=folder,
                               spoiled=spoiled, false_list=false_list, optimum=optimum)
