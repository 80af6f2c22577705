#!/usr/bin/python3
"""Simulated fleets ("Several odometry chains", in the git history of BENCHMARKS.md): `rrr simulate
--robots N` lets N robots drive one path in turn, each its own odometry chain
(keys as GTSAM symbols), with true loops within and between robots and the
simulator's own false loops; `rrr spoil --between-chains` adds false loops
between robots (random, look-alike or grouped). Each set is verified with
the default procedure and scored against both lists of false loops: false
loops accepted, true loops kept, the maps made and the pairs of robots
joined with no true loop among their accepted ones (wrongly joined). Needs no
dataset.

    bench/fleets.py [--robots 3 4] [--layouts grid ring] [--poses 3000]
        [--outliers 100 500] [--kinds random grouped look-alike] [--seeds 31 32]
        [--out bench/out/fleets]
"""
import argparse
import pathlib

import common


def false_pairs(*paths):
    """The (i, j) pairs, both ways, of the false-loop lists `paths`."""
    pairs = set()
    for path in paths:
        for line in open(path):
            fields = line.split()
            if len(fields) >= 2 and not line.startswith("#"):
                i, j = int(fields[0]), int(fields[1])
                pairs.update({(i, j), (j, i)})
    return pairs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", nargs="*", type=int, default=[3, 4])
    parser.add_argument("--layouts", nargs="*", default=["grid", "ring"], choices=["grid", "ring"])
    parser.add_argument("--poses", type=int, default=3000)
    parser.add_argument("--outliers", nargs="*", type=int, default=[100, 500])
    parser.add_argument("--kinds", nargs="*", default=["random", "grouped", "look-alike"],
                        choices=common.SPOIL_KINDS)
    parser.add_argument("--group", type=int, default=10, help="group size of the grouped kind")
    parser.add_argument("--seeds", nargs="*", type=int, default=[31, 32])
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "fleets"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    header = ("robots", "layout", "kind", "false", "seed", "accepted", "false acc", "true kept", "maps",
              "wrong joins", "s")
    print(" ".join(f"{h:>10}" for h in header), flush=True)
    rows = []
    for robots in args.robots:
        for layout in args.layouts:
            for seed in args.seeds:
                world = out / f"{robots}_{layout}_{seed}"
                world.mkdir(exist_ok=True)
                common.run("simulate", "--robots", robots, "--layout", layout, "--poses", args.poses,
                           "--seed", seed, "--output", world / "world.g2o", "--truth", world / "false.txt",
                           "--ground-truth", world / "truth.g2o")
                for kind in args.kinds:
                    for n in args.outliers:
                        folder = world / f"{kind}_{n}"
                        folder.mkdir(exist_ok=True)
                        spoiled = folder / "spoiled.g2o"
                        common.run("spoil", world / "world.g2o", "--outliers", n, "--seed", seed,
                                   "--between-chains", *common.spoil_flags(kind, args.group),
                                   "--output", spoiled, "--truth", folder / "false.txt")
                        report, seconds, _ = common.verify(spoiled, args.window, folder)
                        false = false_pairs(world / "false.txt", folder / "false.txt")
                        accepted = [tuple(p) for p in report["accepted"]]
                        false_accepted = sum(1 for p in accepted if p in false)
                        true_rejected = sum(1 for p in report["rejected"] if tuple(p) not in false)
                        true_total = len(accepted) - false_accepted + true_rejected
                        wrong = sum(1 for p in report["chain_pairs"]
                                    if p["joined"] and all(tuple(a) in false for a in p["accepted"]))
                        row = dict(robots=robots, layout=layout, kind=kind, outliers=n, seed=seed,
                                   accepted=len(accepted), false_accepted=false_accepted,
                                   true_kept=len(accepted) - false_accepted, true_total=true_total,
                                   maps=len(report["maps"]), wrongly_joined=wrong, seconds=seconds)
                        rows.append(row)
                        print(f"{robots:>10} {layout:>10} {kind:>10} {n:>10} {seed:>10} {len(accepted):>10} "
                              f"{false_accepted:>10} {row['true_kept']:>5}/{true_total:<4} {row['maps']:>10} "
                              f"{wrong:>10} {seconds:>10.2f}", flush=True)
    common.write_results(
        out, rows, ["robots", "layout", "false loops between", "seed", "accepted", "false accepted",
                    "true kept", "maps", "wrongly joined", "s"],
        lambda r: [str(r["robots"]), r["layout"], f"{r['outliers']} {r['kind']}", str(r["seed"]),
                   str(r["accepted"]), str(r["false_accepted"]), f"{r['true_kept']} / {r['true_total']}",
                   str(r["maps"]), str(r["wrongly_joined"]), f"{r['seconds']:.2f}"])


if __name__ == "__main__":
    main()
