#!/usr/bin/python3
"""Floods rrr_node as a misbehaving front-end would: odometry at RATE Hz (a
keyframe each, straight ahead) while CANDIDATES loop closures go out as fast
as they can, mixed: ids far past the newest keyframe, stamps in the future,
NaN poses, negative covariances, self-loops, consecutive poses, near-future
ids, and junk pairs of existing keyframes. Stays until the node says it
received them all (~get_status; a publisher that exits drops what is still
queued), then prints one JSON line: how many messages of each topic were
published. Run in the package's ROS environment.

    test/flood_publisher.py CANDIDATES RATE
"""
import json
import math
import random
import sys
import threading

import rospy
from nav_msgs.msg import Odometry
from rrr_slam.msg import LoopClosure
from rrr_slam.srv import GetStatus

COVARIANCE = [0.0] * 36
for axis in range(6):
    COVARIANCE[7 * axis] = 0.01


def odometry_loop(publisher, rate, stop, published):
    """Publishes a keyframe 0.1 m ahead of the last every 1 / rate s."""
    timer = rospy.Rate(rate)
    while not stop.is_set() and not rospy.is_shutdown():
        m = Odometry()
        m.header.stamp = rospy.Time.now()
        m.header.frame_id = "odom"
        m.child_frame_id = "base_link"
        m.pose.pose.position.x = 0.1 * published[0]
        m.pose.pose.orientation.w = 1.0
        m.pose.covariance = COVARIANCE
        publisher.publish(m)
        published[0] += 1
        timer.sleep()


def candidate(number, newest, rng):
    """Loop closure number `number` of the flood, the newest keyframe being
    `newest` (as far as this publisher knows)."""
    m = LoopClosure()
    m.header.stamp = rospy.Time.now()
    m.header.frame_id = "base_link"
    m.reference = LoopClosure.BY_ID
    m.relative_pose.pose.orientation.w = 1.0
    m.relative_pose.covariance = list(COVARIANCE)
    m.confidence = -1
    newest = max(newest, 12)
    kind = number % 10
    m.to_id, m.from_id = newest, rng.randrange(0, newest - 10)
    if kind <= 1:  # far past the newest keyframe
        m.to_id = newest + 5000 + number
    elif kind <= 3:  # a keyframe stamped an hour from now
        m.reference = LoopClosure.BY_STAMP
        m.from_stamp = m.header.stamp
        m.to_stamp = m.header.stamp + rospy.Duration(3600.0)
    elif kind == 4:
        m.relative_pose.pose.position.x = math.nan
    elif kind == 5:
        m.relative_pose.covariance[0] = -1.0
    elif kind == 6:
        m.from_id = m.to_id
    elif kind == 7:
        m.from_id = m.to_id - 1
    elif kind == 8:  # a few keyframes ahead
        m.to_id = newest + 1 + number % 200
    return m


def main():
    candidates, rate = int(sys.argv[1]), float(sys.argv[2])
    rospy.init_node("flood_publisher", anonymous=True)
    odometry = rospy.Publisher("/odom", Odometry, queue_size=candidates + 1)
    loops = rospy.Publisher("/loop_closures", LoopClosure, queue_size=candidates + 1)
    while (odometry.get_num_connections() == 0 or loops.get_num_connections() == 0) \
            and not rospy.is_shutdown():
        rospy.sleep(0.1)
    published = [0]
    stop = threading.Event()
    thread = threading.Thread(target=odometry_loop, args=(odometry, rate, stop, published))
    thread.start()
    rng = random.Random(1)
    rospy.sleep(0.5)
    for number in range(candidates):
        loops.publish(candidate(number, published[0] - 1, rng))
    stop.set()
    thread.join()
    # The publishers' queues go out before the node is asked what it got.
    status = rospy.ServiceProxy("/rrr_node/get_status", GetStatus)
    deadline = rospy.get_time() + 900
    while not rospy.is_shutdown() and rospy.get_time() < deadline:
        got = status()
        if (got.odometry_received, got.loop_closures_received) == (published[0], candidates):
            break
        rospy.sleep(0.5)
    print(json.dumps({"odometry": published[0], "loop_closures": candidates}), flush=True)


if __name__ == "__main__":
    main()
