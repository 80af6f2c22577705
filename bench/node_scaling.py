#!/usr/bin/python3
"""Scaling replay: a spoiled dataset (default city10000 + 1000 random false
loops, rrr spoil --seed 1) written as a bag with odometry at RATE Hz
(rrr to-bag --rate), played in real time into rrr_node with each procedure,
~get_status sampled every second. Reports, per procedure: the update time
percentiles (from the node), the largest queue, the node's peak memory,
whether the final decisions equal rrr verify's with the same procedure, and
the growth of the update time with the keyframes (the slope of log time
against log keyframes, on the 90th percentile, in each 1000 keyframes, of
the longest of the node's last 100 updates, sampled every second). Writes samples (CSV), a summary (JSON) and the plot
bench/plots/node_scaling.png.

    bench/node_scaling.py [--dataset city10000] [--outliers 1000] [--rate 50]
                          [--procedures map published] [--limit 1800]

A procedure that has not taken in every input after --limit seconds is
stopped there; its samples up to then are kept and plotted.
"""
import argparse
import csv
import json
import math
import pathlib
import shutil
import subprocess
import threading

import common
import ros_processes

SAMPLER = common.ROOT / "bench" / "status_sampler.py"


def growth(samples, min_keyframes, bin_size=1000):
    """The slope of log(update seconds) on log(keyframes), fitted to the 90th
    percentile in each bin of `bin_size` keyframes (from `min_keyframes` on)
    of the sampled longest update of the last 100: 1 is linear growth, 0
    none."""
    bins = {}
    for s in samples:
        if s["keyframes"] >= min_keyframes and s["recent_max_update_seconds"] > 0:
            bins.setdefault(s["keyframes"] // bin_size, []).append(s["recent_max_update_seconds"])
    points = []
    for b, values in bins.items():
        values.sort()
        points.append((math.log((b + 0.5) * bin_size), math.log(values[int(0.9 * (len(values) - 1))])))
    if len(points) < 3:
        return float("nan")
    mx = sum(x for x, _ in points) / len(points)
    my = sum(y for _, y in points) / len(points)
    sxx = sum((x - mx) ** 2 for x, _ in points)
    return sum((x - mx) * (y - my) for x, y in points) / sxx if sxx > 0 else float("nan")


def replay(procedure, bag, graph_info, window, limit, port, out):
    """Plays the bag into rrr_node with `procedure`; returns (samples, final
    status, whether every input was processed, the accepted loops or None).
    Samples are also written to out/samples.csv as they arrive."""
    env = common.ros_env(port)
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "rrr_slam", "replay.launch", f"bag:={bag}",
         "rate:=1", f"cluster_window:={window}", f"procedure:={procedure}"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    samples, complete, accepted, final = [], False, None, {}
    try:
        pid = ros_processes.node_pid(launch)
        sampler = subprocess.Popen(["/usr/bin/python3", str(SAMPLER), str(pid), "1.0", str(limit)],
                                   env=env, stdout=subprocess.PIPE, text=True)
        # A service call can block while the node is inside a long update:
        # the sampler is stopped at the limit whatever it is doing.
        stop = threading.Timer(limit + 5, sampler.kill)
        stop.start()
        with open(out / "samples.csv", "w", newline="") as f:
            writer = None
            for line in sampler.stdout:
                sample = json.loads(line)
                samples.append(sample)
                if writer is None:
                    writer = csv.DictWriter(f, fieldnames=list(sample.keys()))
                    writer.writeheader()
                writer.writerow(sample)
                f.flush()
                if sample["inputs_processed"] == graph_info["poses"] + graph_info["candidates"]:
                    complete = True
                    break
        stop.cancel()
        sampler.terminate()
        sampler.wait()
        final = dict(samples[-1]) if samples else {}
        if complete:
            saved = out / f"node_{procedure}.g2o"
            try:
                common.service(env, "/rrr_node/finish")
                common.service(env, "/rrr_node/save_graph",
                               f"{{path: '{saved}', with_candidates: false}}")
                fields = common.service(env, "/rrr_node/get_status")
                final.update({k: fields[k] for k in final if k in fields})
                _, loops = common.loop_lines(saved)
                accepted = {key for key, _ in loops}
            except (subprocess.TimeoutExpired, OSError) as error:
                print(f"{procedure}: the final services failed: {error}", flush=True)
        try:
            final["peak_rss_mb"] = ros_processes.resident_mb(pid)[1]
        except OSError:
            pass
    finally:
        ros_processes.stop(launch)
    return samples, final, complete, accepted


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dataset", default="city10000")
    parser.add_argument("--outliers", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--rate", type=float, default=50.0)
    parser.add_argument("--procedures", nargs="+", default=["map", "published"])
    parser.add_argument("--limit", type=float, default=1800.0,
                        help="seconds a replay may take before it is stopped")
    parser.add_argument("--port", type=int, default=11541)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "node_scaling"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    source = common.datasets_dir() / "synthetic" / f"{args.dataset}.g2o"
    spoiled = out / f"{args.dataset}_{args.outliers}.g2o"
    common.run("spoil", source, "--outliers", args.outliers, "--seed", args.seed,
               "--output", spoiled, "--truth", out / "false_loops.txt")
    bag = out / "input.bag"
    common.run("to-bag", spoiled, "--rate", args.rate, "--output", bag)

    summary, series = {}, {}
    for procedure in args.procedures:
        run_dir = out / procedure
        run_dir.mkdir(exist_ok=True)
        expected = None
        if procedure == "map":  # the published rrr verify takes minutes here
            report, _, _ = common.verify(spoiled, args.window, run_dir, 1,
                                         ["--procedure", procedure])
            expected = {tuple(p) for p in report["accepted"]}
            info = {"poses": report["poses"], "candidates": report["candidates"]}
        else:
            info = summary.get("map", {}).get("inputs") or common.graph_size(spoiled)
        samples, final, complete, accepted = replay(
            procedure, bag, info, args.window, args.limit, args.port, run_dir)
        series[procedure] = samples
        summary[procedure] = {
            "inputs": info,
            "complete": complete,
            "keyframes_reached": samples[-1]["keyframes"] if samples else 0,
            "update_seconds_p50": float(final.get("update_seconds_p50", 0)),
            "update_seconds_p99": float(final.get("update_seconds_p99", 0)),
            "max_update_seconds": float(final.get("max_update_seconds", 0)),
            "max_queue_length": int(final.get("max_queue_length", 0)),
            "inputs_dropped": int(final.get("inputs_dropped", 0)),
            "peak_rss_mb": final.get("peak_rss_mb"),
            "accepted": len(accepted) if accepted is not None else None,
            "equal_to_rrr_verify": (accepted == expected) if expected is not None and
                                   accepted is not None else None,
            "growth_exponent": growth(samples, 1000),
        }
        print(f"{procedure}: {json.dumps(summary[procedure])}", flush=True)
    with open(out / "summary.json", "w") as f:
        json.dump(summary, f, indent=1)
    plot(series, out / "node_scaling.png", args)
    plots = common.ROOT / "bench" / "plots"
    plots.mkdir(exist_ok=True)
    shutil.copy(out / "node_scaling.png", plots / "node_scaling.png")


def plot(series, path, args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for procedure, samples in series.items():
        points = [(s["keyframes"], s["recent_max_update_seconds"]) for s in samples
                  if s["recent_max_update_seconds"] > 0]
        ax.scatter([p[0] for p in points], [1000 * p[1] for p in points], s=6,
                   label=f"{procedure} procedure")
    ax.set_yscale("log")
    ax.set_xlabel("keyframes")
    ax.set_ylabel("longest of the last 100 updates (ms)")
    ax.set_title(f"rrr_node on {args.dataset} + {args.outliers} false loops at {args.rate:g} Hz")
    ax.axhline(100, color="grey", linestyle="--", linewidth=0.8)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
