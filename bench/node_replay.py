#!/usr/bin/python3
"""Replays a g2o dataset through rrr_node (rrr to-bag, then replay.launch with
rosbag play at a speed factor) and reports the per-candidate latency, the
largest queue, whether any input was lost, and whether the final accepted
loops equal rrr verify's on the same file.

    bench/node_replay.py [--level 0.150] [--rate 10] [--span-gate]
    bench/node_replay.py --g2o FILE --window 10 [--rate 10]
    bench/node_replay.py --g2o FLEET.g2o --robots "[a, b, c]" --restart-jump 5 --window 10

A file of several odometry chains (robots as GTSAM symbols) plays as a
fleet's bag (doc/node.md, "Replaying a fleet's graph") into the node serving
`--robots`; its decisions are compared with rrr verify's by robot and
keyframe id.
"""
import argparse
import pathlib
import subprocess
import sys
import time

import common
import ros_processes


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--level", default="0.150", help="Bicocca 25b level (default input)")
    parser.add_argument("--g2o", help="another g2o file instead of Bicocca")
    parser.add_argument("--window", type=int, default=50)
    parser.add_argument("--rate", type=float, default=10.0)
    parser.add_argument("--span-gate", action="store_true")
    parser.add_argument("--robots", help="a fleet's robots, e.g. '[a, b, c]'")
    parser.add_argument("--restart-jump", type=float, default=1.0,
                        help="the node's restart_jump (and rrr to-bag's), with --robots")
    parser.add_argument("--port", type=int, default=11521)
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "node_replay"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stamps = []
    if args.g2o:
        g2o = pathlib.Path(args.g2o)
    else:
        data = common.datasets_dir() / "bicocca25b"
        g2o = data / f"B25b_{args.level}.g2o"
        stamps = ["--timestamps", data / "B25b_timestamps.txt"]
    bag = out / "input.bag"
    fleet = ["--restart-jump", str(args.restart_jump)] if args.robots else []
    common.run("to-bag", g2o, *stamps, *fleet, "--output", bag)
    extra = ["--span-gate"] if args.span_gate else []
    report, _, _ = common.verify(g2o, args.window, out, 1, extra)
    expected = {tuple(p) for p in report["accepted"]}
    if args.robots:  # by robot and keyframe id, as the node names them
        names = ros_processes.fleet_names(g2o)
        expected = {(names[i], names[j]) for i, j in expected}

    env = common.ros_env(args.port)
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(args.port), "rrr_slam", "replay.launch", f"bag:={bag}",
         f"rate:={args.rate}", f"cluster_window:={args.window}",
         f"span_gate:={'true' if args.span_gate else 'false'}",
         f"robots:={args.robots or '[]'}", f"restart_jump:={args.restart_jump}"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        start = time.time()
        while True:
            time.sleep(2.0)
            status = common.service(env, "/rrr_node/get_status")
            if status.get("inputs_processed") == str(report["poses"] + report["candidates"]):
                break
            if time.time() - start > 3600 or launch.poll() is not None:
                sys.exit(f"the replay did not complete: {status}")
        status = common.service(env, "/rrr_node/get_status")
        common.service(env, "/rrr_node/finish")
        saved = out / "node_map.g2o"
        common.service(env, "/rrr_node/save_graph", f"{{path: '{saved}', with_candidates: false}}")
        final = common.service(env, "/rrr_node/get_status")
        if args.robots:  # the saved graph's ids are the node's, not the file's
            accepted = {((d["from_robot"], int(d["from_id"])), (d["to_robot"], int(d["to_id"])))
                        for d in ros_processes.decisions(env) if d["state"] == "1"}
        else:
            accepted = {key for key, _ in common.loop_lines(saved)[1]}
    finally:
        launch.terminate()
        launch.wait()
    print(f"input {g2o.name} at {args.rate}x: {report['poses']} odometry messages, "
          f"{report['candidates']} candidates")
    print(f"candidate latency (arrival -> its update published): "
          f"p50 {1000 * float(status['candidate_latency_p50']):.1f} ms, "
          f"p99 {1000 * float(status['candidate_latency_p99']):.1f} ms, "
          f"max {1000 * float(status['candidate_latency_max']):.1f} ms")
    print(f"update time: max {1000 * float(status['max_update_seconds']):.1f} ms; "
          f"largest queue {status['max_queue_length']}; inputs dropped {final['inputs_dropped']}; "
          f"invalid {final['invalid_messages']}")
    print(f"accepted: node {len(accepted)}, rrr verify {len(expected)}, "
          f"same loops: {accepted == expected}")


if __name__ == "__main__":
    main()
