#!/usr/bin/env python3
"""rostest node: the simulator node's contract, checked from outside over ROS.

- The IMU orientation equals the head frame reported in the rod state (same stamp).
- NaN, infinite and out-of-range motor commands are rejected and the last valid one is kept; a
  flood of them is logged as a few throttled lines, not one per command.
- The failsafe stops the motor when commands stop for longer than the timeout, and a new
  command restarts it; both changes are logged once.
- Pause freezes simulated time; resume continues it.
- Reset puts the robot back in its initial shape while the clock keeps running forward.
- Frames (REP-103/105): world -> odom (static, identity) -> base_link -> head (static) composes
  to the head pose of the rod state at the same stamp, and base_link's x axis is the head's
  forward direction -t^0, z is m1^0.
- The model's parameters are on the parameter server (~model/...), equal to the config file's;
  ~reconfigure applies new ~overrides (mirrored back), and a bad one is refused with the field
  and its range while the session runs on unchanged.
Expects the node in namespace /flagella with initial_motor:=stopped, command_timeout:=0.5,
max_motor_rpm:=200 and noise-free IMU (see test/sim_node.test).
"""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from flagella_msgs.msg import MotorCommand, RodState
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import Imu
from std_srvs.srv import SetBool, Trigger
from tf2_msgs.msg import TFMessage

NS = "/flagella"
COMMAND = 10.0            # rad/s, inside the allowed 200 rpm = 20.9 rad/s
COMMAND_PERIOD = 0.05     # s wall between commands (well inside the 0.5 s failsafe)
TIMEOUT = 0.5             # s of sim time: the failsafe timeout the .test file sets
QUATERNION_TOL = 1e-9     # same state, two message paths: only float formatting differs
WAIT = 30.0               # s wall: generous upper bound for anything to happen on a busy machine


class Listener:
    """Keeps the latest messages and the first rod state."""

    def __init__(self):
        self.lock = threading.Lock()
        self.states = []
        self.imu = {}
        self.first_state = None
        self.received = 0
        self.diagnostics = None
        self.logs = []  # (level, text) of the simulator node's log lines
        rospy.Subscriber(NS + "/rod_state", RodState, self.on_state, queue_size=1000)
        rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        rospy.Subscriber(NS + "/imu", Imu, self.on_imu, queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=100)
        self.tf = {}         # stamp [ns] -> {child: transform} from /tf
        self.tf_static = {}  # child -> transform from /tf_static
        rospy.Subscriber("/tf", TFMessage, self.on_tf, queue_size=1000)
        rospy.Subscriber("/tf_static", TFMessage, self.on_tf_static, queue_size=10)

    def on_tf(self, msg):
        with self.lock:
            for t in msg.transforms:
                self.tf.setdefault(t.header.stamp.to_nsec(), {})[t.child_frame_id] = t
            if len(self.tf) > 2000:
                for key in sorted(self.tf)[:1000]:
                    del self.tf[key]

    def on_tf_static(self, msg):
        with self.lock:
            for t in msg.transforms:
                self.tf_static[t.child_frame_id] = t

    def on_state(self, msg):
        with self.lock:
            if self.first_state is None:
                self.first_state = msg
            self.states.append(msg)
            self.received += 1
            del self.states[:-400]

    def on_imu(self, msg):
        with self.lock:
            self.imu[msg.header.stamp.to_nsec()] = msg
            if len(self.imu) > 2000:
                for key in sorted(self.imu)[:1000]:
                    del self.imu[key]

    def on_log(self, msg):
        if msg.msg.startswith("flagella_sim:"):
            with self.lock:
                self.logs.append((msg.level, msg.msg))

    def log_lines(self, level, text):
        with self.lock:
            return [m for lv, m in self.logs if lv == level and text in m]

    def on_diagnostics(self, msg):
        for status in msg.status:
            if status.name.startswith("flagella: flagella_sim"):
                with self.lock:
                    self.diagnostics = status

    def latest_state(self):
        with self.lock:
            return self.states[-1] if self.states else None

    def diagnostic_value(self, key):
        with self.lock:
            if self.diagnostics is None:
                return None
            for kv in self.diagnostics.values:
                if kv.key == key:
                    return kv.value
        return None


def quat_mul(a, b):
    """Hamilton product of (w, x, y, z) tuples."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def rotate(q, v):
    """v rotated by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = quat_mul(quat_mul(q, (0.0,) + tuple(v)), (q[0], -q[1], -q[2], -q[3]))
    return (x, y, z)


def as_pose(t):
    """(translation, rotation (w, x, y, z)) of a geometry_msgs/TransformStamped."""
    tr, r = t.transform.translation, t.transform.rotation
    return (tr.x, tr.y, tr.z), (r.w, r.x, r.y, r.z)


def compose(parent, child):
    """The pose of `child` (given in `parent`'s frame) in the frame `parent` is given in."""
    (pt, pq), (ct, cq) = parent, child
    moved = rotate(pq, ct)
    return tuple(a + b for a, b in zip(pt, moved)), quat_mul(pq, cq)


class Commander(threading.Thread):
    """Publishes a motor command periodically while enabled (a controller stand-in)."""

    def __init__(self):
        super().__init__(daemon=True)
        self.pub = rospy.Publisher(NS + "/motor_command", MotorCommand, queue_size=10)
        self.enabled = False
        self.value = COMMAND

    def send(self, value):
        msg = MotorCommand()
        msg.header.stamp = rospy.Time.now()
        msg.omega = value
        self.pub.publish(msg)

    def run(self):
        while not rospy.is_shutdown():
            if self.enabled:
                self.send(self.value)
            time.sleep(COMMAND_PERIOD)


def wait_until(condition, timeout=WAIT):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if condition():
            return True
        time.sleep(0.02)
    return False


def sim_time_of(state):
    return state.header.stamp.to_sec()


class SimNodeChecks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("sim_node_checks")
        cls.listener = Listener()
        cls.commander = Commander()
        cls.commander.start()
        assert wait_until(lambda: cls.listener.latest_state() is not None), "no rod_state"
        assert wait_until(lambda: cls.commander.pub.get_num_connections() > 0), "no subscriber"

    def wait_sim(self, seconds):
        """Waits until simulated time has advanced by `seconds` (by the rod_state stamps)."""
        start = sim_time_of(self.listener.latest_state())
        self.assertTrue(
            wait_until(lambda: sim_time_of(self.listener.latest_state()) >= start + seconds),
            "simulated time did not advance by %g s" % seconds)

    def wait_motor(self, value):
        return wait_until(lambda: self.listener.latest_state().omega_motor == value)

    def test_1_imu_orientation_is_the_head_frame(self):
        self.commander.value = COMMAND
        self.commander.enabled = True
        self.assertTrue(self.wait_motor(COMMAND), "valid command not applied")
        self.wait_sim(1.0)  # spinning head: the orientation changes between samples
        matched = 0
        with self.listener.lock:
            pairs = [(s, self.listener.imu.get(s.header.stamp.to_nsec())) for s in self.listener.states]
        for state, imu in pairs:
            if imu is None:
                continue
            q = state.head_pose.orientation
            p = imu.orientation
            dot = q.x * p.x + q.y * p.y + q.z * p.z + q.w * p.w
            self.assertAlmostEqual(abs(dot), 1.0, delta=QUATERNION_TOL)
            self.assertEqual(imu.header.frame_id, "flagella/head")
            matched += 1
        self.assertGreaterEqual(matched, 10, "too few rod_state/imu pairs with equal stamps")
        # A spinning head: the orientation really changed over the window.
        first, last = pairs[0][0].head_pose.orientation, pairs[-1][0].head_pose.orientation
        dot = first.x * last.x + first.y * last.y + first.z * last.z + first.w * last.w
        self.assertLess(abs(dot), 1.0 - 1e-6)

    def test_2_bad_commands_are_rejected_and_the_last_valid_one_kept(self):
        self.commander.value = COMMAND
        self.commander.enabled = True
        self.assertTrue(self.wait_motor(COMMAND))
        self.assertTrue(wait_until(lambda: self.listener.diagnostic_value("motor_rejected") is not None))
        rejected_before = int(self.listener.diagnostic_value("motor_rejected"))
        bad = [float("nan"), float("inf"), -float("inf"), 1e4, -25.0]
        for value in bad:
            self.commander.send(value)
        self.wait_sim(1.0)
        self.assertEqual(self.listener.latest_state().omega_motor, COMMAND)
        self.assertTrue(wait_until(
            lambda: int(self.listener.diagnostic_value("motor_rejected")) == rejected_before + len(bad)),
            "diagnostics do not count the %d rejected commands" % len(bad))
        for state in list(self.listener.states)[-20:]:
            self.assertTrue(math.isfinite(state.omega_motor))
        # A flood of 300 bad commands within about a second: a few throttled error lines (one
        # per 2 s of wall time), not 300.
        time.sleep(2.5)  # past the throttle period of the lines above
        before = len(self.listener.log_lines(Log.ERROR, "rejected"))
        for _ in range(300):
            self.commander.send(float("nan"))
            time.sleep(0.003)
        self.assertTrue(wait_until(
            lambda: int(self.listener.diagnostic_value("motor_rejected")) >= rejected_before + len(bad) + 300))
        time.sleep(1.0)
        flood = len(self.listener.log_lines(Log.ERROR, "rejected")) - before
        self.assertGreaterEqual(flood, 1, "the flood was not logged at all")
        self.assertLessEqual(flood, 2, "the flood gave %d error lines" % flood)

    def test_3_failsafe_stops_the_motor_and_a_new_command_restarts_it(self):
        self.commander.value = COMMAND
        self.commander.enabled = True
        self.assertTrue(self.wait_motor(COMMAND))
        self.commander.enabled = False
        stopped_at = sim_time_of(self.listener.latest_state())
        self.assertTrue(self.wait_motor(0.0), "failsafe did not stop the motor")
        tripped_at = sim_time_of(self.listener.latest_state())
        # Not before the timeout (one rod_state period and one command period of slack).
        self.assertGreaterEqual(tripped_at - stopped_at, TIMEOUT - 0.1)
        self.assertTrue(wait_until(lambda: self.listener.diagnostic_value("failsafe_active") == "true"))
        self.assertEqual(self.listener.diagnostics.level, DiagnosticStatus.WARN)
        self.assertTrue(wait_until(lambda: self.listener.log_lines(Log.WARN, "failsafe engaged")),
                        "the failsafe's engagement was not logged")
        self.commander.enabled = True
        self.assertTrue(self.wait_motor(COMMAND), "a new command did not restart the motor")
        self.assertTrue(wait_until(lambda: self.listener.log_lines(Log.INFO, "failsafe released")),
                        "the failsafe's release was not logged")

    def test_4_pause_freezes_time_and_resume_continues(self):
        pause = rospy.ServiceProxy(NS + "/sim/pause", SetBool)
        pause.wait_for_service(WAIT)
        self.assertTrue(pause(True).success)
        time.sleep(0.3)  # messages in flight
        frozen = sim_time_of(self.listener.latest_state())
        time.sleep(1.0)
        self.assertEqual(sim_time_of(self.listener.latest_state()), frozen)
        self.assertTrue(pause(False).success)
        self.assertTrue(wait_until(lambda: sim_time_of(self.listener.latest_state()) > frozen + 0.2))

    def test_5_reset_restores_the_initial_shape_and_the_clock_goes_on(self):
        self.commander.enabled = False
        self.wait_sim(1.0)
        before = self.listener.latest_state()
        initial = self.listener.first_state
        moved = max(abs(a.x - b.x) + abs(a.y - b.y) + abs(a.z - b.z)
                    for a, b in zip(before.nodes, initial.nodes))
        self.assertGreater(moved, 1e-6, "robot never moved; reset would prove nothing")
        reset = rospy.ServiceProxy(NS + "/sim/reset", Trigger)
        reset.wait_for_service(WAIT)
        t_reset = sim_time_of(before)
        with self.listener.lock:
            received_before = self.listener.received
        self.assertTrue(reset().success)

        def distance_to_initial(state):
            return max(abs(a.x - b.x) + abs(a.y - b.y) + abs(a.z - b.z)
                       for a, b in zip(state.nodes, initial.nodes))

        def reset_state_seen():
            with self.listener.lock:
                new = self.listener.received - received_before
                after = self.listener.states[-new:] if new > 0 else []
            return any(distance_to_initial(s) < 1e-12 for s in after)

        self.assertTrue(wait_until(reset_state_seen), "no state equal to the initial shape after reset")
        self.assertGreaterEqual(sim_time_of(self.listener.latest_state()), t_reset)
        stamps = [sim_time_of(s) for s in self.listener.states]
        self.assertEqual(stamps, sorted(stamps), "clock went backwards")

    def test_6_frames_compose_to_the_head_pose(self):
        self.commander.value = COMMAND
        self.commander.enabled = True
        self.wait_sim(1.0)
        self.assertTrue(wait_until(lambda: len(self.listener.tf_static) >= 2), "no /tf_static")
        with self.listener.lock:
            static = dict(self.listener.tf_static)
            pairs = [(s, self.listener.tf.get(s.header.stamp.to_nsec(), {})) for s in self.listener.states]
        odom, head = static.get(NS[1:] + "/odom"), static.get(NS[1:] + "/head")
        self.assertIsNotNone(odom, "no world -> flagella/odom on /tf_static")
        self.assertIsNotNone(head, "no flagella/base_link -> flagella/head on /tf_static")
        self.assertEqual(odom.header.frame_id, "world")
        self.assertEqual(head.header.frame_id, NS[1:] + "/base_link")
        checked = 0
        # A reset republishes the state at the stamp of the last one before it: skip such stamps.
        stamps = [state.header.stamp.to_nsec() for state, _ in pairs]
        for state, moving in pairs:
            if stamps.count(state.header.stamp.to_nsec()) > 1:
                continue
            base = moving.get(NS[1:] + "/base_link")
            if base is None:
                continue
            self.assertEqual(base.header.frame_id, NS[1:] + "/odom")
            position, rotation = compose(compose(as_pose(odom), as_pose(base)), as_pose(head))
            p, q = state.head_pose.position, state.head_pose.orientation
            for a, b in zip(position, (p.x, p.y, p.z)):
                self.assertAlmostEqual(a, b, delta=1e-9)
            dot = sum(a * b for a, b in zip(rotation, (q.w, q.x, q.y, q.z)))
            self.assertAlmostEqual(abs(dot), 1.0, delta=QUATERNION_TOL)
            # base_link x = -t^0 (forward), z = m1^0, both from the rod state's head frame
            head_q = (q.w, q.x, q.y, q.z)
            base_q = as_pose(base)[1]
            for a, b in zip(rotate(base_q, (1, 0, 0)), rotate(head_q, (0, 0, -1))):
                self.assertAlmostEqual(a, b, delta=1e-9)
            for a, b in zip(rotate(base_q, (0, 0, 1)), rotate(head_q, (1, 0, 0))):
                self.assertAlmostEqual(a, b, delta=1e-9)
            checked += 1
        self.assertGreaterEqual(checked, 10, "too few rod_state / tf pairs with equal stamps")

    def test_7_parameters_on_the_server_and_reconfigure(self):
        import yaml
        with open(rospy.get_param(NS + "/sim/config")) as f:
            in_file = yaml.safe_load(f)["medium"]["viscosity"]
        key = NS + "/sim/model/medium/viscosity"
        self.assertEqual(rospy.get_param(key), in_file)
        reconfigure = rospy.ServiceProxy(NS + "/sim/reconfigure", Trigger)
        rospy.set_param(NS + "/sim/overrides", "medium.viscosity=3.5")
        answer = reconfigure()
        self.assertTrue(answer.success, answer.message)
        self.assertEqual(rospy.get_param(key), 3.5)
        t_after = sim_time_of(self.listener.latest_state())
        self.wait_sim(0.2)  # still running
        self.assertGreater(sim_time_of(self.listener.latest_state()), t_after)
        rospy.set_param(NS + "/sim/overrides", "medium.viscosity=-1")
        answer = reconfigure()
        self.assertFalse(answer.success)
        self.assertIn("medium.viscosity", answer.message)
        self.assertIn("must be in [", answer.message)
        self.assertEqual(rospy.get_param(key), 3.5)
        rospy.set_param(NS + "/sim/overrides", "")
        self.assertTrue(reconfigure().success)
        self.assertEqual(rospy.get_param(key), in_file)


if __name__ == "__main__":
    rostest.rosrun("flagella_sim", "sim_node_checks", SimNodeChecks)
