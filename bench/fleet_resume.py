#!/usr/bin/python3
"""A fleet's session database ("A fleet's session database", in the git history of BENCHMARKS.md):
launch/fleet.launch with three simulated robots at --rate Hz records its
database while they drive --poses keyframes in all; after ~finish the node
stops, and a node started on the database resumes it. Prints the database's
size, the update times while recording, the time from the second node's
start until it answers ~get_status (the resume: every recorded update run
again), and whether ~finish then gives the same counts.

    bench/fleet_resume.py [--poses 6000] [--false-loops 120] [--rate 50]
"""
import argparse
import pathlib
import signal
import subprocess
import time

import common

ROBOTS = "[a, b, c]"


def print_recording(status):
    print(f"recorded: {status['keyframes']} keyframes, {status['candidates']} candidates, "
          f"{status['updates']} updates; update p50 {float(status['update_seconds_p50']) * 1e3:.1f} ms, "
          f"p99 {float(status['update_seconds_p99']) * 1e3:.1f} ms, "
          f"max {float(status['max_update_seconds']) * 1e3:.0f} ms")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", type=int, default=6000)
    parser.add_argument("--false-loops", type=int, default=120)
    parser.add_argument("--rate", type=float, default=50.0)
    parser.add_argument("--port", type=int, default=11877)
    parser.add_argument("--no-database", action="store_true",
                        help="record nothing: the update times without the database, then stop")
    parser.add_argument("--out", default=str(common.ROOT / "bench" / "out" / "fleet_resume"))
    args = parser.parse_args()
    common.require_rrr()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    database = out / "fleet.db"
    for stale in out.glob("fleet.db*"):
        stale.unlink()
    env = common.ros_env(args.port)
    log = open(out / "ros.log", "w")
    core = subprocess.Popen(["roscore", "-p", str(args.port)], env=env, stdout=log, stderr=subprocess.STDOUT)
    node = None
    try:
        time.sleep(4)
        launch = subprocess.Popen(
            ["roslaunch", "rrr_slam", "fleet.launch", f"database:={'' if args.no_database else database}",
             f"poses:={args.poses}",
             f"false_loops:={args.false_loops}", f"rate:={args.rate}"],
            env=env, stdout=log, stderr=subprocess.STDOUT)
        deadline = time.time() + 30 + 2 * args.poses / args.rate
        while int(common.service(env, "/rrr_node/get_status").get("keyframes", 0)) < args.poses:
            if time.time() > deadline:
                raise SystemExit("the robots did not finish")
            time.sleep(1)
        time.sleep(3)
        first = common.service(env, "/rrr_node/finish")
        recorded = common.service(env, "/rrr_node/get_status")
        launch.send_signal(signal.SIGINT)
        launch.wait(timeout=60)
        if args.no_database:
            print_recording(recorded)
            return

        subprocess.run(["rosparam", "load", common.ROOT / "config" / "rrr.yaml", "/rrr_node"], env=env,
                       check=True)
        start = time.time()
        node = subprocess.Popen(
            [common.ROOT / "_build" / "devel" / "lib" / "rrr_slam" / "rrr_node", "__name:=rrr_node",
             f"_robots:={ROBOTS}", f"_database:={database}", "_restart_jump:=5.0"],
            env=env, stdout=log, stderr=subprocess.STDOUT)
        resumed = {}
        while not resumed:
            resumed = common.service(env, "/rrr_node/get_status", timeout=60)
        seconds = time.time() - start
        second = common.service(env, "/rrr_node/finish")
    finally:
        for process in (node, core):
            if process:
                process.send_signal(signal.SIGINT)
                process.wait(timeout=60)
        log.close()
    print_recording(recorded)
    size = database.stat().st_size + sum(p.stat().st_size for p in out.glob("fleet.db-*"))
    inputs = int(recorded["keyframes"]) + int(recorded["candidates"])
    print(f"database: {size / 1e6:.2f} MB ({size / inputs:.0f} bytes per keyframe or candidate)")
    print(f"resumed: {resumed['resumed_keyframes']} keyframes, {resumed['resumed_candidates']} candidates "
          f"in {seconds:.1f} s (start to ~get_status)")
    print(f"~finish: accepted {first['accepted']} / rejected {first['rejected']} recorded, "
          f"{second['accepted']} / {second['rejected']} resumed: {'same' if first == second else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
