"""Shared helpers of the benchmark scripts: where things are, running rrr."""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
RRR = ROOT / "_build" / "devel" / "lib" / "rrr_slam" / "rrr"


def datasets_dir():
    """RRR_DATASETS, else ../shared/datasets beside the repository; exits with
    a clear message when it is missing."""
    path = pathlib.Path(os.environ.get("RRR_DATASETS", ROOT.parent / "shared" / "datasets"))
    if not path.is_dir():
        sys.exit(f"datasets not found at {path}: set RRR_DATASETS to the datasets folder")
    return path


def require_rrr():
    if not RRR.exists():
        sys.exit(f"{RRR} not built: run scripts/setup.sh first")


def run(*args):
    """Runs rrr with `args`; returns stdout, exits on failure."""
    result = subprocess.run([str(RRR), *map(str, args)], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"rrr {' '.join(map(str, args))} failed:\n{result.stdout}{result.stderr}")
    return result.stdout


def read_json(path):
    with open(path) as f:
        return json.load(f)


def verify(graph, window, out_dir, repeat=1, extra=()):
    """Runs rrr verify `repeat` times; returns (report, median seconds, map path)."""
    out_dir = pathlib.Path(out_dir)
    out_map, report = out_dir / "verified.g2o", out_dir / "report.json"
    seconds = []
    for _ in range(repeat):
        run("verify", graph, "--window", window, "--output", out_map, "--report", report, *extra)
        seconds.append(read_json(report)["seconds"])
    return read_json(report), statistics.median(seconds), out_map


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
