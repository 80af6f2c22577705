#!/usr/bin/python3
"""A stretch of city10000 spoiled with grouped false loops (BENCHMARKS.md,
"A stretch of city10000 with grouped false loops"): poses FIRST..LAST of
city10000 (or of another synthetic dataset of one chain, --dataset) with
the loops between them (a quarter of the city by default), then `rrr
spoil --group 10` for each seed and count.
On the whole city the first revisits of a street come with many loops
already in the map; on a stretch a self-consistent false group can be the
first loop joining two streets, so it probes what the map procedure does
when the false group comes before the evidence against it.

    bench/city_stretch.py [--dataset city10000] [--first 5000] [--last 7499] [--outliers 100 250]
        [--seeds 1 2 3 4 5 6] [--methods map dcs gnc pcm]
        [--out bench/out/city_stretch/DATASET_FIRST_LAST]
"""
import argparse
import pathlib
import sys

import common
from compare_methods import METHODS


def cut(src, dst, first, last):
    """Copies the poses first..last of g2o `src` and the edges between them."""
    with open(src) as f, open(dst, "w") as out:
        for line in f:
            fields = line.split()
            if not fields:
                continue
            if fields[0].startswith("VERTEX"):
                inside = first <= int(fields[1]) <= last
            elif fields[0].startswith("EDGE"):
                inside = all(first <= int(v) <= last for v in fields[1:3])
            else:
                inside = True
            if inside:
                out.write(line)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dataset", default="city10000",
                        help="a synthetic dataset (one chain) to cut instead of city10000")
    parser.add_argument("--first", type=int, default=5000)
    parser.add_argument("--last", type=int, default=7499)
    parser.add_argument("--outliers", nargs="*", type=int, default=[100, 250])
    parser.add_argument("--seeds", nargs="*", type=int, default=[1, 2, 3, 4, 5, 6])
    parser.add_argument("--methods", nargs="*", default=["map"], choices=["map", "dcs", "gnc", "pcm"])
    parser.add_argument("--out", help="default: bench/out/city_stretch/DATASET_FIRST_LAST")
    args = parser.parse_args()
    common.require_rrr()
    source = common.datasets_dir() / "synthetic" / f"{args.dataset}.g2o"
    if not source.is_file():
        sys.exit(f"{source} not found: --dataset names a file of {source.parent} without .g2o")
    out = pathlib.Path(args.out or common.ROOT / "bench" / "out" / "city_stretch" /
                       f"{args.dataset}_{args.first}_{args.last}")
    out.mkdir(parents=True, exist_ok=True)
    clean = out / "stretch.g2o"
    cut(source, clean, args.first, args.last)
    rows = []
    for outliers in args.outliers:
        for seed in args.seeds:
            set_dir = out / f"{outliers}_{seed}"
            set_dir.mkdir(exist_ok=True)
            spoiled, truth = set_dir / "spoiled.g2o", set_dir / "false.txt"
            common.run("spoil", clean, "--outliers", outliers, "--group", 10, "--seed", seed,
                       "--output", spoiled, "--truth", truth)
            for method in args.methods:
                run_dir = set_dir / method
                run_dir.mkdir(exist_ok=True)
                _, seconds, _ = common.verify(spoiled, 10, run_dir, extra=METHODS[method])
                scores = common.evaluate(run_dir / "report.json", "--false-loops", truth)
                rows.append(dict(outliers=outliers, seed=seed, method=method,
                                 candidates=scores["candidates"], accepted=scores["accepted"],
                                 precision=scores["precision"], recall=scores["recall"],
                                 seconds=seconds))
                print(f"{outliers:>5} false, seed {seed}, {method:>4}: accepted {scores['accepted']} of "
                      f"{scores['candidates']}, precision {scores['precision']:.4f}, "
                      f"recall {scores['recall']:.4f}, {seconds:.2f} s", flush=True)
    common.write_results(out, rows, ["false loops", "seed", "method", "candidates", "accepted",
                                     "precision", "recall", "s"],
                         lambda r: [str(r["outliers"]), str(r["seed"]), r["method"], str(r["candidates"]),
                                    str(r["accepted"]), f"{r['precision']:.4f}",
                                    f"{r['recall']:.4f}", f"{r['seconds']:.2f}"])


if __name__ == "__main__":
    main()
