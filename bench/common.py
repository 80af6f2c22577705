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
    return run_measured(*args)[0]


def run_measured(*args):
    """Runs rrr with `args`; returns (stdout, peak resident memory in MB of
    that process), exits on failure."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        process = subprocess.Popen([str(RRR), *map(str, args)], stdout=out, stderr=err)
        _, status, usage = os.wait4(process.pid, 0)
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


def verify_flags(args):
    """rrr verify flags for a script's --span-gate and --threads."""
    flags = ["--span-gate"] if args.span_gate else []
    if args.threads:
        flags += ["--threads", args.threads]
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
