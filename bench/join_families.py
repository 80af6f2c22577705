#!/usr/bin/python3
"""Chains that meet the way real sessions and robots meet (BENCHMARKS.md,
"Several chains: the join families"). Five families, each a graph of
several odometry chains with its ground truth:

  kitti   more/kitti_05 and kitti_02 cut in two where the most loops cross
          the cut (the second session drives back through the first along
          one stretch); clean, + 50 random and + 50 look-alike (groups of 5)
          false loops between the sessions.
  ring    a simulated ring of 400 poses driven 440, cut in two robots at pose
          220 (they meet once, at the start); clean, + 10 local false loops
          inside the robots, + 20 false loops between them (groups of 5).
  city    synthetic/city10000 cut in three robots at its thirds; + 100 and
          + 1,000 false loops anywhere (groups of 10), + 100 look-alike false
          loops between robots (groups of 5).
  robots  simulated grid fleets of 3 and 4 robots (rrr simulate --robots,
          keys as GTSAM symbols, fed side by side); + 100 and + 1,000
          look-alike false loops in groups of 5, anywhere or between robots.
  never   two datasets that never meet (intel and manhattanOlson3500,
          manhattanOlson3500 and city10000, the second 10 km away); 50 false
          clusters between them: groups of 5 (random or look-alike) and of 10.

Each set is judged by each method of rrr verify and scored: precision and
recall over every loop, the ATE against the optimum of the graph without
false loops (one alignment for the whole graph: chains left apart show), the
pairs of chains with true loops between them that were joined, the pairs
without any that were (wrongly), and the time. Where a set is a cut of one
graph, the same graph uncut (the same loops) is judged too: a joined set
meets its ATE target within 10 % + 5 cm of the uncut one's.

    bench/join_families.py [--families kitti ring city robots never]
        [--methods rrr pcm gnc] [--out bench/out/join_families]
"""
import argparse
import pathlib

import chains
import common
import never_meet


def loop_pairs(path):
    """The (i, j) of every loop of g2o `path`."""
    return [key for key, _ in common.loop_lines(path)[1]]


def best_cut(path):
    """The pose id that cuts g2o `path` (one chain) where the most loops
    cross the cut, among the ids at least a tenth of the way from each end."""
    loops = loop_pairs(path)
    ids = sorted({i for key in loops for i in key} |
                 {int(l.split()[1]) for l in open(path) if l.startswith("VERTEX")} |
                 {int(f) for l in open(path) if l.startswith("EDGE") for f in l.split()[1:3]})
    lo, hi = ids[len(ids) // 10], ids[-len(ids) // 10]
    return max(range(lo, hi + 1, 10), key=lambda c: sum(1 for a, b in loops if min(a, b) < c <= max(a, b)))


def first_id(path):
    """The lowest pose id of g2o `path` (a vertex's, or an edge's end)."""
    return min(int(f) for line in open(path) if line.startswith(("VERTEX", "EDGE"))
               for f in line.split()[1:(2 if line.startswith("VERTEX") else 3)])


def uncut_with(clean, cut_graph, dst):
    """`clean` (one chain) with the loops of `cut_graph` (the same ids): the
    same set uncut."""
    keep, _ = common.loop_lines(clean)
    _, loops = common.loop_lines(cut_graph)
    with open(dst, "w") as f:
        f.writelines(keep)
        f.writelines(line for _, line in loops)


def spoil(src, dst, false_list, n, kind, group, between, reference, seed=1):
    flags = ["--look-alike"] if kind == "look-alike" else ["--local"] if kind == "local" else []
    if group > 1:
        flags += ["--group", group]
    if between:
        flags.append("--between-chains")
    if reference:
        flags += ["--reference", reference]
    common.run("spoil", src, "--outliers", n, "--seed", seed, *flags, "--output", dst, "--truth", false_list)


def sets(families, out):
    """Yields each set: its name, graph, list of false loops, reference (the
    optimum without false loops, same ids), chain firsts (None for symbol
    keys) and the uncut graph of the same loops (or None)."""
    empty = out / "no_false.txt"
    empty.write_text("")
    if "kitti" in families:
        for name in ("kitti_05", "kitti_02"):
            clean = common.dataset_path(name)
            if not clean.exists():
                print(f"{name}: {clean} not found, skipped", flush=True)
                continue
            optimum = out / f"{name}_optimum.g2o"
            common.run("optimize", clean, "--output", optimum)
            c = best_cut(clean)
            across = sum(1 for a, b in loop_pairs(clean) if min(a, b) < c <= max(a, b))
            two = out / f"{name}_cut.g2o"
            firsts = chains.cut(clean, two, 2, [first_id(clean), c])
            for label, n, kind, group in (("clean", 0, "", 1), ("50 random between", 50, "random", 1),
                                          ("50 look-alike between (5)", 50, "look-alike", 5)):
                graph, false_list = (two, empty) if n == 0 else (out / f"{name}_{kind}.g2o", out / f"{name}_{kind}.txt")
                if n:
                    spoil(two, graph, false_list, n, kind, group, True, optimum)
                uncut = out / f"{graph.stem}_uncut.g2o"
                uncut_with(clean, graph, uncut)
                yield dict(family="kitti", name=f"{name} cut at {c} ({across} loops across), {label}", graph=graph, false_list=false_list,
                           reference=optimum, firsts=firsts, uncut=uncut)
    if "ring" in families:
        for seed in (1, 2):
            world, truth = out / f"ring_{seed}.g2o", out / f"ring_{seed}_truth.g2o"
            common.run("simulate", "--layout", "ring", "--ring", 400, "--poses", 440, "--false-loops", 0,
                       "--seed", seed, "--output", world, "--truth", out / "ring_false.txt", "--ground-truth", truth)
            optimum = out / f"ring_{seed}_optimum.g2o"
            common.run("optimize", world, "--output", optimum)
            two = out / f"ring_{seed}_cut.g2o"
            firsts = chains.cut(world, two, 2, [0, 220])
            for label, n, kind, group, between in (("clean", 0, "", 1, False),
                                                   ("10 local inside", 10, "local", 1, False),
                                                   ("20 between (5)", 20, "random", 5, True)):
                graph, false_list = (two, empty) if n == 0 else (out / f"ring_{seed}_{kind}.g2o",
                                                                  out / f"ring_{seed}_{kind}.txt")
                if n:
                    spoil(two, graph, false_list, n, kind, group, between, optimum)
                uncut = out / f"{graph.stem}_uncut.g2o"
                uncut_with(world, graph, uncut)
                yield dict(family="ring", name=f"ring seed {seed}, {label}", graph=graph, false_list=false_list,
                           reference=optimum, firsts=firsts, uncut=uncut)
    if "city" in families:
        clean = common.dataset_path("city10000")
        if clean.exists():
            optimum = out / "city10000_optimum.g2o"
            common.run("optimize", clean, "--output", optimum)
            three = out / "city10000_three.g2o"
            firsts = chains.cut(clean, three, 3)
            for label, n, kind, group, between in (("100 grouped (10)", 100, "random", 10, False),
                                                   ("1000 grouped (10)", 1000, "random", 10, False),
                                                   ("100 look-alike between (5)", 100, "look-alike", 5, True)):
                graph, false_list = out / f"city_{n}_{kind}_{between}.g2o", out / f"city_{n}_{kind}_{between}.txt"
                spoil(three, graph, false_list, n, kind, group, between, optimum)
                uncut = out / f"{graph.stem}_uncut.g2o"
                uncut_with(clean, graph, uncut)
                yield dict(family="city", name=f"city10000 in 3, {label}", graph=graph, false_list=false_list,
                           reference=optimum, firsts=firsts, uncut=uncut)
    if "robots" in families:
        for robots in (3, 4):
            world, truth = out / f"fleet_{robots}.g2o", out / f"fleet_{robots}_truth.g2o"
            own_false = out / f"fleet_{robots}_false.txt"
            common.run("simulate", "--robots", robots, "--poses", 3000, "--false-loops", 0, "--seed", 40 + robots,
                       "--output", world, "--truth", own_false, "--ground-truth", truth)
            optimum = out / f"fleet_{robots}_optimum.g2o"
            common.run("optimize", world, "--output", optimum)
            for n in (100, 1000):
                for between in (False, True):
                    graph = out / f"fleet_{robots}_{n}_{between}.g2o"
                    false_list = out / f"fleet_{robots}_{n}_{between}.txt"
                    spoil(world, graph, false_list, n, "look-alike", 5, between, optimum)
                    where = "between robots" if between else "anywhere"
                    yield dict(family="robots", name=f"{robots} robots, {n} look-alike (5) {where}", graph=graph,
                               false_list=false_list, reference=optimum, firsts=None, uncut=None)
    if "never" in families:
        for first, second in (("intel", "manhattanOlson3500"), ("manhattanOlson3500", "city10000")):
            a, b = common.dataset_path(first), common.dataset_path(second)
            if not (a.exists() and b.exists()):
                print(f"{first} or {second} not found, skipped", flush=True)
                continue
            both = out / f"{first}_{second}.g2o"
            offset = never_meet.merged(a, b, both)
            # The reference: each dataset's optimum, merged the same way.
            optima = [out / f"{name}_alone_optimum.g2o" for name in (first, second)]
            for src, dst in zip((a, b), optima):
                common.run("optimize", src, "--output", dst)
            optimum = out / f"{first}_{second}_optimum.g2o"
            never_meet.merged(*optima, optimum)
            for label, n, kind, group in (("50 groups of 5", 250, "random", 5),
                                          ("50 look-alike groups of 5", 250, "look-alike", 5),
                                          ("50 groups of 10", 500, "random", 10)):
                graph = out / f"{first}_{second}_{kind}_{group}.g2o"
                false_list = out / f"{first}_{second}_{kind}_{group}.txt"
                spoil(both, graph, false_list, n, kind, group, True, optimum)
                yield dict(family="never", name=f"{first} + {second}, {label}", graph=graph,
                           false_list=false_list, reference=optimum, firsts=[0, offset], uncut=None)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--families", nargs="*", default=["kitti", "ring", "city", "robots", "never"])
    parser.add_argument("--methods", nargs="*", default=["rrr", "pcm", "gnc"], choices=["rrr", "dcs", "gnc", "pcm"])
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "join_families"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    header = ("family", "set", "method", "prec", "recall", "ATE", "uncut ATE", "joined", "wrong", "s", "meets")
    print(" | ".join(header), flush=True)
    rows = []
    for s in sets(args.families, out):
        false_pairs = set()
        for line in open(s["false_list"]):
            if line.strip() and not line.startswith("#"):
                i, j = map(int, line.split()[:2])
                false_pairs.add(tuple(sorted((i, j))))
        for method in args.methods:
            folder = out / f"{s['graph'].stem}_{method}"
            folder.mkdir(exist_ok=True)
            extra = ("--method", method)
            try:
                report, seconds, out_map = common.verify(s["graph"], args.window, folder, extra=extra)
            except SystemExit as e:  # a method that cannot judge the graph
                print(f"{s['family']} | {s['name']} | {method} | failed: {e}", flush=True)
                continue
            scores = common.evaluate(folder / "report.json", "--map", out_map, "--false-loops", s["false_list"],
                                     "--gt-g2o", s["reference"])
            chain_firsts = s["firsts"] or [c["first"] for c in report.get("chains", [{"first": 0}])]
            wanted = chains.chain_pairs(report["accepted"] + report["rejected"], chain_firsts, false_pairs)
            joined = chains.chain_pairs(report["accepted"], chain_firsts)
            uncut_ate = None
            if s["uncut"] is not None and method == "rrr":
                uncut_folder = out / f"{s['graph'].stem}_uncut_{method}"
                uncut_folder.mkdir(exist_ok=True)
                _, _, uncut_map = common.verify(s["uncut"], args.window, uncut_folder, extra=extra)
                uncut_ate = common.evaluate(uncut_folder / "report.json", "--map", uncut_map, "--false-loops",
                                            s["false_list"], "--gt-g2o", s["reference"])["ate_rmse"]
            precision_target = 1.0 if len(false_pairs) <= 100 else 0.999
            # Every set keeps its true loops (chains apart keep their own),
            # joins what meets and nothing else, and a joined cut set is as
            # good as the graph uncut.
            meets = (scores["precision"] >= precision_target and scores["recall"] >= 0.98 and
                     not (joined - wanted) and joined >= wanted and
                     (uncut_ate is None or scores["ate_rmse"] <= 1.1 * uncut_ate + 0.05))
            row = dict(family=s["family"], set=s["name"], method=method, precision=scores["precision"],
                       recall=scores["recall"], ate=scores["ate_rmse"], uncut_ate=uncut_ate,
                       pairs_to_join=len(wanted), joined=len(joined & wanted), wrongly_joined=len(joined - wanted),
                       seconds=seconds, meets=meets)
            rows.append(row)
            print(f"{row['family']} | {row['set']} | {method} | {row['precision']:.4f} | {row['recall']:.4f} | "
                  f"{row['ate']:.3f} | {'' if uncut_ate is None else f'{uncut_ate:.3f}'} | "
                  f"{row['joined']}/{row['pairs_to_join']} | {row['wrongly_joined']} | {seconds:.2f} | "
                  f"{'yes' if meets else 'no'}", flush=True)
    common.write_results(out, rows, header, lambda r: [
        r["family"], r["set"], r["method"], f"{r['precision']:.4f}", f"{r['recall']:.4f}", f"{r['ate']:.3f}",
        "" if r["uncut_ate"] is None else f"{r['uncut_ate']:.3f}", f"{r['joined']}/{r['pairs_to_join']}",
        str(r["wrongly_joined"]), f"{r['seconds']:.2f}", "yes" if r["meets"] else "no"])


if __name__ == "__main__":
    main()
