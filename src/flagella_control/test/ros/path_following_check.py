#!/usr/bin/env python3
"""rostest node: watches one or more robots follow their paths and checks the cross-track error
of the TRUE head path (rod_state head_pose) against the reference path the controller anchored.

Private parameters:
  robots:           namespaces to watch, e.g. [flagella] or [open_loop, closed_loop]
  max_cross_track:  bound on the max cross-track error, in tail lengths (0: not checked)
  tail_length:      l [m]
  require_finished: every robot must report FINISHED (default true)
  compare_open / compare_closed / min_ratio: if set, RMS(open) >= min_ratio * RMS(closed)
  timeout:          wall seconds to wait for all robots to finish"""
import math
import os
import sys
import threading
import time
import unittest

import rospy
import rostest
from flagella_msgs.msg import ControllerStatus, RodState
from nav_msgs.msg import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "scripts"))
from path_tracking import tracking_errors  # noqa: E402


class RobotWatch:
    def __init__(self, ns):
        self.ns = ns
        self.lock = threading.Lock()
        self.reference = []
        self.head = []
        self.start = None
        self.end = None
        self.fault = None
        self.controller = "?"
        rospy.Subscriber("/%s/reference_path" % ns, Path, self.on_reference, queue_size=2)
        rospy.Subscriber("/%s/rod_state" % ns, RodState, self.on_state, queue_size=10000)
        rospy.Subscriber("/%s/controller_status" % ns, ControllerStatus, self.on_status, queue_size=10000)

    def on_reference(self, msg):
        with self.lock:
            self.reference = [(p.pose.position.x, p.pose.position.y) for p in msg.poses]

    def on_state(self, msg):
        p = msg.head_pose.position
        with self.lock:
            self.head.append((msg.header.stamp.to_sec(), p.x, p.y))

    def on_status(self, msg):
        t = msg.header.stamp.to_sec()
        with self.lock:
            self.controller = msg.controller
            if msg.mode == ControllerStatus.RUNNING and self.start is None:
                self.start = t
            elif msg.mode == ControllerStatus.FINISHED and self.end is None:
                self.end = t
            elif msg.mode == ControllerStatus.FAULT and self.fault is None:
                self.fault = msg.message

    def done(self):
        return self.end is not None or self.fault is not None

    def errors(self):
        with self.lock:
            run = [(x, y) for t, x, y in self.head
                   if self.start is not None and t >= self.start and (self.end is None or t <= self.end)]
            return tracking_errors(run, self.reference), len(run)


class PathFollowingCheck(unittest.TestCase):
    def test_path_following(self):
        robots = rospy.get_param("~robots", ["flagella"])
        bound = float(rospy.get_param("~max_cross_track", 0.0))
        tail_length = float(rospy.get_param("~tail_length", 0.11))
        require_finished = bool(rospy.get_param("~require_finished", True))
        timeout = float(rospy.get_param("~timeout", 600.0))
        watches = {ns: RobotWatch(ns) for ns in robots}
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            if all(w.done() for w in watches.values()):
                break
            time.sleep(0.2)
        time.sleep(0.5)  # the last rod states
        rms = {}
        for ns, w in watches.items():
            (max_err, rms_err), samples = w.errors()
            rms[ns] = rms_err
            duration = (w.end if w.end is not None else float("nan")) - (w.start or 0.0)
            print("[path_following] %s (%s): %s, %.0f s simulated, %d head samples; cross-track max %.1f mm "
                  "(%.3f l), RMS %.1f mm (%.3f l)"
                  % (ns, w.controller, "FINISHED" if w.end is not None else ("FAULT: %s" % w.fault if w.fault
                                                                            else "NOT finished"),
                     duration, samples, 1e3 * max_err, max_err / tail_length, 1e3 * rms_err,
                     rms_err / tail_length), flush=True)
            self.assertIsNone(w.fault, "%s reported a fault: %s" % (ns, w.fault))
            if require_finished:
                self.assertIsNotNone(w.end, "%s did not finish its path within %.0f s wall" % (ns, timeout))
            self.assertGreater(samples, 100, "%s: too few head samples to judge" % ns)
            self.assertTrue(math.isfinite(max_err))
            if bound > 0.0:
                self.assertLessEqual(max_err / tail_length, bound,
                                     "%s: max cross-track %.3f l exceeds the bound %.3f l"
                                     % (ns, max_err / tail_length, bound))
        open_ns = rospy.get_param("~compare_open", "")
        closed_ns = rospy.get_param("~compare_closed", "")
        if open_ns and closed_ns:
            ratio = float(rospy.get_param("~min_ratio", 2.0))
            print("[path_following] RMS open / closed = %.2f (required >= %.2f)"
                  % (rms[open_ns] / rms[closed_ns], ratio), flush=True)
            self.assertGreaterEqual(rms[open_ns], ratio * rms[closed_ns])


if __name__ == "__main__":
    rospy.init_node("path_following_check")
    rostest.rosrun("flagella_control", "path_following_check", PathFollowingCheck, sys.argv)
