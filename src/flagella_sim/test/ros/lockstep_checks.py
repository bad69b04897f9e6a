#!/usr/bin/env python3
"""rostest node: the simulator node in lockstep with a controller, checked over ROS.

A stand-in controller answers every IMU sample with a motor command stamped with the sample's
stamp: 0 rad/s before T_SWITCH, COMMAND from T_SWITCH on, and no answer from T_STOP on.
- The simulator never runs ahead: in every diagnostics report up to T_STOP it has published
  exactly one IMU sample more than the commands it accepted (the one awaiting its answer), and
  it accepted every command sent.
- Each command is applied on the very next step: rod_state's omega_motor at stamp t is the
  command answering the IMU sample at t - dt (so 0 at T_SWITCH, COMMAND at T_SWITCH + dt).
- Without an answer the simulator holds for lockstep_timeout wall seconds, then steps on and
  counts the timeout.
Expects test/lockstep.test: lockstep:=true, lockstep_timeout:=1, real_time_factor:=0,
initial_motor:=stopped, state and IMU rate 100 Hz = 1/dt (granular design 1, dt = 0.01 s).
"""
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from flagella_msgs.msg import MotorCommand, RodState
from sensor_msgs.msg import Imu

NS = "/flagella"
DT = 0.01               # s, the config's step (= 1 / imu_rate = 1 / state_rate)
COMMAND = 3.0           # rad/s
T_SWITCH = 1.0          # s of sim time: COMMAND from this IMU stamp on
T_STOP = 2.0            # s of sim time: no answer from this IMU stamp on
LOCKSTEP_TIMEOUT = 1.0  # s wall, as lockstep.test sets
STAMP_TOL = 1e-6        # s: stamps are sums of steps rounded to nanoseconds
WAIT = 60.0             # s wall: generous upper bound on a busy machine
STATUS = "flagella: flagella_sim"


def wait_until(condition, timeout=WAIT):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if condition():
            return True
        time.sleep(0.005)
    return False


class Controller:
    """Answers IMU samples; records what it saw and sent."""

    def __init__(self):
        self.lock = threading.Lock()
        self.imu_stamps = []
        self.sent = 0
        self.unanswered_wall = None  # wall time of the first sample left unanswered
        self.pub = rospy.Publisher(NS + "/motor_command", MotorCommand, queue_size=1000)

    def subscribe(self):
        rospy.Subscriber(NS + "/imu", Imu, self.on_imu, queue_size=1000)

    def on_imu(self, msg):
        t = msg.header.stamp.to_sec()
        with self.lock:
            self.imu_stamps.append(t)
            if t >= T_STOP - STAMP_TOL:
                if self.unanswered_wall is None:
                    self.unanswered_wall = time.time()
                return
        command = MotorCommand()
        command.header.stamp = msg.header.stamp
        command.omega = COMMAND if t >= T_SWITCH - STAMP_TOL else 0.0
        self.pub.publish(command)
        with self.lock:
            self.sent += 1


class Recorder:
    """Keeps every rod state (stamp, omega_motor, wall time) and every simulator status."""

    def __init__(self):
        self.lock = threading.Lock()
        self.states = []
        self.statuses = []
        self.state_sub = rospy.Subscriber(NS + "/rod_state", RodState, self.on_state,
                                          queue_size=1000)
        self.diag_sub = rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics,
                                         queue_size=1000)

    def on_state(self, msg):
        with self.lock:
            self.states.append((msg.header.stamp.to_sec(), msg.omega_motor, time.time()))

    def on_diagnostics(self, msg):
        for status in msg.status:
            if status.name == STATUS:
                values = {kv.key: kv.value for kv in status.values}
                with self.lock:
                    self.statuses.append((msg.header.stamp.to_sec(), values))

    def states_after(self, t):
        with self.lock:
            return [s for s in self.states if s[0] > t + STAMP_TOL]


class LockstepChecks(unittest.TestCase):
    def test_lockstep(self):
        rospy.init_node("lockstep_checks")
        recorder = Recorder()
        controller = Controller()
        # The simulator holds t = 0 until the IMU has a subscriber and motor_command a
        # publisher: be ready to listen and to answer before subscribing to the IMU.
        self.assertTrue(wait_until(lambda: recorder.state_sub.get_num_connections() > 0))
        self.assertTrue(wait_until(lambda: recorder.diag_sub.get_num_connections() > 0))
        self.assertTrue(wait_until(lambda: controller.pub.get_num_connections() > 0))
        controller.subscribe()

        # Run to T_STOP, where the controller stops answering.
        self.assertTrue(wait_until(lambda: controller.unanswered_wall is not None),
                        "the simulator never reached t = %g s" % T_STOP)
        stalled_at = controller.unanswered_wall
        # Held: nothing beyond T_STOP for most of the timeout...
        time.sleep(max(0.0, stalled_at + 0.7 * LOCKSTEP_TIMEOUT - time.time()))
        ahead = recorder.states_after(T_STOP)
        self.assertFalse(ahead, "the simulator stepped past an unanswered IMU sample (to t = %.3f s)"
                         % (ahead[-1][0] if ahead else 0.0))
        # ...then it steps on.
        self.assertTrue(wait_until(lambda: recorder.states_after(T_STOP)),
                        "the simulator never stepped on after the lockstep timeout")
        resumed_at = recorder.states_after(T_STOP)[0][2]
        self.assertGreaterEqual(resumed_at - stalled_at, 0.9 * LOCKSTEP_TIMEOUT)
        # The first report after T_STOP: the one timeout counted, every command sent accepted.
        self.assertTrue(wait_until(lambda: any(stamp > T_STOP + STAMP_TOL
                                               for stamp, _ in list(recorder.statuses))))

        with controller.lock:
            imu_stamps = list(controller.imu_stamps)
            sent = controller.sent
        with recorder.lock:
            states = list(recorder.states)
            statuses = list(recorder.statuses)
        steps = int(round(T_STOP / DT))

        # Every IMU sample up to T_STOP arrived, once, and all before it were answered.
        answered = [t for t in imu_stamps if t < T_STOP - STAMP_TOL]
        self.assertEqual(len(answered), steps)
        self.assertEqual(sent, len(answered))
        self.assertEqual(len(set(round(t / DT) for t in answered)), steps)

        # Never ahead: one IMU sample more than the accepted commands, in every report.
        checked = 0
        for stamp, values in statuses:
            if stamp > T_STOP + STAMP_TOL:
                continue
            imu_published = int(values["published " + NS + "/imu"])
            accepted = int(values["motor_accepted"])
            self.assertEqual(imu_published, accepted + 1, "at t = %.3f s" % stamp)
            checked += 1
        self.assertGreaterEqual(checked, int(T_STOP * 10) - 1, "too few diagnostics reports")
        after = [values for stamp, values in statuses if stamp > T_STOP + STAMP_TOL][0]
        self.assertEqual(int(after["lockstep_timeouts"]), 1)
        self.assertEqual(int(after["motor_accepted"]), sent)
        self.assertEqual(int(after["motor_rejected"]), 0)

        # Applied on the very next step: omega_motor at t answers the sample at t - dt.
        in_window = [s for s in states if STAMP_TOL < s[0] < T_STOP + STAMP_TOL]
        self.assertEqual(len(in_window), steps, "a rod_state per step up to T_STOP")
        for stamp, omega_motor, _ in in_window:
            expected = COMMAND if stamp - DT >= T_SWITCH - STAMP_TOL else 0.0
            self.assertEqual(omega_motor, expected, "at t = %.3f s" % stamp)
        switched = [stamp for stamp, omega_motor, _ in in_window if omega_motor == COMMAND]
        self.assertAlmostEqual(switched[0], T_SWITCH + DT, delta=STAMP_TOL)


if __name__ == "__main__":
    rostest.rosrun("flagella_sim", "lockstep_checks", LockstepChecks)
