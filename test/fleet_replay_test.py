"""A fleet's g2o file replayed through rrr_node: `rrr simulate --robots 3`
makes a world of three robots (GTSAM symbols a, b, c), robot b's chain is
cut in two sessions (a gap in its ids, no odometry between them), `rrr
to-bag` writes it as a bag of the fleet's topics (b's odometry starts again
at zero with its second session), rosbag plays it through rrr_node serving
robots [a, b, c], and after ~finish the node's decisions are rrr verify's
on the file, candidate by candidate, with robot b in two sessions.
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
    """Copies g2o `src` to `dst` with `robot`'s chain cut after its pose
    `at`: the odometry edge from it to the next goes, and the robot's later
    indices count on from one more (a gap: a session of its own)."""
    def moved(key):
        index = key & ((1 << INDEX_BITS) - 1)
        return symbol(robot, index + 1) if robot_of(key) == robot and index > at else key

    cut = (symbol(robot, at), symbol(robot, at + 1))
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
    report = tmp_path / "report.json"
    window = "10"
    subprocess.run([RRR, "verify", cut, "-w", window, "-o", tmp_path / "verified.g2o", "-r",
                    report], check=True, capture_output=True)
    expected_report = json.loads(report.read_text())
    assert len(expected_report["chains"]) == 4, expected_report["chains"]

    # The file's poses as the node names them.
    name = fleet_names(cut)
    loops = expected_report["decisions"]
    expected = {(*name[d["pair"][0]], *name[d["pair"][1]]):
                1 if d["state"] == "accepted" else 2 for d in loops}
    assert 0 < sum(s == 1 for s in expected.values()) < len(expected)

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
                      "_robots:=[a, b, c]", "_restart_jump:=5.0",
                      f"_cluster_window:={window}"], env, log)
        wait_for(lambda: service(env, "/rrr_node/get_status", timeout=60), 60, "the node")
        player = start(ROSBAG_PLAY + ["-r", "5", str(bag)], env, log)
        last = {}

        def every_input_taken():
            last.update(service(env, "/rrr_node/get_status", timeout=60))
            return (int(last.get("keyframes", 0)) == 1500 and
                    int(last.get("loop_closures_received", 0)) == len(loops) and
                    last.get("queue_length") == "0")
        wait_for(every_input_taken, 240, "every input", state=lambda: (
            f"the node's status {last}; exit codes: node {node.poll()}, player {player.poll()}"))
        finished = service(env, "/rrr_node/finish", timeout=300)
        assert int(finished["pending"]) == 0, finished
        decided = {(d["from_robot"], int(d["from_id"]), d["to_robot"], int(d["to_id"])):
                   int(d["state"]) for d in decisions(env)}
        graph = tmp_path / "recorded.g2o"
        saved = service(env, "/rrr_node/save_graph",
                        f"{{path: '{graph}', with_candidates: false}}", timeout=120)
        assert saved.get("success") == "True", saved
    finally:
        for process in (player, node, master):
            stop(process)
        log.close()
    assert decided == expected
    # Robot b's two sessions stay two chains: no odometry edge joins them.
    recorded = tmp_path / "recorded_report.json"
    subprocess.run([RRR, "verify", graph, "-w", window, "-o", tmp_path / "again.g2o", "-r",
                    recorded], check=True, capture_output=True)
    assert len(json.loads(recorded.read_text())["chains"]) == 4
