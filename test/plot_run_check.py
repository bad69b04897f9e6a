#!/usr/bin/env python3
"""Self-check of src/flagella_sim/tools/plot_run.py against closed forms: the forward speed is
the slope of the displacement along the initial head axis (a head moving at constant velocity
gives that velocity's component), the title carries the motor rate and the buckling verdict, a
helical run gets the flagellum-tilt panel, and a table lacking a column exits 2.
  /usr/bin/python3 test/plot_run_check.py
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "src", "flagella_sim", "tools", "plot_run.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import plot_run  # noqa: E402

COLUMNS = ("time,head_x,head_y,head_z,head_axis_x,head_axis_y,head_axis_z,speed,yaw_rate,"
           "flagellum_tilt")


def write_run(folder, tilt_deg, buckled):
    """A head moving at (0.1, 0, -0.3) mm/s with its axis +z (forward is -z): v = 0.3 mm/s."""
    with open(os.path.join(folder, "timeseries.csv"), "w") as f:
        f.write(COLUMNS + "\n")
        for i in range(201):
            t = 0.1 * i
            f.write("%g,%g,0,%g,0,0,1,%g,0,%g\n" % (t, 1e-4 * t, -3e-4 * t, math.hypot(1e-4, 3e-4),
                                                   math.radians(tilt_deg * t / 20.0)))
    with open(os.path.join(folder, "summary.json"), "w") as f:
        json.dump({"config": "config/helical_robot.yaml", "robot": "helical", "omega_T_rpm": 30.0,
                   "flagellum_tilt_max_deg": tilt_deg, "buckled": buckled,
                   "buckling_tilt_deg": 15.0, "speed_mm_s": 0.3, "steady_window_s": [10, 20]}, f)


class PlotRun(unittest.TestCase):
    def test_sliding_slope_of_a_line_is_its_slope(self):
        times = [0.05 * i for i in range(100)]
        slopes = plot_run.sliding_slope(times, [2.5 * t - 1.0 for t in times], 2.0)
        for s in slopes:
            self.assertAlmostEqual(s, 2.5, places=9)

    def test_forward_speed_is_the_component_along_the_initial_axis(self):
        with tempfile.TemporaryDirectory() as d:
            write_run(d, 20.0, True)
            t = plot_run.read_table(os.path.join(d, "timeseries.csv"))
            forward = plot_run.sliding_slope(t["time"], plot_run.forward_displacement(t), 2.0)
            self.assertAlmostEqual(forward[100], 3e-4, places=12)
            self.assertAlmostEqual(t["speed"][100], math.hypot(1e-4, 3e-4), places=9)

    def test_title_names_rate_and_verdict(self):
        with tempfile.TemporaryDirectory() as d:
            write_run(d, 20.0, True)
            title = plot_run.title_of(plot_run.read_summary(os.path.join(d, "timeseries.csv")), d)
            self.assertIn("omega_T = 30 rpm", title)
            self.assertIn("BUCKLED", title)
            write_run(d, 3.0, False)
            title = plot_run.title_of(plot_run.read_summary(os.path.join(d, "timeseries.csv")), d)
            self.assertIn("straight", title)

    def test_helical_run_draws_four_panels_and_bad_tables_exit_2(self):
        with tempfile.TemporaryDirectory() as d:
            write_run(d, 20.0, True)
            png = os.path.join(d, "run.png")
            done = subprocess.run(["/usr/bin/python3", SCRIPT, os.path.join(d, "timeseries.csv"),
                                   png], capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stderr)
            self.assertGreater(os.path.getsize(png), 10000)
            bad = os.path.join(d, "bad.csv")
            with open(bad, "w") as f:
                f.write("time,head_x\n0,0\n")
            done = subprocess.run(["/usr/bin/python3", SCRIPT, bad, png], capture_output=True,
                                  text=True)
            self.assertEqual(done.returncode, 2)
            self.assertIn("missing column", done.stderr)


if __name__ == "__main__":
    unittest.main()
