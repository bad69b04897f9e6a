#!/usr/bin/env python3
"""rostest node: watches the helical robot steered through 3-D waypoints by the
mass-transformer controller node (launch/steering_3d.launch).

Always checked: the controller anchors and publishes its waypoints, steering status and slider
commands, no fault, and the slider commands reach the simulated robot and pitch it: the TRUE
head axis (rod_state head_pose) changes its elevation by at least min_pitch_deg.
With require_reached: the TRUE head path passes every waypoint within the tolerance (the watch
ends when it has, when the controller reports FINISHED, or at the timeout); whether the
controller itself declared the mission finished is printed, not required (its estimate may
place a waypoint the true path passed just outside the tolerance).

Private parameters:
  robot:            namespace of the robot (default flagella)
  watch:            simulated seconds to watch when require_reached is false [s]
  require_reached:  every waypoint must be reached (default false)
  tolerance:        required closest approach per waypoint [m]
  head_length:      for the printed figures [m] (2 R_H)
  min_pitch_deg:    least change of the head axis's elevation [deg]
  timeout:          wall seconds to wait"""
import math
import sys
import threading
import time
import unittest

import rospy
import rostest
from flagella_msgs.msg import RodState, SteeringStatus
from visualization_msgs.msg import MarkerArray


class SteeringWatch:
    def __init__(self, ns):
        self.lock = threading.Lock()
        self.waypoints = []
        self.head = []
        self.elevations = []
        self.last_stamp = 0.0
        self.finished_at = None
        self.fault = None
        self.last = None
        self.slider_commands = set()
        rospy.Subscriber("/%s/waypoint_markers" % ns, MarkerArray, self.on_waypoints, queue_size=2)
        rospy.Subscriber("/%s/rod_state" % ns, RodState, self.on_state, queue_size=10000)
        rospy.Subscriber("/%s/steering_status" % ns, SteeringStatus, self.on_status, queue_size=10000)

    def on_waypoints(self, msg):
        points = sorted((m.id, (m.pose.position.x, m.pose.position.y, m.pose.position.z))
                        for m in msg.markers if m.ns == "waypoints")
        with self.lock:
            self.waypoints = [p for _, p in points]

    def on_state(self, msg):
        p = msg.head_pose.position
        q = msg.head_pose.orientation
        # Head axis t = R e_z; the direction of travel is -t (docs/model.md 7.4).
        tz = 1.0 - 2.0 * (q.x * q.x + q.y * q.y)
        with self.lock:
            self.head.append((p.x, p.y, p.z))
            self.elevations.append(math.degrees(math.asin(max(-1.0, min(1.0, -tz)))))
            self.last_stamp = msg.header.stamp.to_sec()

    def on_status(self, msg):
        with self.lock:
            self.last = msg
            self.slider_commands.add(round(msg.slider_command, 5))
            if msg.mode == SteeringStatus.FINISHED and self.finished_at is None:
                self.finished_at = msg.header.stamp.to_sec()
            elif msg.mode == SteeringStatus.FAULT and self.fault is None:
                self.fault = msg.message

    def done(self):
        return self.finished_at is not None or self.fault is not None

    def misses(self):
        with self.lock:
            return [min((math.dist(w, h) for h in self.head), default=float("inf"))
                    for w in self.waypoints]


class SteeringCheck(unittest.TestCase):
    def test_steering_session(self):
        ns = rospy.get_param("~robot", "flagella")
        require_reached = bool(rospy.get_param("~require_reached", False))
        watch_time = float(rospy.get_param("~watch", 60.0))
        tolerance = float(rospy.get_param("~tolerance", 0.018))
        head_length = float(rospy.get_param("~head_length", 0.036))
        min_pitch = float(rospy.get_param("~min_pitch_deg", 10.0))
        timeout = float(rospy.get_param("~timeout", 900.0))
        watch = SteeringWatch(ns)
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown() and not watch.done():
            if not require_reached and watch.last_stamp >= watch_time:
                break
            if require_reached and watch.waypoints and max(watch.misses()) <= tolerance:
                break  # the true path has passed every waypoint
            time.sleep(0.5)
        time.sleep(0.5)  # the last rod states
        misses = watch.misses()
        with watch.lock:
            pitch = (max(watch.elevations) - min(watch.elevations)) if watch.elevations else 0.0
        print("[steering] %s at %.0f s simulated; misses %s mm (tolerance %.1f mm = %.2f head lengths); "
              "head elevation range %.1f deg; %d buckle cycles, %d distinct slider commands"
              % ("FINISHED" if watch.finished_at is not None else ("FAULT: %s" % watch.fault if watch.fault
                                                                    else "running"),
                 watch.last_stamp, ", ".join("%.1f" % (1e3 * m) for m in misses), 1e3 * tolerance,
                 tolerance / head_length, pitch, watch.last.buckle_cycles if watch.last else -1,
                 len(watch.slider_commands)), flush=True)
        self.assertIsNone(watch.fault, "the controller reported a fault: %s" % watch.fault)
        self.assertIsNotNone(watch.last, "no steering_status received")
        self.assertGreater(len(watch.waypoints), 0, "no waypoint markers received")
        self.assertGreater(len(watch.head), 100, "too few head samples to judge")
        self.assertGreater(len(watch.slider_commands), 10, "the slider commands never changed")
        self.assertGreaterEqual(pitch, min_pitch, "the head's elevation changed by %.1f deg only" % pitch)
        if require_reached:
            for i, miss in enumerate(misses):
                self.assertLessEqual(miss, tolerance, "waypoint %d: true path passed %.1f mm away "
                                     "(tolerance %.1f mm)" % (i + 1, 1e3 * miss, 1e3 * tolerance))


if __name__ == "__main__":
    rospy.init_node("steering_check")
    rostest.rosrun("flagella_control", "steering_check", SteeringCheck, sys.argv)
