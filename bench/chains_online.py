#!/usr/bin/python3
"""The map procedure over several chains over time, as a fleet's node runs it
("Several chains over time", in the git history of BENCHMARKS.md): each dataset (synthetic/ or more/) cut into
N chains (as bench/chains.py cuts it), with false loops between the chains
(rrr spoil --between-chains), fed by bench/chains_online.cc robot by robot
side by side with an update after every pose. Prints the update times
(median, p99, largest), Finish(), the whole run, whether the decisions equal
those of the batch (what rrr verify runs) on the same graph in the same
order, and its time.

    bench/chains_online.py [--datasets manhattanOlson3500 city10000]
        [--chains 2 4] [--outliers 100] [--kinds random]
        [--out bench/out/chains_online]
"""
import argparse
import json
import pathlib
import subprocess
import sys

import chains
import common

ONLINE = common.RRR.parent / "chains_online"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", default=["manhattanOlson3500", "city10000"])
    parser.add_argument("--chains", nargs="*", type=int, default=[2, 4])
    parser.add_argument("--outliers", nargs="*", type=int, default=[100])
    parser.add_argument("--kinds", nargs="*", default=["random"], choices=common.SPOIL_KINDS)
    parser.add_argument("--group", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "chains_online"))
    args = parser.parse_args()
    common.require_rrr()
    if not ONLINE.exists():
        sys.exit(f"{ONLINE} not built: cmake --build _build --target chains_online")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print("| set | chains | candidates | accepted | maps | update median ms | p99 ms | max ms "
          "| Finish s | run s | = batch | batch s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.datasets:
        clean = common.dataset_path(name)
        if not clean.exists():
            print(f"{name}: {clean} not found, skipped", flush=True)
            continue
        for n_chains in args.chains:
            cut = out / f"{name}_{n_chains}.g2o"
            chains.cut(clean, cut, n_chains)
            for kind in args.kinds:
                for n in args.outliers:
                    spoiled = out / f"{name}_{n_chains}_{kind}_{n}.g2o"
                    common.run("spoil", cut, "--outliers", n, "--seed", args.seed,
                               "--between-chains", *common.spoil_flags(kind, args.group),
                               "--output", spoiled, "--truth", out / f"{spoiled.stem}_false.txt")
                    result = json.loads(subprocess.run(
                        [str(ONLINE), str(spoiled), "--window", str(args.window)],
                        check=True, capture_output=True, text=True).stdout)
                    print(f"| {name} + {n} {kind} between | {result['chains']} | {result['candidates']} "
                          f"| {result['accepted']} | {result['maps']} | {result['update_median_ms']:.2f} "
                          f"| {result['update_p99_ms']:.1f} | {result['update_max_ms']:.0f} "
                          f"| {result['finish_s']:.2f} | {result['online_s']:.1f} "
                          f"| {'yes' if result['equal_to_batch'] else 'NO'} | {result['batch_s']:.2f} |",
                          flush=True)


if __name__ == "__main__":
    main()
