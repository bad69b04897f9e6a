#!/usr/bin/env python3
"""rostest node: the helical robot (one flagellum with RSS hydrodynamics) over ROS.

- The rod state has the head group and exactly one tail group, the flagellum x_3 .. x_{N-1}
  (plate rim, hook, helix), and every node position is finite.
- Under a constant motor command the motor drives the flagellum and the head counter-rotates
  (omega_h and omega_t of opposite signs), the applied motor rate equals the command, and the
  shape stays finite.
- rviz markers are published.
Expects the node in namespace /flagella with initial_motor:=stopped (see test/helical_session.test).
"""
import math
import threading
import time
import unittest

import rospy
import rostest
from flagella_msgs.msg import MotorCommand, RodState
from visualization_msgs.msg import MarkerArray

NS = "/flagella"
COMMAND = 3.0         # rad/s (about 29 rpm), below the buckling threshold of the default robot
SPIN_UP = 3.0         # s of sim time before the rates are read
WAIT = 120.0          # s wall: generous bound on a busy 2-core machine


class HelicalSessionChecks(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.states = []
        self.markers = 0
        rospy.Subscriber(NS + "/rod_state", RodState, self.on_state, queue_size=100)
        rospy.Subscriber(NS + "/markers", MarkerArray, self.on_markers, queue_size=10)
        self.pub = rospy.Publisher(NS + "/motor_command", MotorCommand, queue_size=10)

    def on_state(self, msg):
        with self.lock:
            self.states.append(msg)
            del self.states[:-50]

    def on_markers(self, _msg):
        with self.lock:
            self.markers += 1

    def latest(self):
        with self.lock:
            return self.states[-1] if self.states else None

    def wait_for(self, predicate, what):
        deadline = time.time() + WAIT
        while time.time() < deadline and not rospy.is_shutdown():
            if predicate():
                return
            time.sleep(0.05)
        self.fail("timed out waiting for " + what)

    def command(self, omega):
        msg = MotorCommand()
        msg.header.stamp = rospy.Time.now()
        msg.omega = omega
        self.pub.publish(msg)

    def assert_finite(self, state):
        for p in state.nodes:
            self.assertTrue(all(math.isfinite(v) for v in (p.x, p.y, p.z)), "non-finite node")

    def test_flagellum_session(self):
        self.wait_for(lambda: self.latest() is not None, "a rod state")
        first = self.latest()
        self.assertEqual(len(first.tails), 1, "the helical robot has one flagellum group")
        flagellum = list(first.tails[0].nodes)
        self.assertEqual(flagellum, list(range(3, len(first.nodes))),
                         "the flagellum group is x_3 .. x_{N-1}")
        self.assert_finite(first)
        self.wait_for(lambda: self.pub.get_num_connections() > 0, "the motor_command subscriber")
        # Spin up for SPIN_UP s of sim time from the first state that shows the command applied:
        # the lockstep-free simulator can run seconds of sim time before the first command
        # arrives, and those seconds do not count.
        applied = None
        deadline = time.time() + WAIT
        while time.time() < deadline and not rospy.is_shutdown():
            self.command(COMMAND)
            state = self.latest()
            if applied is None and abs(state.omega_motor - COMMAND) < 1e-9:
                applied = state.header.stamp.to_sec()
            if applied is not None and state.header.stamp.to_sec() > applied + SPIN_UP:
                break
            time.sleep(0.1)
        state = self.latest()
        self.assertIsNotNone(applied, "the motor command was never applied")
        self.assertGreater(state.header.stamp.to_sec(), applied + SPIN_UP, "simulation did not run")
        self.assert_finite(state)
        self.assertAlmostEqual(state.omega_motor, COMMAND, places=9)
        self.assertLess(state.omega_h * state.omega_t, 0.0,
                        "head (%g) and flagellum (%g) must counter-rotate"
                        % (state.omega_h, state.omega_t))
        self.assertGreater(abs(state.omega_t), 0.1 * COMMAND)
        self.wait_for(lambda: self.markers > 0, "rviz markers")


if __name__ == "__main__":
    rospy.init_node("helical_session_checks")
    rostest.rosrun("flagella_sim", "helical_session_checks", HelicalSessionChecks)
