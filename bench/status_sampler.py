#!/usr/bin/python3
"""Calls rrr_node's ~get_status every PERIOD seconds and prints one JSON line
per sample (wall time, the status fields, and the node's resident memory),
until the node goes away or SECONDS pass. Run it in the package's ROS
environment (bench/node_scaling.py does).

    bench/status_sampler.py PID [PERIOD] [SECONDS]
"""
import json
import pathlib
import sys
import time

import rospy
from rrr_slam.srv import GetStatus

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "scripts"))
import ros_processes  # noqa: E402


def main():
    pid, period = int(sys.argv[1]), float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    limit = float(sys.argv[3]) if len(sys.argv) > 3 else 1e9
    rospy.wait_for_service("/rrr_node/get_status", timeout=60)
    get_status = rospy.ServiceProxy("/rrr_node/get_status", GetStatus, persistent=True)
    start = time.time()
    while time.time() - start < limit:
        try:
            status = get_status()
            rss, peak = ros_processes.resident_mb(pid)
        except (rospy.ServiceException, OSError):
            break
        sample = {slot: getattr(status, slot) for slot in status.__slots__}
        sample.update(wall=time.time() - start, rss_mb=rss, peak_rss_mb=peak)
        print(json.dumps(sample), flush=True)
        time.sleep(period)


if __name__ == "__main__":
    main()
