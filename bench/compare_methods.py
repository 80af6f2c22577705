#!/usr/bin/python3
"""Every method on every spoiled dataset: RRR as published, RRR with the map
procedure (the recommended configuration), DCS, GNC-TLS and PCM, each run
with rrr verify on the same spoiled file and scored the same way (precision,
recall, ATE against the optimum of the dataset without false loops, seconds,
peak memory). Writes results.json, a Markdown table (table.md) and one plot
per dataset (precision, recall and ATE by method and set) into OUT.

    bench/compare_methods.py [--datasets manhattanOlson3500 intel city10000 sphere2500]
        [--outliers 100 500 1000] [--kinds random local grouped] [--group 10]
        [--seeds 1 2 3] [--methods published map dcs gnc pcm]
        [--timeout 900] [--reuse] [--out bench/out/compare]

A run that takes longer than --timeout seconds is stopped and reported as
such (the published procedure needs hours on city10000 with 1000 false
loops). With --reuse, a method whose report is already in OUT from an earlier
run on the same spoiled set (same bytes) is scored from it, not run again (so
one method can be re-run after a change while the others' runs are kept); a
run on it that was stopped at a timeout at least as long is reported stopped
again.
"""
import argparse
import hashlib
import json
import pathlib
import subprocess

import common

METHODS = {
    "published": ["--procedure", "published"],
    "map": ["--procedure", "map"],
    "dcs": ["--method", "dcs"],
    "gnc": ["--method", "gnc"],
    "pcm": ["--method", "pcm"],
}


# The spoiled-set matrix of BENCHMARKS.md ("Spoiled synthetic sets, every method"): 108 sets.
MATRIX = dict(datasets=["manhattanOlson3500", "intel", "city10000", "sphere2500"],
              outliers=[100, 500, 1000], kinds=["random", "local", "grouped"], group=10,
              seeds=[1, 2, 3], window=10)


def run_method(spoiled, window, run_dir, method, timeout, reuse):
    """rrr verify with `method`; (report, map path) or None on timeout."""
    run_dir.mkdir(parents=True, exist_ok=True)
    out_map, report = run_dir / "verified.g2o", run_dir / "report.json"
    stopped = run_dir / "stopped"
    # Reused only if made by this script on this very input.
    digest = hashlib.sha256(spoiled.read_bytes()).hexdigest()
    if reuse and report.exists() and out_map.exists():
        result = common.read_json(report)
        if "peak_rss_mb" in result and result.get("input_sha256") == digest:
            return result, out_map
    if reuse and stopped.exists():
        timeout_then, _, digest_then = stopped.read_text().partition(" ")
        if float(timeout_then) >= timeout and digest_then.strip() == digest:
            return None
    stopped.unlink(missing_ok=True)
    try:
        _, peak = common.run_measured("verify", spoiled, "--window", window, "--output", out_map,
                                      "--report", report, *METHODS[method], timeout=timeout)
    except subprocess.TimeoutExpired:
        stopped.write_text(f"{timeout} {digest}\n")
        return None
    result = common.read_json(report)
    result["peak_rss_mb"] = peak
    result["input_sha256"] = digest
    report.write_text(json.dumps(result, indent=1))
    return result, out_map


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--datasets", nargs="*", default=MATRIX["datasets"])
    parser.add_argument("--outliers", nargs="*", type=int, default=MATRIX["outliers"])
    parser.add_argument("--kinds", nargs="*", default=MATRIX["kinds"],
                        choices=common.SPOIL_KINDS)
    parser.add_argument("--group", type=int, default=MATRIX["group"])
    parser.add_argument("--seeds", nargs="*", type=int, default=MATRIX["seeds"])
    parser.add_argument("--methods", nargs="*", default=list(METHODS), choices=list(METHODS))
    parser.add_argument("--window", type=int, default=MATRIX["window"])
    parser.add_argument("--timeout", type=float, default=900)
    parser.add_argument("--reuse", action="store_true",
                        help="score a method from its report of an earlier run in OUT")
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "compare"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for spoiled_set in common.spoiled_sets(args, out):
        for method in args.methods:
            row = {key: spoiled_set[key] for key in ("kind", "outliers", "seed")}
            row.update(dataset=spoiled_set["name"], method=method)
            method_dir = spoiled_set["folder"] / method
            done = run_method(spoiled_set["spoiled"], args.window, method_dir, method,
                              args.timeout, args.reuse)
            if done is None:
                row.update(timeout=True)
            else:
                report, out_map = done
                scores = common.evaluate(method_dir / "report.json", "--map", out_map,
                                         "--false-loops", spoiled_set["false_list"],
                                         "--gt-g2o", spoiled_set["optimum"])
                row.update(timeout=False, accepted=scores["accepted"],
                           precision=scores["precision"], recall=scores["recall"],
                           ate=scores["ate_rmse"], seconds=report["seconds"],
                           peak_rss_mb=report["peak_rss_mb"])
            rows.append(row)
            print(json.dumps(row), flush=True)
            (out / "results.json").write_text(json.dumps(rows, indent=1))
    write_table(rows, out / "table.md")
    plot(rows, out)


def write_table(rows, path):
    """A summary by dataset and method (worst precision, recall and ATE over
    its sets, median seconds), then every run."""
    lines = ["| dataset | method | sets | stopped | worst precision | worst recall | worst ATE m | "
             "median s |", "|---|---|---|---|---|---|---|---|"]
    for name in sorted({r["dataset"] for r in rows}):
        for method in METHODS:
            runs = [r for r in rows if r["dataset"] == name and r["method"] == method]
            done = [r for r in runs if not r["timeout"]]
            if not runs:
                continue
            if not done:
                lines.append(f"| {name} | {method} | {len(runs)} | {len(runs)} | – | – | – | – |")
                continue
            seconds = sorted(r["seconds"] for r in done)
            lines.append(f"| {name} | {method} | {len(runs)} | {len(runs) - len(done)} | "
                         f"{min(r['precision'] for r in done):.4f} | "
                         f"{min(r['recall'] for r in done):.4f} | "
                         f"{max(r['ate'] for r in done):.3f} | {seconds[len(seconds) // 2]:.2f} |")
    lines += ["", "| dataset | kind | N | seed | method | precision | recall | ATE m | s |",
              "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["timeout"]:
            figures = "– | – | – | stopped"
        else:
            figures = (f"{r['precision']:.4f} | {r['recall']:.4f} | {r['ate']:.3f} | "
                       f"{r['seconds']:.2f}")
        lines.append(f"| {r['dataset']} | {r['kind']} | {r['outliers']} | {r['seed']} | "
                     f"{r['method']} | {figures} |")
    path.write_text("\n".join(lines) + "\n")


def plot(rows, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for name in sorted({r["dataset"] for r in rows}):
        sets = sorted({(r["kind"], r["outliers"], r["seed"]) for r in rows if r["dataset"] == name})
        methods = [m for m in METHODS if any(r["method"] == m for r in rows)]
        fig, axes = plt.subplots(3, 1, figsize=(max(8, len(sets) * 0.45), 8), sharex=True)
        for m_index, method in enumerate(methods):
            for axis, key in zip(axes, ("precision", "recall", "ate")):
                xs, ys = [], []
                for s_index, (kind, n, seed) in enumerate(sets):
                    for r in rows:
                        if (r["dataset"], r["kind"], r["outliers"], r["seed"], r["method"]) == \
                                (name, kind, n, seed, method) and not r["timeout"]:
                            xs.append(s_index + 0.12 * (m_index - len(methods) / 2))
                            ys.append(r[key])
                axis.scatter(xs, ys, s=12, label=method)
        for axis, label in zip(axes, ("precision", "recall", "ATE (m)")):
            axis.set_ylabel(label)
        axes[2].set_yscale("symlog", linthresh=0.1)
        axes[2].set_xticks(range(len(sets)))
        axes[2].set_xticklabels([f"{k[:4]} {n} s{s}" for k, n, s in sets], rotation=90, fontsize=7)
        axes[0].legend(ncol=len(methods), fontsize=8)
        axes[0].set_title(f"{name}: every method on the same spoiled sets")
        fig.tight_layout()
        fig.savefig(out / f"compare_{name}.png", dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
