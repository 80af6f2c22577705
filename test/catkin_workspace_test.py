"""The package builds, installs and launches from a catkin workspace:
`catkin_make` and `catkin_make install` with the package in `src/`, then
`roslaunch rrr_slam rrr.launch` from the install space answers its services.

Runs in a clean environment (nothing of the package's own build sourced), so
only the workspace can provide `rrr_slam`.
"""
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from ros_processes import free_port, stop  # noqa: E402


def in_workspace(workspace, command, space=None, timeout=1800, check=True):
    """Runs `command` (a shell string) in a clean environment, with the
    workspace's `space` (devel or install) sourced if given."""
    env = {"PATH": "/usr/bin:/bin", "HOME": str(workspace), "LANG": "C.UTF-8",
           "ROS_HOME": str(workspace / "ros_home"), "ROS_HOSTNAME": "localhost"}
    setup = f"source {workspace / space / 'setup.bash'} && " if space else ""
    return subprocess.run(["bash", "-c", setup + command], cwd=workspace, env=env,
                          capture_output=True, text=True, timeout=timeout, check=check)


def test_catkin_make_install_and_launch_from_the_install_space():
    with tempfile.TemporaryDirectory() as tmp:
        workspace = pathlib.Path(tmp)
        (workspace / "src").mkdir()
        (workspace / "src" / "rrr_slam").symlink_to(ROOT)
        flags = ("-DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=OFF "
                 "-DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3")
        build = in_workspace(workspace, f"catkin_make -j2 {flags} && catkin_make install -j2 {flags}",
                             check=False)
        assert build.returncode == 0, build.stdout[-4000:] + build.stderr[-4000:]
        install = workspace / "install"
        assert (install / "lib" / "rrr_slam" / "rrr_node").is_file()
        assert (install / "share" / "rrr_slam" / "launch" / "rrr.launch").is_file()

        found = in_workspace(workspace, "rospack find rrr_slam", space="install")
        assert found.stdout.strip().startswith(str(install))
        msg = in_workspace(workspace, "rosmsg show rrr_slam/LoopClosure", space="install")
        assert "geometry_msgs/PoseWithCovariance" in msg.stdout
        tool = in_workspace(workspace, "rosrun rrr_slam rrr --help", space="install")
        assert "verify" in tool.stdout

        port = free_port()
        uri = f"export ROS_MASTER_URI=http://localhost:{port} && "
        env_setup = f"source {install / 'setup.bash'} && {uri}"
        launch = subprocess.Popen(
            ["bash", "-c", env_setup + f"exec roslaunch -p {port} rrr_slam rrr.launch"],
            cwd=workspace, env={"PATH": "/usr/bin:/bin", "HOME": str(workspace),
                                "ROS_HOME": str(workspace / "ros_home"),
                                "ROS_HOSTNAME": "localhost"},
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
            start_new_session=True)
        try:
            status = None
            deadline = time.time() + 120
            while time.time() < deadline and launch.poll() is None:
                status = in_workspace(workspace, uri + "rosservice call /rrr_node/get_status",
                                      space="install", timeout=60, check=False)
                if status.returncode == 0:
                    break
                time.sleep(1)
            assert launch.poll() is None, launch.stdout.read()
            assert status is not None and status.returncode == 0, status.stderr
            assert "keyframes: 0" in status.stdout
        finally:
            stop(launch)
