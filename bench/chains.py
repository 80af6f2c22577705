#!/usr/bin/python3
"""One graph as several odometry chains ("Several odometry chains", in the
git history of BENCHMARKS.md): each dataset (synthetic/ or more/) spoiled with false loops (rrr
spoil, as bench/spoiled_synthetic.py), then cut into N chains of equal
length: the odometry edge into each cut's first pose removed and every later
chain's vertex estimates moved by a rigid transform (a session whose
odometry restarted elsewhere; a graph of edges only has no estimates, and
each chain starts from its own origin). Every loop is kept; those across a cut become loops
between chains, false ones among them. rrr verify judges each set; scored
against the list of false loops, with the ATE against the optimum of the
dataset without false loops (one rigid alignment for the whole map: chains
left apart show as a large ATE), whether every pair of chains with true loops
between them was joined (an accepted loop between them) and whether a pair
without any was, and the time against the uncut set's.

With --between, the false loops are drawn between chains only (the dataset
cut first, then rrr spoil --between-chains). --methods judges every set with
each method of rrr verify (rrr: the map procedure; dcs, gnc, pcm), side by
side, each timed against its own run on the uncut set.

    bench/chains.py [--datasets city10000 manhattanOlson3500 sphere2500]
        [--chains 1 2 4] [--outliers 100 1000] [--kinds random grouped] [--seeds 1]
        [--between] [--methods rrr dcs gnc pcm] [--out bench/out/chains]
"""
import argparse
import json
import math
import pathlib

import common


def quaternion_product(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def rotate(q, v):
    w, x, y, z = quaternion_product(quaternion_product(q, (0.0, *v)), (q[0], -q[1], -q[2], -q[3]))
    return (x, y, z)


def moved_vertex(fields, k):
    """The VERTEX line `fields` moved by the k-th chain's rigid transform."""
    angle, shift = 0.7 * k, (30.0 * k, -20.0 * k, 5.0 * k)
    if fields[0] == "VERTEX_SE2":
        x, y, theta = map(float, fields[2:5])
        c, s = math.cos(angle), math.sin(angle)
        moved = (c * x - s * y + shift[0], s * x + c * y + shift[1], theta + angle)
        return " ".join([fields[0], fields[1], *(f"{v:.9g}" for v in moved)]) + "\n"
    x, y, z, qx, qy, qz, qw = map(float, fields[2:9])
    r = (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))
    t = rotate(r, (x, y, z))
    q = quaternion_product(r, (qw, qx, qy, qz))
    values = (t[0] + shift[0], t[1] + shift[1], t[2] + shift[2], q[1], q[2], q[3], q[0])
    return " ".join([fields[0], fields[1], *(f"{v:.9g}" for v in values)]) + "\n"


def cut(src, dst, chains, firsts=None):
    """Writes `src` cut into `chains` chains of equal length (or chains that
    start at the ids `firsts`, the first the graph's) to `dst`; returns the
    ids of each chain's first pose."""
    lines = open(src).read().splitlines(keepends=True)
    ids = sorted(int(l.split()[1]) for l in lines if l.startswith("VERTEX"))
    if not ids:  # edges only: the poses are the edges' ends
        ids = sorted({int(f) for l in lines if l.startswith("EDGE") for f in l.split()[1:3]})
    if firsts is None:
        firsts = [ids[len(ids) * k // chains] for k in range(chains)]

    def chain_of(i):
        return sum(1 for f in firsts if i >= f) - 1

    with open(dst, "w") as out:
        for line in lines:
            fields = line.split()
            if fields and fields[0].startswith("VERTEX"):
                k = chain_of(int(fields[1]))
                out.write(moved_vertex(fields, k) if k else line)
            elif fields and fields[0].startswith("EDGE"):
                i, j = sorted((int(fields[1]), int(fields[2])))
                if not (j == i + 1 and j in firsts[1:]):
                    out.write(line)
            else:
                out.write(line)
    return firsts


def chain_pairs(loops, firsts, skip=frozenset()):
    """The pairs of chains that the loops `loops` (but those in `skip`) join."""
    def chain_of(i):
        return sum(1 for f in firsts if i >= f) - 1
    pairs = set()
    for a, b in loops:
        if chain_of(a) != chain_of(b) and tuple(sorted((a, b))) not in skip:
            pairs.add(tuple(sorted((chain_of(a), chain_of(b)))))
    return pairs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", default=["city10000", "manhattanOlson3500", "sphere2500"])
    parser.add_argument("--chains", nargs="*", type=int, default=[1, 2, 4])
    parser.add_argument("--outliers", nargs="*", type=int, default=[100, 1000])
    parser.add_argument("--kinds", nargs="*", default=["random", "grouped"], choices=common.SPOIL_KINDS)
    parser.add_argument("--group", type=int, default=10, help="group size of the grouped kind")
    parser.add_argument("--seeds", nargs="*", type=int, default=[1])
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--between", action="store_true",
                        help="false loops only between chains: the dataset cut first, then rrr spoil "
                             "--between-chains (the row of 1 chain: the uncut dataset with the same false loops)")
    parser.add_argument("--methods", nargs="*", default=["rrr"], choices=["rrr", "dcs", "gnc", "pcm"])
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "chains"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    header = ("dataset", "kind", "false", "chains", "method", "acc", "prec", "recall", "ATE", "joined", "sec", "× 1 chain")
    print(" ".join(f"{h:>10}" for h in header), flush=True)
    rows = []

    def judge(name, kind, outliers, seed, chains, folder, graph, firsts, false_list, optimum, single_seconds):
        """Judges `graph` with each method in its own folder; returns the
        seconds of each method."""
        seconds = {}
        for method in args.methods:
            sub = folder / method
            sub.mkdir(exist_ok=True)
            seconds[method] = judge_with(method, name, kind, outliers, seed, chains, sub, graph, firsts,
                                         false_list, optimum, (single_seconds or {}).get(method))
        return seconds

    def judge_with(method, name, kind, outliers, seed, chains, folder, graph, firsts, false_list, optimum,
                   single_seconds):
        false_pairs = set()
        for line in open(false_list):
            if line.strip() and not line.startswith("#"):
                a, b = map(int, line.split()[:2])
                false_pairs.add(tuple(sorted((a, b))))
        report, seconds, out_map = common.verify(graph, args.window, folder, extra=("--method", method))
        scores = common.evaluate(folder / "report.json", "--map", out_map, "--false-loops",
                                 false_list, "--gt-g2o", optimum)
        # Joined: an accepted loop between the two chains (every method's
        # map then holds them in one frame).
        wanted = chain_pairs(report["accepted"] + report["rejected"], firsts, false_pairs)
        joined = chain_pairs(report["accepted"], firsts)
        wrong = joined - wanted
        row = dict(dataset=name, kind=kind, outliers=outliers, seed=seed, chains=chains, method=method,
                   accepted=len(report["accepted"]), precision=scores["precision"], recall=scores["recall"],
                   ate=scores["ate_rmse"], pairs_to_join=len(wanted), joined=len(joined & wanted),
                   wrongly_joined=len(wrong), seconds=seconds,
                   ratio=seconds / single_seconds if single_seconds else 1.0)
        rows.append(row)
        print(f"{name[:10]:>10} {kind:>10} {outliers:>10} {chains:>10} {method:>10} "
              f"{row['accepted']:>10} {row['precision']:>10.4f} {row['recall']:>10.4f} {row['ate']:>10.3f} "
              f"{row['joined']:>4}/{row['pairs_to_join']:<2}{'!' * len(wrong):>4} {seconds:>10.2f} "
              f"{row['ratio']:>10.2f}", flush=True)
        return seconds

    if not args.between:
        for spoiled_set in common.spoiled_sets(args, out):
            single_seconds = None
            for chains in sorted(args.chains):
                folder = spoiled_set["folder"] / f"chains_{chains}"
                folder.mkdir(exist_ok=True)
                graph = folder / "cut.g2o"
                firsts = cut(spoiled_set["spoiled"], graph, chains)
                seconds = judge(spoiled_set["name"], spoiled_set["kind"], spoiled_set["outliers"],
                                spoiled_set["seed"], chains, folder, graph, firsts, spoiled_set["false_list"],
                                spoiled_set["optimum"], single_seconds)
                if chains == 1:
                    single_seconds = seconds
    else:
        for name in args.datasets:
            clean = common.dataset_path(name)
            if not clean.exists():
                print(f"{name}: {clean} not found, skipped", flush=True)
                continue
            optimum = out / f"{name}_optimum.g2o"
            if not optimum.exists():
                common.run("optimize", clean, "--output", optimum)
            for chains in sorted(c for c in args.chains if c >= 2):
                for kind in args.kinds:
                    for n in args.outliers:
                        for seed in args.seeds:
                            folder = out / f"{name}_between_{kind}_{n}_{seed}_chains_{chains}"
                            folder.mkdir(exist_ok=True)
                            cut_clean = folder / "cut_clean.g2o"
                            firsts = cut(clean, cut_clean, chains)
                            graph, false_list = folder / "cut.g2o", folder / "false.txt"
                            extra = common.spoil_flags(kind, args.group)
                            common.run("spoil", cut_clean, "--outliers", n, "--seed", seed, "--between-chains",
                                       *extra, "--reference", optimum, "--output", graph, "--truth", false_list)
                            # The same false loops on the uncut graph: the time of one chain.
                            _, false_lines = common.loop_lines(graph)
                            uncut = folder / "uncut.g2o"
                            with open(uncut, "w") as f:
                                f.writelines(open(clean).readlines())
                                f.writelines(line for (i, j), line in false_lines
                                             if tuple(sorted((i, j))) in {
                                                 tuple(sorted(map(int, l.split()[:2])))
                                                 for l in open(false_list) if l.strip() and not l.startswith("#")})
                            single = folder / "single"
                            single.mkdir(exist_ok=True)
                            single_seconds = judge(name, f"{kind} between", n, seed, 1, single, uncut, [0],
                                                   false_list, optimum, None)
                            judge(name, f"{kind} between", n, seed, chains, folder, graph, firsts, false_list,
                                  optimum, single_seconds)
    with open(out / "results.json", "w") as f:
        json.dump(rows, f, indent=1)
    with open(out / "table.md", "w") as f:
        f.write("| dataset | kind | false loops | chains | method | accepted | precision | recall | ATE m | pairs joined / with true loops | wrongly joined | s | × 1 chain |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['dataset']} | {r['kind']} | {r['outliers']} | {r['chains']} | {r['method']} | {r['accepted']} | "
                    f"{r['precision']:.4f} | {r['recall']:.4f} | {r['ate']:.3f} | {r['joined']} / {r['pairs_to_join']} | "
                    f"{r['wrongly_joined']} | {r['seconds']:.2f} | {r['ratio']:.2f} |\n")
    print(f"wrote {out / 'table.md'}")


if __name__ == "__main__":
    main()
