"""A session survives kill -9: rrr_node records its session database while a
bag plays, is killed with SIGKILL in the middle, restarts on the same
database, and the rest of the bag is played from its last recorded keyframe.
The final accepted loops equal rrr verify's on the same graph, only the
inputs of the unfinished update come again, and rrr export and rrr verify
read the database. With checkpoints every 200 keyframes, and without any.
Runs on a world the package generates, and on Bicocca 25b (0.150) when the
datasets are there (RRR_DATASETS, default ../shared/datasets).
"""
import json
import os
import pathlib
import signal
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from ros_processes import (ROSBAG_PLAY, free_port, node_pid, ros_env, service, start,  # noqa: E402
                           stop, wait_for)
from world_files import generated_and_bicocca, loop_pairs  # noqa: E402

BUILD = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
RRR = BUILD / "devel" / "lib" / "rrr_slam" / "rrr"
RATE = 100.0  # odometry messages per second in the bag


def status(env):
    return service(env, "/rrr_node/get_status", timeout=60)


def start_master(tmp_path):
    """A master on a free port: (the build's environment for it, the log
    file tmp_path/ros.log that it and the nodes write, its process)."""
    port = free_port()
    env = ros_env(BUILD, port, tmp_path)
    log = open(tmp_path / "ros.log", "w")
    return env, log, start(["roscore", "-p", port], env, log)


def play(env, log, bag, *options):
    """Starts rosbag play of `bag` with `options` (kept alive past the bag's
    end: stop it with stop())."""
    return start([*ROSBAG_PLAY, *options, bag], env, log)


def played(player, tmp_path):
    """What a wait on `player` reports when it times out."""
    return f"the player's exit code {player.poll()}; {(tmp_path / 'ros.log').read_text()[-3000:]}"


def start_node(env, database, window, log, checkpoint_keyframes=1000):
    return start(["roslaunch", "--wait", "rrr_slam", "rrr.launch", f"database:={database}",
                  f"cluster_window:={window}", f"checkpoint_keyframes:={checkpoint_keyframes}",
                  "output:=log"], env, log)


@pytest.mark.parametrize("checkpoint_keyframes", [0, 200])
@pytest.mark.parametrize("source", generated_and_bicocca())
def test_killed_node_resumes_with_the_decisions_of_an_uninterrupted_run(source, checkpoint_keyframes,
                                                                        tmp_path):
    graph = tmp_path / "world.g2o"
    window = 10
    if source == "simulated":
        subprocess.run([RRR, "simulate", "--poses", "2000", "--false-loops", "60", "--group", "3",
                        "--seed", "2", "-o", graph, "-t", tmp_path / "false.txt",
                        "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    else:
        window = 50
        graph.write_text(pathlib.Path(source).read_text())
    subprocess.run([RRR, "verify", graph, "-w", str(window), "-o", tmp_path / "verified.g2o",
                    "-r", tmp_path / "report.json"], check=True, capture_output=True)
    expected = {tuple(p) for p in json.loads((tmp_path / "report.json").read_text())["accepted"]}
    bag = tmp_path / "world.bag"
    subprocess.run([RRR, "to-bag", graph, "--rate", str(RATE), "-o", bag], check=True,
                   capture_output=True)
    poses = sum(1 for line in graph.read_text().splitlines() if line.startswith("VERTEX"))

    env, log, master = start_master(tmp_path)
    database = tmp_path / "session.db"
    launch = player = None
    try:
        launch = start_node(env, database, window, log, checkpoint_keyframes)
        pid = node_pid(launch)
        wait_for(lambda: status(env), 60, "~get_status")
        player = play(env, log, bag)
        # Kill it in the middle of the replay, then stop the bag.
        wait_for(lambda: int(status(env).get("keyframes", 0)) >= poses // 2, 120,
                 "half of the keyframes")
        os.kill(pid, signal.SIGKILL)
        os.killpg(player.pid, signal.SIGINT)
        player.wait(timeout=30)
        launch.wait(timeout=30)

        launch = start_node(env, database, window, log, checkpoint_keyframes)
        node_pid(launch)
        resumed = wait_for(lambda: status(env), 120, "the restarted node")
        keyframes = int(resumed["resumed_keyframes"])
        assert poses // 4 < keyframes < poses, resumed
        # With checkpoints every 200 keyframes, the resume restored one (of
        # the map procedure, the default) and ran only the updates after it.
        restored_from = int(resumed["resumed_from_update"])
        assert (restored_from > 0) == (checkpoint_keyframes > 0), resumed
        assert resumed["database"] == str(database)
        # Play on from the last recorded keyframe (pose k is at 1 + k / RATE).
        start = (keyframes - 1) / RATE - 0.5 / RATE
        player = play(env, log, bag, "-s", f"{start:.6f}")
        final = wait_for(lambda: (lambda s: s if s.get("keyframes") == str(poses)
                                  and s.get("queue_length") == "0" else None)(status(env)),
                         420, "every keyframe", state=lambda: played(player, tmp_path))
        stop(player)
        subprocess.run(["rosservice", "call", "/rrr_node/finish"], env=env, check=True,
                       capture_output=True, timeout=300)
        # Only the last recorded keyframe and the candidates at its stamp come again.
        assert int(final["inputs_already_recorded"]) <= 1, final
        assert int(final["inputs_dropped"]) == 0 and int(final["invalid_messages"]) == 0, final
    finally:
        for process in (player, launch, master):
            stop(process)
        log.close()

    exported = tmp_path / "exported.g2o"
    subprocess.run([RRR, "export", database, "-o", exported], check=True, capture_output=True)
    assert loop_pairs(exported) == expected
    everything = tmp_path / "everything.g2o"
    subprocess.run([RRR, "export", database, "--with-rejected", "-o", everything], check=True,
                   capture_output=True)
    assert loop_pairs(everything) == loop_pairs(graph)
    # rrr verify reads the database as it reads a g2o file.
    subprocess.run([RRR, "verify", database, "-w", str(window), "-o", tmp_path / "again.g2o",
                    "-r", tmp_path / "again.json"], check=True, capture_output=True)
    again = {tuple(p) for p in json.loads((tmp_path / "again.json").read_text())["accepted"]}
    assert again == expected


def test_a_candidate_waiting_by_stamp_survives_kill(tmp_path):
    """A candidate named by stamp waits for a keyframe that does not exist
    yet when the node is killed; the restarted node holds it again, and it
    becomes a candidate when the keyframe comes."""
    graph = tmp_path / "world.g2o"
    subprocess.run([RRR, "simulate", "--poses", "600", "--false-loops", "10", "--seed", "3",
                    "-o", graph, "-t", tmp_path / "false.txt",
                    "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    bag = tmp_path / "world.bag"
    subprocess.run([RRR, "to-bag", graph, "--rate", str(RATE), "-o", bag], check=True,
                   capture_output=True)
    pairs = loop_pairs(graph)
    later, earlier = 450, 5  # a pair the world has no loop for
    while (later, earlier) in pairs:
        later += 1
    stamp = lambda pose: 1 + pose / RATE  # noqa: E731 (as rrr to-bag writes it)
    as_time = lambda t: f"{{secs: {int(t)}, nsecs: {round((t - int(t)) * 1e9)}}}"  # noqa: E731
    loop = ("{header: {frame_id: base_link}, reference: 1, "
            f"from_stamp: {as_time(stamp(later))}, to_stamp: {as_time(stamp(earlier))}, "
            "relative_pose: {pose: {position: {x: 1.0, y: 0.5, z: 0.0}, "
            "orientation: {x: 0.0, y: 0.0, z: 0.0, w: 1.0}}, "
            "covariance: [0.01, 0, 0, 0, 0, 0, 0, 0.01, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, "
            "0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0.001]}, confidence: -1}")

    env, log, master = start_master(tmp_path)
    database = tmp_path / "session.db"
    launch = player = None
    try:
        launch = start_node(env, database, 10, log)
        pid = node_pid(launch)
        wait_for(lambda: status(env), 60, "~get_status")
        # The first 300 poses, then the candidate naming pose `later`.
        player = play(env, log, bag, "-u", f"{300 / RATE:.3f}")
        wait_for(lambda: int(status(env).get("keyframes", 0)) >= 250, 180, "the first keyframes",
                 state=lambda: played(player, tmp_path))
        stop(player)
        before = int(status(env)["updates"])
        subprocess.run(["rostopic", "pub", "-1", "/loop_closures", "rrr_slam/LoopClosure", loop],
                       env=env, check=True, capture_output=True, timeout=60)
        # Recorded: an update after it took it in has committed.
        wait_for(lambda: (lambda s: s.get("waiting_by_stamp") == "1" and
                          int(s.get("updates", 0)) > before and
                          s.get("queue_length") == "0")(status(env)), 60,
                 "the candidate to wait by stamp")
        os.kill(pid, signal.SIGKILL)
        launch.wait(timeout=30)

        launch = start_node(env, database, 10, log)
        node_pid(launch)
        resumed = wait_for(lambda: status(env), 120, "the restarted node")
        assert resumed["resumed_waiting_by_stamp"] == "1", resumed
        assert resumed["waiting_by_stamp"] == "1", resumed
        keyframes = int(resumed["resumed_keyframes"])
        start = (keyframes - 1) / RATE - 0.5 / RATE
        player = play(env, log, bag, "-s", f"{start:.6f}")
        final = wait_for(lambda: (lambda s: s if s.get("keyframes") == "600"
                                  and s.get("queue_length") == "0" else None)(status(env)),
                         420, "every keyframe", state=lambda: played(player, tmp_path))
        stop(player)
        assert final["waiting_by_stamp"] == "0", final
        assert int(final["skipped_unknown_poses"]) == 0, final
        assert int(final["invalid_messages"]) == 0, final
    finally:
        for process in (player, launch, master):
            stop(process)
        log.close()

    everything = tmp_path / "everything.g2o"
    subprocess.run([RRR, "export", database, "--with-rejected", "-o", everything], check=True,
                   capture_output=True)
    assert loop_pairs(everything) == pairs | {(later, earlier)}
