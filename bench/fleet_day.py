#!/usr/bin/python3
"""A day-long fleet (BENCHMARKS.md, "The node: a fleet"): `rrr simulate
--robots 4` (a grid world driven by 4 robots side by side, --poses keyframes
in all, false loops in groups of 4), `rrr to-bag --rate` (each robot's
odometry at RATE Hz), played at --play times real time into one rrr_node
serving robots [a, b, c, d] with a session database. At --kill-at of the
keyframes the node is killed with SIGKILL and the player stopped; a node
started on the database is timed until ~get_status answers (the resume),
the bag plays on from the robots' last recorded keyframe, and ~finish.
Prints the update times of both runs (p50, p99, longest, from ~get_status),
the node's peak memory, the resume time, whether an input was lost, and
whether the node's final decisions (~save_graph with every candidate) equal
`rrr verify`'s on the graph it saved.

    bench/fleet_day.py [--poses 100000] [--false-loops 2000] [--rate 50]
                       [--play 4] [--kill-at 0.75] [--out bench/out/fleet_day]
"""
import argparse
import json
import os
import pathlib
import signal
import sqlite3
import subprocess
import sys
import time

import common

sys.path.insert(0, str(common.ROOT / "scripts"))
from ros_processes import (ROSBAG_PLAY, fleet_names, free_port, resident_mb, ros_env, service,  # noqa: E402
                           start, stop, wait_for)

ROBOTS = "[a, b, c, d]"
NODE = common.ROOT / "_build" / "devel" / "lib" / "rrr_slam" / "rrr_node"


def start_node(env, log, database):
    subprocess.run(["rosparam", "load", common.ROOT / "config" / "rrr.yaml", "/rrr_node"], env=env,
                   check=True, timeout=60)
    return start([NODE, "__name:=rrr_node", f"_robots:={ROBOTS}", f"_database:={database}",
                  "_restart_jump:=5.0"], env, log)


def updates(status):
    return {"updates": int(status["updates"]),
            "p50_ms": float(status["update_seconds_p50"]) * 1e3,
            "p99_ms": float(status["update_seconds_p99"]) * 1e3,
            "max_ms": float(status["max_update_seconds"]) * 1e3}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", type=int, default=100000)
    parser.add_argument("--false-loops", type=int, default=2000)
    parser.add_argument("--rate", type=float, default=50.0)
    parser.add_argument("--play", type=float, default=4.0)
    parser.add_argument("--kill-at", type=float, default=0.75)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "fleet_day"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    world, bag, database = out / "world.g2o", out / "world.bag", out / "fleet.db"
    for stale in out.glob("fleet.db*"):
        stale.unlink()
    common.run("simulate", "--robots", 4, "--poses", args.poses, "--false-loops", args.false_loops,
               "--group", 4, "--seed", args.seed, "--output", world, "--truth", out / "false.txt",
               "--ground-truth", out / "truth.g2o")
    common.run("to-bag", world, "--rate", args.rate, "--restart-jump", 5, "--output", bag)
    per_robot = args.poses // 4

    env = ros_env(common.ROOT / "_build", free_port(), out)
    log = open(out / "ros.log", "w")
    master = start(["roscore", "-p", env["ROS_MASTER_URI"].rsplit(":", 1)[1]], env, log)
    node = player = None
    peak = 0.0
    try:
        wait_for(lambda: subprocess.run(["rosparam", "list"], env=env, capture_output=True,
                                        timeout=30).returncode == 0, 60, "the master")
        node = start_node(env, log, database)
        wait_for(lambda: service(env, "/rrr_node/get_status", timeout=60), 60, "the node")
        player = start(ROSBAG_PLAY + ["-r", str(args.play), str(bag)], env, log)
        killed_at = int(args.kill_at * args.poses)
        last = {}

        def reached():
            last.update(service(env, "/rrr_node/get_status", timeout=60))
            return int(last.get("keyframes", 0)) >= killed_at
        wait_for(reached, 4 * args.poses / args.rate / args.play + 600, "the kill point", period=1.0)
        first = updates(last)
        peak = max(peak, resident_mb(node.pid)[1])
        os.kill(node.pid, signal.SIGKILL)
        stop(player)
        node.wait(timeout=60)

        began = time.time()
        node = start_node(env, log, database)
        resumed = wait_for(lambda: service(env, "/rrr_node/get_status", timeout=120), 600, "the resume",
                           period=0.1)
        resume_seconds = time.time() - began
        # Each robot's keyframe k is at 1 + k / rate: play on from a second
        # before the first robot's last recorded keyframe (what the node has
        # is not taken again: keyframes by stamp, candidates as duplicates),
        # so that a candidate whose topic lagged the odometry comes again.
        with sqlite3.connect(f"file:{database}?mode=ro", uri=True) as db:
            kept = min(n for (n,) in db.execute(
                "SELECT max(number) FROM inputs WHERE kind IN (0, 1) GROUP BY robot"))
        player = start(ROSBAG_PLAY + ["-r", str(args.play), "-s", f"{max(kept - args.rate, 0) / args.rate:.3f}",
                                      str(bag)], env, log)
        final, longest = {}, []  # (keyframes, longest update so far) at each sample

        def everything():
            final.update(service(env, "/rrr_node/get_status", timeout=60))
            if final:
                longest.append((int(final["keyframes"]), float(final["max_update_seconds"]) * 1e3))
            return int(final.get("keyframes", 0)) == 4 * per_robot and final.get("queue_length") == "0"
        wait_for(everything, 4 * args.poses / args.rate / args.play + 600, "every keyframe", period=1.0)
        stop(player)
        player = None
        peak = max(peak, resident_mb(node.pid)[1])
        second = updates(final)
        service(env, "/rrr_node/finish", timeout=1200)
        saved = out / "saved.g2o"
        service(env, "/rrr_node/save_graph", f"{{path: '{saved}', with_candidates: true}}", timeout=600)
        final = service(env, "/rrr_node/get_status", timeout=60)
    finally:
        for process in (player, node, master):
            stop(process)
        log.close()

    # The node's decisions (~save_graph's DECISION lines name robot:id) and
    # rrr verify's on the world the bag holds (every input arrived), named
    # alike.
    node_accepted = set()
    for line in open(saved):
        fields = line.split()
        if line.startswith("# DECISION") and fields[4] == "accepted":
            node_accepted.add(frozenset(tuple(f.split(":")) for f in fields[2:4]))
    (out / "verify").mkdir(exist_ok=True)
    report, verify_seconds, _ = common.verify(world, 10, out / "verify")
    names = fleet_names(world)
    verify_accepted = {frozenset((names[i][0], str(names[i][1])) for i in d["pair"])
                       for d in report["decisions"] if d["state"] == "accepted"}
    size = sum(p.stat().st_size for p in out.glob("fleet.db*"))
    summary = {
        "keyframes": int(final["keyframes"]), "candidates": int(final["candidates"]),
        "before_kill": first, "after_resume": second,
        "longest_update_reached_at_keyframes": next((k for k, m in longest if m >= second["max_ms"]), None),
        "resume_seconds": resume_seconds, "resumed_keyframes": int(resumed["resumed_keyframes"]),
        "resumed_from_update": int(resumed["resumed_from_update"]),
        "inputs_dropped": int(final["inputs_dropped"]), "invalid_messages": int(final["invalid_messages"]),
        "inputs_already_recorded": int(final["inputs_already_recorded"]),
        "skipped_duplicates": int(final["skipped_duplicates"]),
        "peak_rss_mb": peak, "database_mb": size / 1e6,
        "accepted_node": len(node_accepted), "accepted_verify": len(verify_accepted),
        "same_decisions": node_accepted == verify_accepted, "verify_seconds": verify_seconds,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
