#!/usr/bin/python3
"""Two robots that never meet ("Several odometry chains", in the git history of BENCHMARKS.md):
two different 2D datasets made one graph of two odometry chains (the
second's ids after the first's, its estimates moved 10 km away), then
`rrr spoil --between-chains` draws false loops between them (random,
look-alike or grouped). Nothing is true between the chains, so they must
never be joined and no loop between them accepted, and the loops inside
each chain should be decided as that dataset alone decides them. Each
method of `rrr verify` judges each set; the time is against the two
datasets verified alone (summed).

    bench/never_meet.py [--pairs intel:manhattanOlson3500 manhattanOlson3500:city10000]
        [--outliers 100 1000] [--kinds random look-alike grouped] [--methods rrr pcm dcs gnc]
        [--out bench/out/never_meet]
"""
import argparse
import pathlib

import common


def merged(first, second, dst):
    """Writes `first` and `second` (2D g2o files) as one graph of two chains
    to `dst`; returns the offset added to the second's ids."""
    a = open(first).read().splitlines()
    b = open(second).read().splitlines()
    offset = 1 + max(int(line.split()[1]) for line in a if line.startswith("VERTEX"))
    with open(dst, "w") as out:
        out.writelines(line + "\n" for line in a)
        for line in b:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "VERTEX_SE2":
                fields[1] = str(int(fields[1]) + offset)
                fields[2] = repr(float(fields[2]) + 10000.0)
            elif fields[0].startswith("EDGE"):
                fields[1] = str(int(fields[1]) + offset)
                fields[2] = str(int(fields[2]) + offset)
            elif fields[0] == "FIX":
                continue
            out.write(" ".join(fields) + "\n")
    return offset


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pairs", nargs="*", default=["intel:manhattanOlson3500", "manhattanOlson3500:city10000"])
    common.add_between_chains_arguments(parser, [100, 1000], "never_meet")
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    data = common.datasets_dir() / "synthetic"

    header = ("first", "second", "kind", "false", "method", "joined", "between acc", "inside same", "s", "× alone")
    print(" ".join(f"{h:>12}" for h in header), flush=True)
    rows = []
    alone = {}  # (dataset, method) -> (accepted pairs, seconds)
    for pair in args.pairs:
        names = pair.split(":")
        for name in names:
            for method in args.methods:
                if (name, method) in alone:
                    continue
                folder = out / f"{name}_alone_{method}"
                folder.mkdir(exist_ok=True)
                report, seconds, _ = common.verify(data / f"{name}.g2o", args.window, folder,
                                                   extra=("--method", method))
                alone[(name, method)] = ({tuple(p) for p in report["accepted"]}, seconds)
        two = out / f"{names[0]}_{names[1]}.g2o"
        offset = merged(data / f"{names[0]}.g2o", data / f"{names[1]}.g2o", two)
        for kind in args.kinds:
            for n in args.outliers:
                folder = out / f"{names[0]}_{names[1]}_{kind}_{n}"
                folder.mkdir(exist_ok=True)
                spoiled = folder / "spoiled.g2o"
                # The merged file is its own reference: a draw is discarded if the
                # two maps, 10 km apart, already agree with it (none does).
                common.run("spoil", two, "--outliers", n, "--seed", args.seed, "--between-chains",
                           *common.spoil_flags(kind, args.group), "--reference", two,
                           "--output", spoiled, "--truth", folder / "false.txt")
                for method in args.methods:
                    sub = folder / method
                    sub.mkdir(exist_ok=True)
                    report, seconds, _ = common.verify(spoiled, args.window, sub, extra=("--method", method))
                    accepted = {tuple(p) for p in report["accepted"]}
                    between = {p for p in accepted if (p[0] >= offset) != (p[1] >= offset)}
                    first = {p for p in accepted if p[0] < offset and p[1] < offset}
                    second = {(p[0] - offset, p[1] - offset) for p in accepted if p[0] >= offset and p[1] >= offset}
                    same = first == alone[(names[0], method)][0] and second == alone[(names[1], method)][0]
                    single = alone[(names[0], method)][1] + alone[(names[1], method)][1]
                    row = dict(first=names[0], second=names[1], kind=kind, outliers=n, method=method,
                               joined=bool(between), between_accepted=len(between), inside_same=same,
                               inside_accepted=len(first) + len(second), seconds=seconds, ratio=seconds / single)
                    rows.append(row)
                    print(f"{names[0][:12]:>12} {names[1][:12]:>12} {kind:>12} {n:>12} {method:>12} "
                          f"{str(row['joined']):>12} {len(between):>12} {str(same):>12} {seconds:>12.2f} "
                          f"{row['ratio']:>12.2f}", flush=True)
    common.write_results(
        out, rows, ["chains", "false loops between", "method", "joined", "loops between accepted",
                    "loops inside as each alone", "s", "× the two alone"],
        lambda r: [f"{r['first']} + {r['second']}", f"{r['outliers']} {r['kind']}", r["method"],
                   "yes" if r["joined"] else "no", str(r["between_accepted"]),
                   "yes" if r["inside_same"] else "no", f"{r['seconds']:.2f}", f"{r['ratio']:.2f}"])

if __name__ == "__main__":
    main()
