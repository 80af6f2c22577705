#!/usr/bin/python3
"""Synthetic datasets spoiled with false loop closures (BENCHMARKS.md):
rrr spoil, then rrr verify, scored against the list of false loops, with the
ATE against the optimum of the dataset without false loops (0 is ideal).

    bench/spoiled_synthetic.py [--datasets manhattanOlson3500 city10000 ...]
        [--outliers 100 500 1000] [--seeds 1 2 ...] [--kinds random local grouped]
        [--group 10] [--span-gate] [--threads N] [--repeat 1] [--out bench/out/synthetic]
"""
import argparse
import pathlib

import common


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*",
                        default=["manhattanOlson3500", "intel", "sphere2500", "city10000"])
    parser.add_argument("--outliers", nargs="*", type=int, default=[100])
    parser.add_argument("--seeds", nargs="*", type=int, default=[1])
    parser.add_argument("--kinds", nargs="*", default=["random"], choices=["random", "local", "grouped"])
    parser.add_argument("--group", type=int, default=10, help="group size of the grouped kind")
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=1, help="runs of rrr verify; the median time is reported")
    parser.add_argument("--span-gate", action="store_true", help="pass --span-gate to rrr verify")
    parser.add_argument("--threads", type=int, help="pass --threads to rrr verify (default: rrr's, every core)")
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "synthetic"))
    args = parser.parse_args()
    common.require_rrr()
    data = common.datasets_dir() / "synthetic"
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    header = ("dataset", "kind", "N", "seed", "cand", "clusters", "acc", "prec", "recall", "ATE", "sec", "peak MB")
    print(" ".join(f"{h:>10}" for h in header), flush=True)
    rows = []
    for name in args.datasets:
        clean = data / f"{name}.g2o"
        if not clean.exists():
            print(f"{name}: {clean} not found, skipped")
            continue
        optimum = out / f"{name}_optimum.g2o"
        if not optimum.exists():
            common.run("optimize", clean, "--output", optimum)
        for kind in args.kinds:
            for n in args.outliers:
                for seed in args.seeds:
                    run_dir = out / f"{name}_{kind}_{n}_{seed}"
                    run_dir.mkdir(exist_ok=True)
                    spoiled, false_list = run_dir / "spoiled.g2o", run_dir / "false.txt"
                    extra = {"random": [], "local": ["--local"], "grouped": ["--group", args.group]}[kind]
                    common.run("spoil", clean, "--outliers", n, "--seed", seed, *extra,
                               "--output", spoiled, "--truth", false_list)
                    report, seconds, out_map = common.verify(
                        spoiled, args.window, run_dir, args.repeat, common.verify_flags(args))
                    scores = common.evaluate(run_dir / "report.json", "--map", out_map,
                                             "--false-loops", false_list, "--gt-g2o", optimum)
                    row = dict(dataset=name, kind=kind, outliers=n, seed=seed,
                               candidates=scores["candidates"], clusters=report["clusters"],
                               accepted=scores["accepted"], precision=scores["precision"],
                               recall=scores["recall"], ate=scores["ate_rmse"], seconds=seconds,
                               peak_rss_mb=report["peak_rss_mb"])
                    rows.append(row)
                    print(f"{name[:10]:>10} {kind:>10} {n:>10} {seed:>10} {row['candidates']:>10} "
                          f"{row['clusters']:>10} {row['accepted']:>10} {row['precision']:>10.4f} "
                          f"{row['recall']:>10.4f} {row['ate']:>10.3f} "
                          f"{seconds:>10.2f} {row['peak_rss_mb']:>10.1f}", flush=True)
    (out / "results.json").write_text(common.json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
