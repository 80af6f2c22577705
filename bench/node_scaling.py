#!/usr/bin/python3
"""Scaling replay: a spoiled dataset (default city10000 + 1000 random false
loops, rrr spoil --seed 1), or with --world N a simulated world of N poses
(rrr simulate: revisits throughout, --outliers false loops in groups of 4),
written as a bag with odometry at RATE Hz (rrr to-bag --rate), played at
PLAY times real time into rrr_node with each procedure (with --database, into
a session database that is then resumed and timed),
~get_status sampled every second. Reports, per procedure: the update time
percentiles (from the node), the largest queue, the node's peak memory,
whether the final decisions equal rrr verify's with the same procedure, and
the growth of the update time with the keyframes (the slope of log time
against log keyframes, on the 90th percentile, in each 1000 keyframes, of
the longest of the node's last 100 updates, sampled every second). Writes samples (CSV), a summary (JSON) and the plot
(OUT/node_scaling.png, or --plot PATH).

    bench/node_scaling.py [--dataset city10000 | --world 100000] [--outliers 1000]
                          [--rate 50] [--play 1] [--database]
                          [--procedures map published] [--limit 1800] [--plot PATH]

A procedure that has not taken in every input after --limit seconds is
stopped there; its samples up to then are kept and plotted.
"""
import argparse
import csv
import json
import math
import pathlib
import subprocess
import threading
import time

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


def p99_growth(samples, from_keyframes):
    """The growth exponent of the node's update-time p99 (over the updates
    so far) from the first sample at `from_keyframes` keyframes or more to
    the last: log(p99 ratio) / log(keyframes ratio)."""
    later = [s for s in samples if s["keyframes"] >= from_keyframes and s["update_seconds_p99"] > 0]
    if len(later) < 2 or later[-1]["keyframes"] <= later[0]["keyframes"]:
        return float("nan")
    return (math.log(later[-1]["update_seconds_p99"] / later[0]["update_seconds_p99"]) /
            math.log(later[-1]["keyframes"] / later[0]["keyframes"]))


def replay(procedure, bag, graph_info, window, limit, port, out, play=1.0, database=None):
    """Plays the bag into rrr_node with `procedure`; returns (samples, final
    status, whether every input was processed, the accepted loops or None).
    Samples are also written to out/samples.csv as they arrive."""
    env = common.ros_env(port)
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "rrr_slam", "replay.launch", f"bag:={bag}",
         f"rate:={play}", f"cluster_window:={window}", f"procedure:={procedure}",
         f"database:={database or ''}"],
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


def resume(database, procedure, window, port, info):
    """Starts rrr_node on the recorded session `database` with no input and
    times how long it takes until ~get_status answers with every keyframe
    resumed; returns that, the update whose checkpoint it restored (0: none),
    the database's size and its bytes per keyframe and candidate."""
    env = common.ros_env(port)
    size = sum(p.stat().st_size for p in database.parent.glob(database.name + "*"))
    start = time.monotonic()
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "rrr_slam", "rrr.launch", f"cluster_window:={window}",
         f"procedure:={procedure}", f"database:={database}"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    seconds = checkpoint = None
    try:
        while time.monotonic() - start < 600:
            fields = common.service(env, "/rrr_node/get_status", timeout=60)
            if fields and int(fields["resumed_keyframes"]) >= info["poses"]:
                seconds = time.monotonic() - start
                checkpoint = int(fields["resumed_from_update"])
                break
            time.sleep(0.5)
    finally:
        ros_processes.stop(launch)
    return {"database_bytes": size,
            "database_bytes_per_keyframe_and_candidate": size / (info["poses"] + info["candidates"]),
            "resume_seconds": seconds,
            "resumed_from_update": checkpoint}


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dataset", default="city10000")
    parser.add_argument("--world", type=int, default=0,
                        help="replay a simulated world of this many poses instead of a dataset")
    parser.add_argument("--play", type=float, default=1.0, help="rosbag play's rate factor")
    parser.add_argument("--database", action="store_true",
                        help="record a session database, then time resuming it")
    parser.add_argument("--outliers", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--rate", type=float, default=50.0)
    parser.add_argument("--procedures", nargs="+", default=["map", "published"])
    parser.add_argument("--limit", type=float, default=1800.0,
                        help="seconds a replay may take before it is stopped")
    parser.add_argument("--port", type=int, default=11541)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "node_scaling"))
    parser.add_argument("--plot", help="where the plot goes (default OUT/node_scaling[_worldN].png)")
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    if args.world:
        args.dataset = f"world{args.world}"
        spoiled = out / f"world{args.world}_{args.outliers}.g2o"
        common.run("simulate", "--poses", args.world, "--false-loops", args.outliers,
                   "--group", 4, "--seed", args.seed, "--output", spoiled,
                   "--truth", out / "false_loops.txt", "--ground-truth", out / "world_truth.g2o")
    else:
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
        database = run_dir / "session.db" if args.database else None
        if database:
            for stale in run_dir.glob("session.db*"):
                stale.unlink()
        samples, final, complete, accepted = replay(
            procedure, bag, info, args.window, args.limit, args.port, run_dir, args.play, database)
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
            "growth_exponent_from_10000": growth(samples, 10000, 10000),
            "p99_growth_exponent_from_10000": p99_growth(samples, 10000),
            "verify_seconds": report["seconds"] if procedure == "map" else None,
            "verify_peak_rss_mb": report["peak_rss_mb"] if procedure == "map" else None,
        }
        if database and complete:
            summary[procedure].update(resume(database, procedure, args.window, args.port, info))
        print(f"{procedure}: {json.dumps(summary[procedure])}", flush=True)
    with open(out / "summary.json", "w") as f:
        json.dump(summary, f, indent=1)
    name = f"node_scaling_world{args.world}.png" if args.world else "node_scaling.png"
    plot(series, pathlib.Path(args.plot) if args.plot else out / name, args)


def plot(series, path, args):
    """Update time (the longest of the last 100 updates) and the node's
    resident memory against keyframes, one colour per procedure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, mem) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for procedure, samples in series.items():
        points = [(s["keyframes"], s["recent_max_update_seconds"]) for s in samples
                  if s["recent_max_update_seconds"] > 0]
        ax.scatter([p[0] for p in points], [1000 * p[1] for p in points], s=6,
                   label=f"{procedure} procedure")
        mem.plot([s["keyframes"] for s in samples], [s["rss_mb"] for s in samples],
                 label=f"{procedure} procedure")
    ax.set_yscale("log")
    ax.set_ylabel("longest of the last 100 updates (ms)")
    ax.set_title(f"rrr_node: {args.dataset} + {args.outliers} false loops, {args.rate:g} Hz"
                 + (f" played at {args.play:g}x" if args.play != 1 else ""))
    ax.axhline(100, color="grey", linestyle="--", linewidth=0.8)
    ax.legend()
    mem.set_xlabel("keyframes")
    mem.set_ylabel("resident memory (MB)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
