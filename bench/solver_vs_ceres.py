#!/usr/bin/python3
"""rrr optimize against an independent solver, from each start: every
dataset of RRR_DATASETS (../shared/datasets) minimized with all edges
active by rrr's Levenberg-Marquardt from the odometry, from the chordal
start and with its default (`--init`), and by Ceres Solver's (the same
cost: bench/ceres_reference.cc) from the odometry and from the chordal
start. Prints and writes (OUT/table.md, OUT/results.json) the final chi2 of
each, the default's excess over the lower of Ceres's two, iterations and why
each stopped, and the median time of each over --repeat runs. A file that
rrr cannot read is listed with the reason.

    bench/solver_vs_ceres.py [--repeat 3] [--max-iterations 10000] [--out bench/out/solver_vs_ceres]
        [--datasets synthetic/city10000 more/CSAIL ...]
"""
import argparse
import pathlib
import statistics
import subprocess
import sys
import tempfile

import common

CERES = common.ROOT / "_build" / "devel" / "lib" / "rrr_slam" / "ceres_reference"


def default_datasets():
    data = common.datasets_dir()
    names = [f"{folder}/{path.stem}" for folder in ("synthetic", "more")
             for path in sorted((data / folder).glob("*.g2o"))]
    # Bicocca 25b: the graph with the most and with the fewest candidates.
    names += ["bicocca25b/B25b_0.000", "bicocca25b/B25b_1.000"]
    return names


def ceres_binary():
    if not CERES.exists():
        subprocess.run(["cmake", "--build", str(common.ROOT / "_build"), "--target", "ceres_reference"],
                       check=True, stdout=subprocess.DEVNULL)
    return CERES


def run_rrr(graph, max_iterations, init, tmp):
    """rrr optimize; returns its report, or None and the error if it refused the file."""
    report = tmp / "report.json"
    command = [str(common.RRR), "optimize", str(graph), "--output", str(tmp / "out.g2o"),
               "--report", str(report), "--max-iterations", str(max_iterations)]
    if init:
        command += ["--init", init]
    process = subprocess.run(command, capture_output=True, text=True)
    if process.returncode not in (0, 3):  # 3: ran, did not converge
        return None, (process.stderr.strip().splitlines() or ["failed"])[-1]
    return common.read_json(report), None


def run_ceres(graph, max_iterations, init):
    out = subprocess.run([str(ceres_binary()), str(graph), "--max-iterations", str(max_iterations),
                          "--init", init], capture_output=True, text=True, check=True).stdout
    return common.json.loads(out)


STARTS = ("odometry", "chordal")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", help="FOLDER/NAME under the datasets folder (default: all)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each; the median time is reported")
    parser.add_argument("--max-iterations", type=int, default=10000)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "solver_vs_ceres"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    data = common.datasets_dir()
    print(f"{'dataset':>24} {'run':>16} {'chi2':>14} {'it':>6} {'stopped by':>18} {'s':>8}", flush=True)
    rows = []
    for name in args.datasets or default_datasets():
        graph = data / f"{name}.g2o"
        row = dict(dataset=name, runs={})
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            for init in (None,) + STARTS:
                label = f"rrr {init or 'default'}"
                reports = []
                for _ in range(args.repeat):
                    report, error = run_rrr(graph, args.max_iterations, init, tmp)
                    if report is None:
                        break
                    reports.append(report)
                if not reports:
                    row["error"] = error
                    print(f"{name[-24:]:>24} not read: {error}", flush=True)
                    break
                o = reports[0]["optimization"]
                row.update(poses=reports[0]["poses"], edges=reports[0]["edges"])
                row["runs"][label] = dict(chi2=o["final_chi2"], initial_chi2=o["initial_chi2"],
                                          iterations=o["iterations"], stopped_by=o["stopped_by"],
                                          converged=o["converged"], start=reports[0]["start"],
                                          seconds=statistics.median(r["seconds"] for r in reports))
        if "error" in row:
            rows.append(row)
            continue
        for init in STARTS:
            runs = [run_ceres(graph, args.max_iterations, init) for _ in range(args.repeat)]
            row["runs"][f"ceres {init}"] = dict(
                chi2=runs[0]["final_chi2"], initial_chi2=runs[0]["initial_chi2"],
                iterations=runs[0]["iterations"], stopped_by=runs[0]["termination"],
                converged=runs[0]["converged"], seconds=statistics.median(r["seconds"] for r in runs))
        best_ceres = min(row["runs"][f"ceres {s}"]["chi2"] for s in STARTS)
        row["excess_percent"] = 100.0 * (row["runs"]["rrr default"]["chi2"] / best_ceres - 1.0)
        rows.append(row)
        for label, r in row["runs"].items():
            print(f"{name[-24:]:>24} {label:>16} {r['chi2']:>14.8g} {r['iterations']:>6} "
                  f"{str(r['stopped_by'])[:18]:>18} {r['seconds']:>8.3f}", flush=True)
        print(f"{name[-24:]:>24} default over the better Ceres: {row['excess_percent']:+.4f} %", flush=True)
    (out / "results.json").write_text(common.json.dumps(rows, indent=1))
    write_table(rows, args.max_iterations, out / "table.md")


def write_table(rows, max_iterations, path):
    labels = [f"rrr {s}" for s in ("default",) + STARTS] + [f"ceres {s}" for s in STARTS]
    lines = ["| dataset | poses | " + " | ".join(f"{l} χ² (iterations, s)" for l in labels) +
             " | default − better Ceres |", "|---|---|" + "---|" * (len(labels) + 1)]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['dataset']} | not read: {r['error']} |" + " |" * len(labels))
            continue
        cells = []
        for l in labels:
            run = r["runs"][l]
            mark = "" if run["converged"] else " **not converged**"
            cells.append(f"{run['chi2']:.7g} ({run['iterations']}, {run['seconds']:.3f}){mark}")
        lines.append(f"| {r['dataset']} | {r['poses']} | " + " | ".join(cells) +
                     f" | {r['excess_percent']:+.4f} % |")
    lines.append(f"\n(at most {max_iterations} iterations each; rrr default: `rrr optimize` without `--init`)")
    path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
