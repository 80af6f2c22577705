"""ROS processes for the package's Python tests and benchmarks: an
environment with the build's devel space, a free master port, starting and
stopping process groups, waiting, service calls and a process's memory.

Import it with `sys.path.insert(0, <repository>/scripts)`.
"""
import os
import signal
import socket
import subprocess
import time


# rosbag play, waiting for its subscribers, with an outgoing queue that holds
# a whole bag: rosbag's default (100 per topic) drops messages when the node
# reads them more slowly than the bag plays (a loaded machine, a fast rate).
# Kept alive past the bag's end: a player that exits shuts its connections
# down and drops what is still queued for the node. Stop it with stop() once
# the node has taken in what the caller waits for.
ROSBAG_PLAY = ["rosbag", "play", "--quiet", "--wait-for-subscribers", "--keep-alive",
               "--queue", "1000000"]


def ros_env(build_dir, port, home=None):
    """The environment of `build_dir`'s devel space with a master on `port`
    and ROS_HOME in `home` (default: the caller's ROS_HOME or /tmp)."""
    env = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8", "ROS_HOSTNAME": "localhost",
           "ROS_MASTER_URI": f"http://localhost:{port}"}
    home = home or os.environ.get("ROS_HOME", "/tmp/rrr_ros_home")
    env.update(HOME=str(home), ROS_HOME=str(home))
    setup = os.path.join(build_dir, "devel", "setup.bash")
    out = subprocess.run(["bash", "-c", f"source {setup} && env -0"], env=env,
                         capture_output=True, text=True, check=True).stdout
    return dict(line.split("=", 1) for line in out.split("\0") if "=" in line)


def free_port():
    """A TCP port on localhost that nothing listens on now."""
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def start(args, env, log, **kwargs):
    """Starts `args` in its own process group, output to the file `log`."""
    return subprocess.Popen([str(a) for a in args], env=env, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True, **kwargs)


def stop(process, timeout=30):
    """Stops `process` and its group: SIGINT, then SIGKILL after `timeout`
    seconds. Does nothing if it has ended."""
    if process is None or process.poll() is not None:
        return
    os.killpg(process.pid, signal.SIGINT)
    try:
        process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()


def wait_for(condition, seconds, what, period=0.5, state=None):
    """Calls `condition` until it returns something true (returned) or
    `seconds` pass (AssertionError naming `what`, and `state()` if given:
    what the caller last saw)."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(period)
    seen = f"; {state()}" if state else ""
    raise AssertionError(f"timed out after {seconds} s waiting for {what}{seen}")


def service(env, name, request="{}", timeout=600):
    """Calls a ROS service with rosservice; returns its top-level response
    fields as strings ({} if the call failed, e.g. no such service yet)."""
    try:
        out = subprocess.run(["rosservice", "call", name, request], env=env,
                             capture_output=True, text=True, timeout=timeout).stdout
    except subprocess.TimeoutExpired:
        return {}
    fields = {}
    for line in out.splitlines():
        if ":" in line and not line.startswith(" "):
            key, value = line.split(":", 1)
            fields[key.strip()] = value.strip().strip('"')
    return fields


def decisions(env, timeout=120):
    """Every candidate of ~get_decisions, in order, as a dict of its fields
    (from_robot, from_id, to_robot, to_id, state, test, ...), as strings."""
    out = subprocess.run(["rosservice", "call", "/rrr_node/get_decisions", "{}"], env=env,
                         capture_output=True, text=True, timeout=timeout, check=True).stdout
    every = []
    for line in out.splitlines():
        stripped = line.strip()
        if stripped == "-" or stripped.startswith("- "):  # a list's next entry
            every.append({})
            stripped = stripped[1:].strip()
        if every and ":" in stripped:
            key, value = stripped.split(":", 1)
            every[-1][key.strip()] = value.strip().strip('"').strip("'")
    return every


def fleet_names(g2o, robot="a"):
    """The poses of g2o file `g2o` as `rrr to-bag` names them for a fleet's
    rrr_node: id -> (robot, keyframe id). The robot of an id is the letter
    of its GTSAM symbol (top byte), else `robot`; each robot's keyframes are
    numbered 0, 1, ... in id order over all its sessions."""
    ids = set()
    with open(g2o) as f:
        for line in f:
            fields = line.split()
            if fields and fields[0].startswith("VERTEX"):
                ids.add(int(fields[1]))
            elif fields and fields[0].startswith("EDGE"):
                ids.update((int(fields[1]), int(fields[2])))
    names, count = {}, {}
    for key in sorted(ids):
        letter = chr(key >> 56)
        owner = letter if letter.isalpha() else robot
        names[key] = (owner, count.get(owner, 0))
        count[owner] = count.get(owner, 0) + 1
    return names


def node_pid(launch, name="rrr_node", seconds=60):
    """The pid of the process `name` that roslaunch `launch` started."""
    def find():
        out = subprocess.run(["pgrep", "-P", str(launch.pid), "-f", name],
                             capture_output=True, text=True).stdout.split()
        return int(out[0]) if out else None
    return wait_for(find, seconds, f"{name} to start")


def resident_mb(pid):
    """(current, peak) resident memory of process `pid` in MB."""
    fields = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            key, _, value = line.partition(":")
            fields[key] = value.split()
    return int(fields["VmRSS"][0]) / 1024.0, int(fields["VmHWM"][0]) / 1024.0
