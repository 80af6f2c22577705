#!/usr/bin/python3
"""Two robots that meet once ("Several odometry chains", in the git history of BENCHMARKS.md):
a dataset (synthetic/ or more/) cut into two chains (bench/chains.py's cut: the
odometry edge at the middle removed, the second chain's estimates moved),
of the loops between the chains only one revisit kept (the largest set of
them joined by steps of at most --window poses at both ends, as RRR
clusters them), then 100 false loops drawn between the chains (`rrr
spoil --between-chains`: random, look-alike, grouped). One true cluster
among 100 false ones: a method must join the chains by it, or leave them
apart and say so; never join them by a false loop. Each method of `rrr
verify` judges each set.

    bench/meet_once.py [--datasets manhattanOlson3500 city10000 sphere2500]
        [--outliers 100] [--kinds random look-alike grouped] [--methods rrr pcm dcs gnc]
        [--out bench/out/meet_once]
"""
import argparse
import pathlib

import common
from chains import cut


def one_revisit(loops, first, window):
    """Of the loops (a, b) between the chains (the second chain starting at
    pose `first`), the largest revisit: the loops joined by steps of at most
    `window` poses at both ends (as RRR clusters them)."""
    between = sorted((a, b) if a < first else (b, a) for a, b in loops if (a < first) != (b < first))
    revisits = []
    for a, b in between:
        near = [r for r in revisits if any(abs(a - x) <= window and abs(b - y) <= window for x, y in r)]
        merged = [(a, b)] + [p for r in near for p in r]
        revisits = [r for r in revisits if r not in near] + [merged]
    largest = max(revisits, key=len, default=[])
    return {tuple(sorted(p)) for p in largest}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", default=["manhattanOlson3500", "city10000", "sphere2500"])
    common.add_between_chains_arguments(parser, [100], "meet_once")
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    header = ("dataset", "kind", "false", "method", "true between", "accepted true", "accepted false",
              "outcome", "inside prec", "inside recall", "s")
    print(" ".join(f"{h:>14}" for h in header), flush=True)
    rows = []
    for name in args.datasets:
        clean = common.dataset_path(name)
        if not clean.exists():
            print(f"{name}: {clean} not found, skipped", flush=True)
            continue
        two = out / f"{name}_two.g2o"
        first = cut(clean, two, 2)[1]
        _, loops = common.loop_lines(two)
        keys = [key for key, _ in loops]
        pairs = {tuple(sorted(key)) for key in keys}
        revisit = one_revisit(pairs, first, args.window)
        inside = {p for p in pairs if (p[0] < first) == (p[1] < first)}
        once = out / f"{name}_once.g2o"
        common.write_with_loops(two, once, {key for key in keys if tuple(sorted(key)) in inside | revisit})
        for kind in args.kinds:
            for n in args.outliers:
                folder = out / f"{name}_{kind}_{n}"
                folder.mkdir(exist_ok=True)
                spoiled = folder / "spoiled.g2o"
                common.run("spoil", once, "--outliers", n, "--seed", args.seed, "--between-chains",
                           *common.spoil_flags(kind, args.group), "--reference", once,
                           "--output", spoiled, "--truth", folder / "false.txt")
                for method in args.methods:
                    sub = folder / method
                    sub.mkdir(exist_ok=True)
                    report, seconds, _ = common.verify(spoiled, args.window, sub, extra=("--method", method))
                    accepted = {tuple(sorted(p)) for p in report["accepted"]}
                    between = {p for p in accepted if (p[0] < first) != (p[1] < first)}
                    true_between = between & revisit
                    false_between = between - revisit
                    if false_between:
                        outcome = "joined wrongly"
                    elif true_between:
                        outcome = "joined"
                    else:
                        apart = [q for q in report.get("chain_pairs", []) if not q.get("joined")]
                        outcome = "apart, said" if apart else "apart"
                    kept_inside = accepted & inside
                    row = dict(dataset=name, kind=kind, outliers=n, method=method, revisit=len(revisit),
                               true_between=len(true_between), false_between=len(false_between),
                               outcome=outcome,
                               inside_precision=len(kept_inside) / max(1, len(accepted - between)),
                               inside_recall=len(kept_inside) / max(1, len(inside)), seconds=seconds)
                    rows.append(row)
                    print(f"{name[:14]:>14} {kind:>14} {n:>14} {method:>14} {len(revisit):>14} "
                          f"{len(true_between):>14} {len(false_between):>14} {outcome:>14} "
                          f"{row['inside_precision']:>14.4f} {row['inside_recall']:>14.4f} {seconds:>14.2f}",
                          flush=True)
    common.write_results(
        out, rows, ["dataset", "false loops between", "method", "true loops between (one revisit)",
                    "accepted true", "accepted false", "outcome", "inside precision", "inside recall", "s"],
        lambda r: [r["dataset"], f"{r['outliers']} {r['kind']}", r["method"], str(r["revisit"]),
                   str(r["true_between"]), str(r["false_between"]), r["outcome"],
                   f"{r['inside_precision']:.4f}", f"{r['inside_recall']:.4f}", f"{r['seconds']:.2f}"])

if __name__ == "__main__":
    main()
