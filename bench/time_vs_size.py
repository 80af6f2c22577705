#!/usr/bin/python3
"""Time against graph size (BENCHMARKS.md, "Speed, one chain"): built-in grid
worlds (rrr simulate) of 1,000 to 100,000 poses, each with false loops in
groups of 4 (one per 20 poses), judged by each method of rrr verify; the
wall time of the whole verification (rrr verify's `seconds`) against the
number of edges, on log-log axes. A method that takes longer than
--timeout on a size is not run on larger ones. Needs no dataset.

    bench/time_vs_size.py [--poses 1000 3000 10000 30000 100000]
        [--methods map published dcs gnc pcm] [--timeout 600] [--out bench/out/time_vs_size]
"""
import argparse
import pathlib
import subprocess

import common

FLAGS = {"map": [], "published": ["--procedure", "published"], "dcs": ["--method", "dcs"],
         "gnc": ["--method", "gnc"], "pcm": ["--method", "pcm"]}


def plot(rows, methods, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for method in methods:
        points = sorted((r["edges"], r["seconds"]) for r in rows if r["method"] == method)
        if points:
            ax.loglog(*zip(*points), "o-", label=method)
    ax.set_xlabel("edges (odometry and loop candidates)")
    ax.set_ylabel("verification time (s)")
    ax.set_title("rrr verify on grid worlds with 5 % false loops")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", nargs="*", type=int, default=[1000, 3000, 10000, 30000, 100000])
    parser.add_argument("--methods", nargs="*", default=list(FLAGS), choices=list(FLAGS))
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "time_vs_size"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows, too_slow = [], set()
    print("method | poses | edges | accepted | s", flush=True)
    for poses in args.poses:
        world = out / f"world_{poses}.g2o"
        common.run("simulate", "--poses", poses, "--false-loops", poses // 20, "--group", 4, "--seed", 1,
                   "--output", world, "--truth", out / f"false_{poses}.txt",
                   "--ground-truth", out / f"truth_{poses}.g2o")
        edges = sum(1 for line in open(world) if line.startswith("EDGE"))
        for method in args.methods:
            if method in too_slow:
                continue
            folder = out / f"{method}_{poses}"
            folder.mkdir(exist_ok=True)
            try:
                _, peak = common.run_measured("verify", world, "--report", folder / "report.json",
                                              *FLAGS[method], timeout=args.timeout)
            except subprocess.TimeoutExpired:
                print(f"{method} | {poses} | {edges} | - | > {args.timeout:.0f}", flush=True)
                too_slow.add(method)
                continue
            report = common.read_json(folder / "report.json")
            rows.append(dict(method=method, poses=poses, edges=edges, accepted=len(report["accepted"]),
                             seconds=report["seconds"], peak_rss_mb=peak))
            print(f"{method} | {poses} | {edges} | {len(report['accepted'])} | {report['seconds']:.2f}",
                  flush=True)
    common.write_results(out, rows, ("method", "poses", "edges", "accepted", "s", "peak MB"),
                         lambda r: [r["method"], str(r["poses"]), str(r["edges"]), str(r["accepted"]),
                                    f"{r['seconds']:.2f}", f"{r['peak_rss_mb']:.0f}"])
    plot(rows, args.methods, out / "time_vs_size.png")


if __name__ == "__main__":
    main()
