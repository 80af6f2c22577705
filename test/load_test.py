"""rrr_node under load, through a real rosmaster.

A flood: 100,000 loop candidates as fast as a publisher can send them, mixed
from every kind a misbehaving front-end sends, beside 100 Hz odometry. The
node's resident memory stays under MEMORY_BOUND_MB and ~get_status accounts
for every message: received = processed + refused, and every candidate is a
candidate, waiting, invalid, skipped or refused under its reason. Its valid
candidates are a junk stream (no revisit on a straight road): none is
accepted.

A fast replay: a bag played at 100 times its speed loses no input and gives
the decisions of rrr verify; on a generated world always, and on Bicocca 25b
(0.150) when the datasets are there (RRR_DATASETS, default
../shared/datasets). A node stalled while the bag ends loses nothing either.
"""
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
import ros_processes  # noqa: E402
from world_files import generated_and_bicocca, loop_pairs  # noqa: E402

BUILD = pathlib.Path(os.environ.get("RRR_BUILD_DIR", ROOT / "_build"))
RRR = BUILD / "devel" / "lib" / "rrr_slam" / "rrr"
MEMORY_BOUND_MB = 200.0  # doc/node.md, "Resuming a session" (limits)
FLOOD_CANDIDATES = 100000


class Ros:
    """A rosmaster and rrr_node (rrr.launch with `arguments`) in `tmp_path`."""

    def __init__(self, tmp_path, *arguments):
        port = ros_processes.free_port()
        self.env = ros_processes.ros_env(BUILD, port, tmp_path)
        self.log = open(tmp_path / "ros.log", "w")
        self.master = ros_processes.start(["roscore", "-p", port], self.env, self.log)
        self.launch = ros_processes.start(["roslaunch", "--wait", "rrr_slam", "rrr.launch",
                                           "output:=log", *arguments], self.env, self.log)
        self.pid = ros_processes.node_pid(self.launch)
        ros_processes.wait_for(self.status, 60, "~get_status")

    def status(self):
        return ros_processes.service(self.env, "/rrr_node/get_status", timeout=60)

    def close(self):
        ros_processes.stop(self.launch)
        ros_processes.stop(self.master)
        self.log.close()


@pytest.fixture
def ros_factory(tmp_path):
    started = []

    def make(*arguments):
        started.append(Ros(tmp_path, *arguments))
        return started[-1]
    yield make
    for ros in started:
        ros.close()


def config_with(tmp_path, name, value):
    """The launch argument of a copy of config/rrr.yaml with `name` set to
    `value`."""
    config = tmp_path / "rrr.yaml"
    config.write_text(re.sub(rf"(?m)^{name}: .*$", f"{name}: {value}",
                             (ROOT / "config" / "rrr.yaml").read_text()))
    return f"config:={config}"


def number(fields, *names):
    return sum(int(fields[name]) for name in names)


def received(fields):
    """The inputs the node received (~get_status fields), if it has taken
    every one of them in (processed or refused), else None."""
    if not fields:
        return None
    got = number(fields, "odometry_received", "loop_closures_received")
    return got if got == number(fields, "inputs_processed", "inputs_refused") else None


def flood(ros):
    """Runs test/flood_publisher.py against `ros`'s node until the node has
    taken in everything; returns (what was sent, final status, peak MB)."""
    published = subprocess.run([sys.executable, ROOT / "test" / "flood_publisher.py",
                                str(FLOOD_CANDIDATES), "100"], env=ros.env,
                               capture_output=True, text=True, timeout=1200)
    assert published.returncode == 0, published.stderr
    sent = json.loads(published.stdout.splitlines()[-1])
    peak = 0.0

    def drained():
        nonlocal peak
        peak = max(peak, ros_processes.resident_mb(ros.pid)[1])
        s = ros.status()
        return s if s and s["queue_length"] == "0" and received(s) is not None else None
    final = ros_processes.wait_for(drained, 900, "the node to take in the flood", period=2)
    peak = max(peak, ros_processes.resident_mb(ros.pid)[1])
    print(f"flood: {sent}, peak resident memory {peak:.1f} MB, status {final}")
    # Nothing lost between the publisher and the node, or inside it.
    assert int(final["odometry_received"]) == sent["odometry"]
    assert int(final["loop_closures_received"]) == sent["loop_closures"]
    assert int(final["inputs_dropped"]) == 0
    return sent, final, peak


def test_a_flood_is_bounded_in_memory_and_every_message_is_accounted_for(ros_factory):
    ros = ros_factory()
    sent, final, peak = flood(ros)
    assert peak <= MEMORY_BOUND_MB
    # With the default queue limit nothing is refused at the queue, and every
    # candidate message is under one heading: a candidate (judged or waiting
    # by id), waiting by stamp, invalid, skipped or refused by a bound.
    assert int(final["inputs_refused"]) == 0
    assert int(final["keyframes"]) == sent["odometry"]
    assert number(final, "candidates", "waiting_by_stamp", "invalid_messages",
                  "skipped_self_loops", "skipped_consecutive_poses", "skipped_duplicates",
                  "skipped_unknown_poses", "refused_too_far_ahead",
                  "refused_waiting_full") == sent["loop_closures"]
    # Each kind of the flood was seen and counted under its reason.
    for name in ("invalid_messages", "skipped_self_loops", "skipped_consecutive_poses",
                 "refused_too_far_ahead", "refused_waiting_full", "waiting_by_stamp"):
        assert int(final[name]) > 0, name
    assert int(final["waiting_by_stamp"]) <= 10000  # max_waiting
    # The flood's valid candidates are a junk stream: pairs of keyframes at
    # least 10 (1 m) apart on a straight road, each measured as the
    # identity. None may be accepted, once every cluster is judged.
    ros_processes.service(ros.env, "/rrr_node/finish")
    judged = ros.status()
    # Pending now: only those that wait for a keyframe by id.
    assert int(judged["pending"]) == int(judged["waiting"]) - int(judged["waiting_by_stamp"]), judged
    assert int(judged["rejected"]) > 0, judged
    assert int(judged["accepted"]) == 0, judged


def test_a_flood_past_the_queue_limit_is_refused_and_counted(ros_factory, tmp_path):
    # A queue of one input: every message that arrives while one waits for
    # the worker is refused, and a flood at the publisher's full speed (tens
    # of thousands a second) outruns any worker, which also publishes and
    # answers between batches.
    sent, final, peak = flood(ros_factory(config_with(tmp_path, "max_queue_length", 1)))
    assert peak <= MEMORY_BOUND_MB
    # The queue reached its limit and never passed it, and what came beyond
    # it was refused and counted.
    assert int(final["max_queue_length"]) == 1, final
    assert int(final["inputs_refused"]) > 0, final
    # received = processed + refused (checked when drained) and each kept
    # keyframe or candidate is one that was not refused.
    assert int(final["keyframes"]) <= sent["odometry"]


def report_pairs(report):
    return {tuple(p) for p in json.loads(pathlib.Path(report).read_text())["accepted"]}


def bag_of(graph, tmp_path):
    """rrr to-bag of `graph` at 100 poses a second: (the bag, its odometry
    messages, its loop candidates)."""
    bag = tmp_path / "world.bag"
    subprocess.run([RRR, "to-bag", graph, "--rate", "100", "-o", bag], check=True,
                   capture_output=True)
    lines = pathlib.Path(graph).read_text().splitlines()
    poses = sum(1 for line in lines if line.startswith("VERTEX"))
    return bag, poses, sum(1 for line in lines if line.startswith("EDGE")) - (poses - 1)


def play(ros, bag, messages, rate, while_playing=None):
    """Plays `bag` at `rate` times its speed into `ros`'s node, calls
    `while_playing(player)` if given, and returns once the node has received
    and taken in all `messages` of the bag (AssertionError after 300 s)."""
    player = ros_processes.start([*ros_processes.ROSBAG_PLAY, "-r", str(rate), bag], ros.env,
                                 ros.log)
    last = {}

    def every_input_taken():
        last.update(ros.status())
        return last and received(last) == messages
    try:
        if while_playing:
            while_playing(player)
        ros_processes.wait_for(every_input_taken, 300, "every input of the bag", state=lambda: (
            f"the node's status {last}; the player's exit code {player.poll()}"))
    finally:
        ros_processes.stop(player)


@pytest.mark.parametrize("source", generated_and_bicocca())
def test_a_replay_at_100_times_its_speed_loses_nothing(source, ros_factory, tmp_path):
    graph, window = tmp_path / "world.g2o", 10
    if source == "simulated":
        subprocess.run([RRR, "simulate", "--poses", "3000", "--false-loops", "60", "--group", "3",
                        "--seed", "5", "-o", graph, "-t", tmp_path / "false.txt",
                        "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    else:
        graph, window = source, 50
    subprocess.run([RRR, "verify", graph, "-w", str(window), "-o", tmp_path / "verified.g2o",
                    "-r", tmp_path / "report.json"], check=True, capture_output=True)
    bag, poses, candidates = bag_of(graph, tmp_path)

    # At 100x the loop topic can lag the odometry by more than a window
    # (hundreds of keyframes a second): the decisions wait for it.
    ros = ros_factory(f"cluster_window:={window}", "decision_delay:=2000")
    play(ros, bag, poses + candidates, 100)
    saved = tmp_path / "node.g2o"
    ros_processes.service(ros.env, "/rrr_node/finish")
    ros_processes.service(ros.env, "/rrr_node/save_graph",
                          f"{{path: '{saved}', with_candidates: false}}")
    final = ros.status()
    print(f"replay at 100x: {poses} keyframes, {candidates} candidates, status {final}")
    assert number(final, "inputs_refused", "inputs_dropped", "invalid_messages") == 0
    assert int(final["keyframes"]) == poses
    assert int(final["candidates"]) == candidates
    # The node's accepted graph holds exactly rrr verify's accepted loops.
    assert loop_pairs(saved) == report_pairs(tmp_path / "report.json")


def test_a_node_stalled_past_the_bags_end_loses_nothing(ros_factory, tmp_path):
    # The node's process stops (SIGSTOP, as a loaded machine can stall it)
    # soon after the bag begins and goes on well after the player has sent
    # the last message. What the node had not read waits in the sockets and
    # in the player, kept alive, and comes when it goes on: more messages
    # than the sockets hold, so a player that exits would lose the rest.
    # The loop topic may then be read far ahead of the odometry, past the
    # bound on how far ahead a candidate may name a keyframe: lifted here.
    graph = tmp_path / "world.g2o"
    subprocess.run([RRR, "simulate", "--poses", "15000", "--false-loops", "30", "--seed", "6",
                    "-o", graph, "-t", tmp_path / "false.txt",
                    "--ground-truth", tmp_path / "truth.g2o"], check=True, capture_output=True)
    bag, poses, candidates = bag_of(graph, tmp_path)
    ros = ros_factory(config_with(tmp_path, "max_future_keyframes", 100000))

    def stall(player):
        ros_processes.wait_for(lambda: int(ros.status().get("odometry_received", 0)) > 0, 60,
                               "the first keyframe")
        os.kill(ros.pid, signal.SIGSTOP)
        try:
            time.sleep(15)  # the bag lasts 150 s: 7.5 s at 20 times its speed
        finally:
            os.kill(ros.pid, signal.SIGCONT)
    play(ros, bag, poses + candidates, 20, while_playing=stall)
    final = ros.status()
    assert number(final, "inputs_refused", "inputs_dropped", "invalid_messages") == 0, final
    assert int(final["keyframes"]) == poses, final
    assert int(final["candidates"]) == candidates, final
