#!/usr/bin/python3
"""rrr optimize against an independent solver: every dataset of
RRR_DATASETS (../shared/datasets) minimized from its odometry, all edges
active, by rrr's Levenberg-Marquardt and by Ceres Solver's (the same cost:
bench/ceres_reference.cc). Prints and writes (OUT/table.md, OUT/results.json)
the final chi2 of each, its excess over Ceres's, iterations, whether each
converged, and the median time of each over --repeat runs with their ratio.
A file that rrr cannot read is listed with the reason.

    bench/solver_vs_ceres.py [--repeat 3] [--max-iterations 100] [--out bench/out/solver_vs_ceres]
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


def run_rrr(graph, max_iterations, tmp):
    """rrr optimize; returns its report, or None and the error if it refused the file."""
    report = tmp / "report.json"
    process = subprocess.run([str(common.RRR), "optimize", str(graph), "--output", str(tmp / "out.g2o"),
                              "--report", str(report), "--max-iterations", str(max_iterations)],
                             capture_output=True, text=True)
    if process.returncode not in (0, 3):  # 3: ran, did not converge
        return None, (process.stderr.strip().splitlines() or ["failed"])[-1]
    return common.read_json(report), None


def run_ceres(graph, max_iterations):
    out = subprocess.run([str(ceres_binary()), str(graph), "--max-iterations", str(max_iterations)],
                         capture_output=True, text=True, check=True).stdout
    return common.json.loads(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", help="FOLDER/NAME under the datasets folder (default: all)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each; the median time is reported")
    parser.add_argument("--max-iterations", type=int, default=100)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "solver_vs_ceres"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    data = common.datasets_dir()
    header = ("dataset", "rrr chi2", "it", "conv", "ceres chi2", "it", "conv", "excess %",
              "rrr s", "ceres s", "ratio")
    print(" ".join(f"{h:>12}" for h in header), flush=True)
    rows = []
    for name in args.datasets or default_datasets():
        graph = data / f"{name}.g2o"
        with tempfile.TemporaryDirectory() as tmp:
            tmp = pathlib.Path(tmp)
            ours, error = run_rrr(graph, args.max_iterations, tmp)
            if ours is None:
                rows.append(dict(dataset=name, error=error))
                print(f"{name[-12:]:>12} not read: {error}", flush=True)
                continue
            seconds = [ours["seconds"]]
            for _ in range(args.repeat - 1):
                seconds.append(run_rrr(graph, args.max_iterations, tmp)[0]["seconds"])
        runs = [run_ceres(graph, args.max_iterations) for _ in range(args.repeat)]
        theirs = runs[0]
        mine = ours["optimization"]
        row = dict(dataset=name, poses=ours["poses"], edges=ours["edges"],
                   initial_chi2=mine["initial_chi2"], chi2=mine["final_chi2"],
                   iterations=mine["iterations"], converged=mine["converged"],
                   ceres_chi2=theirs["final_chi2"], ceres_iterations=theirs["iterations"],
                   ceres_termination=theirs["termination"],
                   excess_percent=100.0 * (mine["final_chi2"] / theirs["final_chi2"] - 1.0),
                   seconds=statistics.median(seconds),
                   ceres_seconds=statistics.median(r["seconds"] for r in runs))
        row["time_ratio"] = row["seconds"] / row["ceres_seconds"]
        rows.append(row)
        print(f"{name[-12:]:>12} {row['chi2']:>12.6g} {row['iterations']:>12} {str(row['converged']):>12} "
              f"{row['ceres_chi2']:>12.6g} {row['ceres_iterations']:>12} {row['ceres_termination'][:12]:>12} "
              f"{row['excess_percent']:>12.4f} {row['seconds']:>12.3f} {row['ceres_seconds']:>12.3f} "
              f"{row['time_ratio']:>12.2f}", flush=True)
    (out / "results.json").write_text(common.json.dumps(rows, indent=1))
    write_table(rows, args.max_iterations, out / "table.md")


def write_table(rows, max_iterations, path):
    lines = [f"| dataset | poses | edges | χ² from odometry | rrr χ² | rrr iterations | rrr converged | "
             f"Ceres χ² | Ceres iterations | Ceres termination | rrr − Ceres | rrr s | Ceres s | rrr / Ceres time |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['dataset']} | not read: {r['error']} |" + " |" * 12)
            continue
        lines.append(f"| {r['dataset']} | {r['poses']} | {r['edges']} | {r['initial_chi2']:.6g} | "
                     f"{r['chi2']:.6g} | {r['iterations']} | {'yes' if r['converged'] else '**no**'} | "
                     f"{r['ceres_chi2']:.6g} | {r['ceres_iterations']} | {r['ceres_termination']} | "
                     f"{r['excess_percent']:+.4f} % | {r['seconds']:.3f} | {r['ceres_seconds']:.3f} | "
                     f"{r['time_ratio']:.2f} |")
    lines.append(f"\n(at most {max_iterations} iterations each)")
    path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
