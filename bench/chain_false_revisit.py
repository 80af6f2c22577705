#!/usr/bin/env python3
"""A false revisit inside one session that only the other session refutes
("A false revisit inside a chain", in the git history of BENCHMARKS.md).

Each world is `rrr simulate` (a grid city, no false loops) of --poses poses
cut into two sessions at its middle (bench/chains.py's cut). Inside the
second session come --group false loops (s+k -> s+gap+k, k = 0..group-1, s
the session's first pose + --second) whose measurement is what the odometry
between their poses says, moved by --offset metres ahead and 0.03 rad per
metre: a revisit that the odometry's drift over the gap can explain, so the
second session's own loops may not refute it, while the loops between the
sessions (true revisits of the first session's places) do. The same loops
are judged in the uncut world (one chain) and in the two sessions; the table
gives, for each, the true loops kept and the false ones accepted, by each
method of --methods (rrr: the map procedure; dcs, gnc, pcm).

    bench/chain_false_revisit.py [--seeds 3 4 5 6] [--second 100 300]
        [--gap 200 400] [--offset 2 3.5] [--methods rrr]
        [--out bench/out/chain_false_revisit]
"""
import argparse
import math
import pathlib

import chains
import common


def se2_vertices(path):
    """The SE(2) vertex estimates of a g2o file, by id."""
    poses = {}
    for line in open(path):
        fields = line.split()
        if fields and fields[0] == "VERTEX_SE2":
            poses[int(fields[1])] = tuple(map(float, fields[2:5]))
    return poses


def between(a, b):
    """a⁻¹·b for SE(2) poses (x, y, θ)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, b[2] - a[2])


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def false_revisit(world, first, second, gap, group, offset):
    """The false loops as EDGE_SE2 lines, with the information of the world's
    first loop, and their pose pairs."""
    poses = se2_vertices(world)
    _, loops = common.loop_lines(world)
    information = loops[0][1].split()[6:12]
    moved = (offset, 0.0, 0.03 * offset)
    lines, pairs = [], set()
    for k in range(group):
        i = first + second + k
        j = i + gap
        z = compose(between(poses[i], poses[j]), moved)
        lines.append(" ".join(["EDGE_SE2", str(i), str(j), *(f"{v:.9g}" for v in z), *information]) + "\n")
        pairs.add((i, j))
    return lines, pairs


def judged(graph, folder, false_pairs, method):
    """(true loops kept, false loops accepted) by rrr verify --method `method`
    on `graph`."""
    folder.mkdir(parents=True, exist_ok=True)
    report, _, _ = common.verify(graph, 10, folder, extra=("--method", method))
    wrong = sum(1 for a, b in report["accepted"] if (a, b) in false_pairs or (b, a) in false_pairs)
    return len(report["accepted"]) - wrong, wrong


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", nargs="*", type=int, default=[3, 4, 5, 6])
    parser.add_argument("--poses", type=int, default=1600)
    parser.add_argument("--second", nargs="*", type=int, default=[100, 300])
    parser.add_argument("--gap", nargs="*", type=int, default=[200, 400])
    parser.add_argument("--offset", nargs="*", type=float, default=[2.0, 3.5])
    parser.add_argument("--group", type=int, default=10)
    parser.add_argument("--methods", nargs="*", default=["rrr"], choices=["rrr", "dcs", "gnc", "pcm"])
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "chain_false_revisit"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for seed in args.seeds:
        world = out / f"world_{seed}.g2o"
        common.run("simulate", "--poses", args.poses, "--false-loops", 0, "--seed", seed, "-o", world,
                   "-t", out / f"world_{seed}.false", "--ground-truth", out / f"world_{seed}.gt")
        two = out / f"world_{seed}_two.g2o"
        firsts = chains.cut(world, two, 2)
        texts = {"one": world.read_text(), "two": two.read_text()}
        for second in args.second:
            for gap in args.gap:
                for offset in args.offset:
                    name = f"{seed}_{second}_{gap}_{offset:g}"
                    lines, pairs = false_revisit(world, firsts[1], second, gap, args.group, offset)
                    graphs = {}
                    for kind, text in texts.items():
                        graphs[kind] = out / f"{name}_{kind}.g2o"
                        graphs[kind].write_text(text + "".join(lines))
                    for method in args.methods:
                        row = dict(method=method, seed=seed, second=second, gap=gap, offset=offset)
                        for kind, graph in graphs.items():
                            row[f"{kind}_kept"], row[f"{kind}_false"] = judged(
                                graph, out / f"{name}_{kind}_{method}", pairs, method)
                        rows.append(row)
                        print(*row.values(), flush=True)
    for method in args.methods:
        mine = [r for r in rows if r["method"] == method]
        worse = sum(1 for r in mine if r["two_false"] > r["one_false"])
        wrong = sum(1 for r in mine if r["two_false"] > 0)
        print(f"{method}: {len(mine)} worlds; false loops accepted in {wrong} as two sessions, "
              f"more than as one chain in {worse}")
    columns = ["method", "seed", "second", "gap", "offset m", "one chain: true kept", "one chain: false accepted",
               "two sessions: true kept", "two sessions: false accepted"]
    common.write_results(out, rows, columns, lambda r: [f"{v:g}" if isinstance(v, float) else str(v)
                                                        for v in r.values()])


if __name__ == "__main__":
    main()
