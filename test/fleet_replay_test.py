"""Graphs of several sessions replayed through rrr_node. A fleet: `rrr
simulate --robots 3` makes a world of three robots (GTSAM symbols a, b, c),
robot b's chain is cut in two sessions (a gap in its ids, no odometry
between them), `rrr to-bag` writes it as a bag of the fleet's topics (b's
odometry starts again at zero with its second session), rosbag plays it
through rrr_node serving robots [a, b, c], and after ~finish the node's
decisions are rrr verify's on the file, candidate by candidate, with robot b
in two sessions. One robot: its world cut in two the same way is a bag of
the one robot's topics (`odom`, `loop_closures`) whose odometry restarts at
zero halfway; the node without `robots` keeps the restart a session of its
own that only its loops join, and decides as rrr verify.
"""
import json
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from ros_processes import (  # noqa: E402
    ROSBAG_PLAY, decisions, fleet_names, free_port, ros_env, service, start, stop, wait_for)

BUILD = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
RRR = BUILD / "devel" / "lib" / "rrr_slam" / "rrr"
INDEX_BITS = 56


def symbol(robot, index):
    return (ord(robot) << INDEX_BITS) | index


def robot_of(key):
    return chr(key >> INDEX_BITS)


def cut_session(src, dst, robot, at):
    """Copies g2o `src` to `dst` with `robot`'s chain (None: the one chain of
    plain ids) cut after its pose `at`: the odometry edge from it to the next
    goes, and the robot's later indices count on from one more (a gap: a
    session of its own)."""
    def key_of(index):
        return index if robot is None else symbol(robot, index)

    def moved(key):
        index = key if robot is None else key & ((1 << INDEX_BITS) - 1)
        ours = robot is None or robot_of(key) == robot
        return key_of(index + 1) if ours and index > at else key

    cut = (key_of(at), key_of(at + 1))
    with open(src) as f, open(dst, "w") as out:
        for line in f:
            fields = line.split()
            if fields and fields[0].startswith("VERTEX"):
                fields[1] = str(moved(int(fields[1])))
            elif fields and fields[0].startswith("EDGE"):
                ends = (int(fields[1]), int(fields[2]))
                if ends == cut:
                    continue
                fields[1], fields[2] = str(moved(ends[0])), str(moved(ends[1]))
            out.write(" ".join(fields) + "\n")


def replay(tmp_path, graph, bag, window, node_args, inputs):
    """Plays `bag` at 5x through rrr_node (config/rrr.yaml, cluster_window
    `window`, `node_args`) until it took `inputs` (keyframes, candidates),
    finishes it, and returns its decisions (keyed by the ends' robot and
    keyframe), its status, and rrr verify's report on the graph it saved."""
    port = free_port()
    env = ros_env(BUILD, port, tmp_path)
    log = open(tmp_path / "ros.log", "w")
    master = start(["roscore", "-p", str(port)], env, log)
    node = player = None
    try:
        wait_for(lambda: subprocess.run(["rosparam", "list"], env=env, capture_output=True,
                                        timeout=30).returncode == 0, 60, "the master")
        subprocess.run(["rosparam", "load", ROOT / "config" / "rrr.yaml", "/rrr_node"], env=env,
                       check=True, timeout=60)
        node = start([BUILD / "devel" / "lib" / "rrr_slam" / "rrr_node", "__name:=rrr_node",
                      f"_cluster_window:={window}", *node_args], env, log)
        wait_for(lambda: service(env, "/rrr_node/get_status", timeout=60), 60, "the node")
        player = start(ROSBAG_PLAY + ["-r", "5", str(bag)], env, log)
        last = {}

        def every_input_taken():
            last.update(service(env, "/rrr_node/get_status", timeout=60))
            return (int(last.get("keyframes", 0)) == inputs[0] and
                    int(last.get("loop_closures_received", 0)) == inputs[1] and
                    last.get("queue_length") == "0")
        wait_for(every_input_taken, 240, "every input", state=lambda: (
            f"the node's status {last}; exit codes: node {node.poll()}, player {player.poll()}"))
        finished = service(env, "/rrr_node/finish", timeout=300)
        assert int(finished["pending"]) == 0, finished
        decided = {(d["from_robot"], int(d["from_id"]), d["to_robot"], int(d["to_id"])):
                   int(d["state"]) for d in decisions(env)}
        status = service(env, "/rrr_node/get_status", timeout=60)
        saved = service(env, "/rrr_node/save_graph",
                        f"{{path: '{graph}', with_candidates: false}}", timeout=120)
        assert saved.get("success") == "True", saved
    finally:
        for process in (player, node, master):
            stop(process)
        log.close()
    report = tmp_path / "recorded_report.json"
    subprocess.run([RRR, "verify", graph, "-w", window, "-o", tmp_path / "again.g2o", "-r",
                    report], check=True, capture_output=True)
    return decided, status, json.loads(report.read_text())


def expected_decisions(tmp_path, cut, window, name):
    """rrr verify's decisions on the g2o file `cut`, keyed by `name`'s naming
    of the poses, and its report."""
    report = tmp_path / "report.json"
    subprocess.run([RRR, "verify", cut, "-w", window, "-o", tmp_path / "verified.g2o", "-r",
                    report], check=True, capture_output=True)
    expected_report = json.loads(report.read_text())
    loops = expected_report["decisions"]
    expected = {(*name(d["pair"][0]), *name(d["pair"][1])):
                1 if d["state"] == "accepted" else 2 for d in loops}
    assert 0 < sum(s == 1 for s in expected.values()) < len(expected)
    return expected, expected_report


def test_fleet_bag_replays_as_rrr_verify_decides_the_file(tmp_path):
    world, cut = tmp_path / "world.g2o", tmp_path / "cut.g2o"
    subprocess.run([RRR, "simulate", "--poses", "1500", "--robots", "3", "--false-loops", "30",
                    "--group", "3", "--seed", "3", "-o", world, "-t", tmp_path / "false.txt",
                    "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    cut_session(world, cut, "b", 249)
    bag = tmp_path / "cut.bag"
    made = subprocess.run([RRR, "to-bag", cut, "--rate", "100", "--restart-jump", "5", "-o", bag],
                          check=True, capture_output=True, text=True).stdout
    assert "of 3 robots (4 sessions)" in made, made
    window = "10"
    names = fleet_names(cut)
    expected, report = expected_decisions(tmp_path, cut, window, lambda key: names[key])
    assert len(report["chains"]) == 4, report["chains"]
    decided, status, recorded = replay(
        tmp_path, tmp_path / "recorded.g2o", bag, window,
        ["_robots:=[a, b, c]", "_restart_jump:=5.0"], (1500, len(expected)))
    assert decided == expected
    # Robot b's two sessions stay two chains: no odometry edge joins them.
    assert len(recorded["chains"]) == 4
    assert int(status["sessions"]) == 4, status


def test_one_robots_restart_is_a_session_joined_by_its_loops_alone(tmp_path):
    world, cut = tmp_path / "world.g2o", tmp_path / "cut.g2o"
    subprocess.run([RRR, "simulate", "--poses", "1200", "--false-loops", "30", "--group", "3",
                    "--seed", "5", "-o", world, "-t", tmp_path / "false.txt",
                    "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    cut_session(world, cut, None, 599)
    bag = tmp_path / "cut.bag"
    made = subprocess.run([RRR, "to-bag", cut, "--rate", "100", "-o", bag],
                          check=True, capture_output=True, text=True).stdout
    assert "of 1 robot (2 sessions)" in made, made
    window = "10"
    # The node's keyframe ids count on over the sessions: the file's ids
    # without the gap.
    expected, report = expected_decisions(
        tmp_path, cut, window, lambda key: ("", key if key < 600 else key - 1))
    assert len(report["chains"]) == 2, report["chains"]
    decided, status, recorded = replay(tmp_path, tmp_path / "recorded.g2o", bag, window, [],
                                       (1200, len(expected)))
    assert decided == expected
    assert int(status["sessions"]) == 2, status
    assert int(status["maps"]) == 1, status
    assert int(status["odometry_restarts_joined"]) == 0, status
    assert len(recorded["chains"]) == 2
