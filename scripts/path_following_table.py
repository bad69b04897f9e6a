#!/usr/bin/env python3
"""Re-runs the README's path-following results table: the interface robot follows the 0.3 m
square once, with the main job's sensor noise (IMU orientation 0.01 rad, gyro 0.005 rad/s, camera
2 Hz with 2 mm, seed 1: launch/path_following.launch's defaults), open loop and closed loop, with
the robot's lateral-force coefficient C_yr at 1.4, 2.0 and 2.6 while the controller keeps the
calibration made with 2.0; then, closed loop on the nominal robot without noise, the circle,
the triangle and the open zigzag (config/paths). Runs flagella_follow_path (the simulator and the controller core over
LCM memq://, no ROS) and prints the Markdown table.

Usage: scripts/path_following_table.py [--jobs N] [--seed S]
"""
import argparse
import concurrent.futures
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOL = os.path.join(ROOT, "devel/bin/flagella_follow_path")
MAIN_JOB_NOISE = ["--imu-orientation-noise", "0.01", "--imu-gyro-noise", "0.005",
                  "--camera-rate", "2", "--camera-noise", "0.002"]
C_YR = [("1.4 (-30 %)", "1.4"), ("2.0 (nominal)", "2.0"), ("2.6 (+30 %)", "2.6")]
RESULT = re.compile(r"max ([0-9.]+) mm \(([0-9.]+) l\), RMS ([0-9.]+) mm \(([0-9.]+) l\)")


def follow(mode, c_yr, seed, path="square", noise=MAIN_JOB_NOISE):
    command = [TOOL, os.path.join(ROOT, "config/interface_path_planning.yaml"),
               "--calibration", os.path.join(ROOT, "config/calibration/interface_path_planning.yaml"),
               "--path", os.path.join(ROOT, "config/paths/%s.yaml" % path), "--mode", mode,
               "--set", "effects.interface_lateral_force.C_yr=" + c_yr, "--seed", str(seed)]
    out = subprocess.run(command + noise, capture_output=True, text=True)
    m = RESULT.search(out.stdout)
    if out.returncode != 0 or not m:
        raise RuntimeError("%s exited %d:\n%s%s" % (" ".join(command), out.returncode, out.stdout,
                                                   out.stderr))
    return tuple(float(x) for x in m.groups())  # max mm, max l, rms mm, rms l


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if not 1 <= args.jobs <= 64:
        parser.error("--jobs must be in [1, 64]")
    runs = [(mode, value) for _, value in C_YR for mode in ("open_loop", "closed_loop")]
    shapes = ["circle", "triangle", "zigzag"]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = dict(zip(runs, pool.map(lambda r: follow(r[0], r[1], args.seed), runs)))
        clean = dict(zip(shapes, pool.map(
            lambda p: follow("closed_loop", "2.0", args.seed, path=p, noise=[]), shapes)))
    print("| robot's C_yr (calibration made with 2.0) | open loop max / RMS | closed loop max / RMS "
          "| RMS ratio |")
    print("|---|---|---|---|")
    for label, value in C_YR:
        o, c = results[("open_loop", value)], results[("closed_loop", value)]
        print("| %s | %.1f / %.1f mm (%.2f / %.2f l) | %.1f / %.1f mm (%.2f / %.2f l) | %.1f |"
              % (label, o[0], o[2], o[1], o[3], c[0], c[2], c[1], c[3], o[2] / c[2]))
    print()
    print("Closed loop, nominal, no noise: " + ", ".join(
        "%s max %.1f mm (%.2f l), RMS %.1f mm" % (p, clean[p][0], clean[p][1], clean[p][2])
        for p in shapes) + ".")
    return 0


if __name__ == "__main__":
    sys.exit(main())
