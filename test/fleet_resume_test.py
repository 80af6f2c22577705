"""A fleet's session survives kill -9: rrr_node serving three simulated
robots records its fleet database, is killed with SIGKILL in the middle,
and started again on the database (the robots gone with the first run's
launch). It resumes every committed keyframe and candidate; ~finish then
decides as rrr verify decides the graph it recorded (with a candidate by
stamp added after the restart); and a node started on the finished database
decides exactly as the finished one.
"""
import json
import os
import pathlib
import signal
import sqlite3
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from ros_processes import (  # noqa: E402
    decisions, free_port, node_pid, ros_env, service, stop, wait_for)

BUILD = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
LIB = BUILD / "devel" / "lib" / "rrr_slam"
ROBOTS = "[a, b, c]"


def as_time(ns):
    return f"{{secs: {ns // 10**9}, nsecs: {ns % 10**9}}}"


def status(env):
    return service(env, "/rrr_node/get_status", timeout=60)


def node_alone(env, database, log):
    """rrr_node for the fleet on `database`, without robots, with the
    parameters of launch/fleet.launch (the robots on the command line, as
    rosrun's users give them)."""
    subprocess.run(["rosparam", "load", ROOT / "config" / "rrr.yaml", "/rrr_node"], env=env,
                   check=True, timeout=60)
    return subprocess.Popen(  # the robots as README's two-machine example gives them
        [LIB / "rrr_node", "__name:=rrr_node", f"_robots:={ROBOTS}", f"_database:={database}",
         "_restart_jump:=5.0"],
        env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def test_killed_fleet_node_resumes_and_decides_as_rrr_verify(tmp_path):
    port = free_port()
    env = ros_env(BUILD, port, tmp_path)
    log = open(tmp_path / "ros.log", "w")
    master = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=log,
                              stderr=subprocess.STDOUT, start_new_session=True)
    database = tmp_path / "fleet.db"
    launch = node = None
    try:
        launch = subprocess.Popen(
            ["roslaunch", "--wait", "rrr_slam", "fleet.launch", f"database:={database}",
             f"robots:={ROBOTS}", "poses:=1500", "false_loops:=30", "seed:=2", "rate:=50"],
            env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        pid = node_pid(launch)
        # Kill it once the robots are past their first loops between them.
        running = wait_for(lambda: (lambda s: s if int(s.get("keyframes", 0)) >= 700 else None)(
            status(env)), 120, "half of the keyframes")
        os.kill(pid, signal.SIGKILL)
        launch.wait(timeout=60)  # the node was required: the robots went with it
        assert int(running["candidates"]) > 50, running

        node = node_alone(env, database, log)
        resumed = wait_for(lambda: status(env), 120, "the restarted node")
        assert resumed["database"] == str(database), resumed
        keyframes = int(resumed["resumed_keyframes"])
        # Every committed keyframe (those of the update being run when it
        # died, at most, are lost) and every committed candidate.
        assert int(running["keyframes"]) - 60 <= keyframes <= 1500, (running, resumed)
        assert int(resumed["resumed_candidates"]) >= int(running["candidates"]) - 20, resumed
        # A candidate by stamp between two recorded keyframes of robots a
        # and b (their stamps from the database) is taken at once.
        with sqlite3.connect(database) as db:
            stamps = [db.execute("SELECT max(stamp_ns) FROM inputs WHERE kind < 2 AND robot = ?",
                                 (robot,)).fetchone()[0] for robot in (0, 1)]
        loop = ("{from_robot: a, to_robot: b, loop: {header: {frame_id: base_link}, reference: 1, "
                f"from_stamp: {as_time(stamps[0])}, to_stamp: {as_time(stamps[1])}, "
                "relative_pose: {pose: {position: {x: 1.0, y: 0.5, z: 0.0}, "
                "orientation: {x: 0.0, y: 0.0, z: 0.0, w: 1.0}}, "
                "covariance: [0.01, 0, 0, 0, 0, 0, 0, 0.01, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, "
                "0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0.001]}, confidence: -1}}")
        candidates = int(resumed["candidates"])
        subprocess.run(["rostopic", "pub", "-1", "/fleet_loop_closures",
                        "rrr_slam/FleetLoopClosure", loop], env=env, check=True,
                       capture_output=True, timeout=60)
        wait_for(lambda: int(status(env).get("candidates", 0)) == candidates + 1, 60,
                 "the candidate by stamp")
        assert status(env)["waiting_by_stamp"] == "0"
        finished = service(env, "/rrr_node/finish", timeout=300)
        assert int(finished.get("accepted", 0)) > 0, finished
        graph = tmp_path / "recorded.g2o"
        saved = service(env, "/rrr_node/save_graph",
                        f"{{path: '{graph}', with_candidates: true}}", timeout=120)
        assert saved.get("success") == "True", saved
        first = [(d["state"], d["test"]) for d in decisions(env)]
        stop(node)

        # rrr verify on the graph the resumed node recorded: the same loops.
        report = tmp_path / "report.json"
        window = subprocess.run(["rosparam", "get", "/rrr_node/cluster_window"], env=env,
                                check=True, capture_output=True, text=True).stdout.strip()
        subprocess.run([LIB / "rrr", "verify", graph, "-w", window, "-o", tmp_path / "verified.g2o", "-r",
                        report], check=True, capture_output=True)
        accepted = json.loads(report.read_text())["accepted"]
        assert len(accepted) == int(finished["accepted"]), (finished, len(accepted))

        # A node started on the finished database decides as the finished one.
        node = node_alone(env, database, log)
        again = wait_for(lambda: status(env), 300, "the node started again")
        assert int(again["resumed_keyframes"]) == keyframes, again
        assert [(d["state"], d["test"]) for d in decisions(env)] == first
    finally:
        for process in (node, launch, master):
            stop(process)
        log.close()
