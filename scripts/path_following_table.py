#!/usr/bin/env python3
"""Re-runs the README's path-following table: the interface robot follows the square, the circle
and the triangle (config/paths) once each, with the main job's sensor noise (IMU orientation
0.01 rad, gyro 0.005 rad/s, camera 2 Hz with 2 mm: launch/path_following.launch's defaults) and
seeds 1..N, with the robot's lateral-force coefficient C_yr at 1.4, 2.0 and 2.6 while the
controllers keep the calibration made with 2.0. Per case: the tracking bound of the TRUE robot
(flagella_calibrate on the robot with that C_yr, then flagella_tracking_bound), and the median and
worst over the seeds of the receding-horizon controller (the main job's) and of the line-of-sight
controller (closed_loop), as max / RMS cross-track and as ratios to the bound. Runs
flagella_follow_path (simulator and controller core over LCM memq://, no ROS).

Usage: scripts/path_following_table.py [--jobs N] [--seeds N] [--paths square,circle,triangle]
"""
import argparse
import concurrent.futures
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "devel/bin")
CONFIG = os.path.join(ROOT, "config/interface_path_planning.yaml")
CALIBRATION = os.path.join(ROOT, "config/calibration/interface_path_planning.yaml")
MAIN_JOB_NOISE = ["--imu-orientation-noise", "0.01", "--imu-gyro-noise", "0.005",
                  "--camera-rate", "2", "--camera-noise", "0.002"]
C_YR = [("1.4 (-30 %)", "1.4"), ("2.0 (nominal)", "2.0"), ("2.6 (+30 %)", "2.6")]
MODES = [("receding_horizon", "receding horizon"), ("closed_loop", "line of sight")]
RESULT = re.compile(r"max ([0-9.]+) mm \(([0-9.]+) l\), RMS ([0-9.]+) mm \(([0-9.]+) l\)")
COMPLETE = re.compile(r"path complete")


def run(command):
    out = subprocess.run(command, capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError("%s exited %d:\n%s%s" % (" ".join(command), out.returncode, out.stdout,
                                                   out.stderr))
    return out.stdout


def follow(mode, c_yr, seed, path):
    out = run([os.path.join(BIN, "flagella_follow_path"), CONFIG, "--calibration", CALIBRATION,
               "--path", os.path.join(ROOT, "config/paths/%s.yaml" % path), "--mode", mode,
               "--set", "effects.interface_lateral_force.C_yr=" + c_yr, "--seed", str(seed),
               "--no-bound"] + MAIN_JOB_NOISE)
    m = RESULT.search(out)
    if not m or not COMPLETE.search(out):
        raise RuntimeError("flagella_follow_path %s %s C_yr %s seed %d: no complete result:\n%s"
                           % (mode, path, c_yr, seed, out))
    return float(m.group(1)), float(m.group(3))  # max, RMS [mm]


def bound(c_yr, path, folder):
    """The tracking bound of the robot with this C_yr, from its own calibration."""
    calibration = CALIBRATION
    if c_yr != "2.0":
        calibration = os.path.join(folder, "cyr_%s.yaml" % c_yr)
        if not os.path.exists(calibration):
            run([os.path.join(BIN, "flagella_calibrate"), CONFIG, "-o", calibration,
                 "--set", "effects.interface_lateral_force.C_yr=" + c_yr])
    result = os.path.join(folder, "bound_%s_%s.json" % (c_yr, path))
    run([os.path.join(BIN, "flagella_tracking_bound"), "--calibration", calibration,
         "--path", os.path.join(ROOT, "config/paths/%s.yaml" % path), "--json", result])
    with open(result) as f:
        figures = json.load(f)
    return figures["bound_max_mm"], figures["bound_rms_mm"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--paths", default="square,circle,triangle")
    args = parser.parse_args()
    if not 1 <= args.jobs <= 64:
        parser.error("--jobs must be in [1, 64]")
    if not 1 <= args.seeds <= 100:
        parser.error("--seeds must be in [1, 100]")
    paths = args.paths.split(",")
    for p in paths:
        if not os.path.exists(os.path.join(ROOT, "config/paths/%s.yaml" % p)):
            parser.error("--paths: no config/paths/%s.yaml" % p)
    seeds = range(1, args.seeds + 1)
    with tempfile.TemporaryDirectory() as folder, \
            concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        # Calibrations first (the bounds of one C_yr share one), then the bounds and the runs.
        list(pool.map(lambda c: bound(c, paths[0], folder), [v for _, v in C_YR]))
        cases = [(p, v) for p in paths for _, v in C_YR]
        bounds = dict(zip(cases, pool.map(lambda c: bound(c[1], c[0], folder), cases)))
        runs = [(m, v, s, p) for p in paths for _, v in C_YR for m, _ in MODES for s in seeds]
        results = dict(zip(runs, pool.map(lambda r: follow(*r), runs)))

    print("| path | robot's C_yr | bound max / RMS | %s |" % " | ".join(
        "%s max / RMS, median (worst) of %d seeds" % (label, args.seeds) for _, label in MODES))
    print("|---|---|---|%s" % ("---|" * len(MODES)))
    worst_ratio = {}
    for p in paths:
        for label, v in C_YR:
            b = bounds[(p, v)]
            cells = []
            for mode, _ in MODES:
                maxes = [results[(mode, v, s, p)][0] for s in seeds]
                rmses = [results[(mode, v, s, p)][1] for s in seeds]
                cells.append("%.1f (%.1f) / %.1f (%.1f) mm = %.2f (%.2f) / %.2f (%.2f) x bound"
                             % (statistics.median(maxes), max(maxes), statistics.median(rmses), max(rmses),
                                statistics.median(maxes) / b[0], max(maxes) / b[0],
                                statistics.median(rmses) / b[1], max(rmses) / b[1]))
                worst_ratio[(mode, v)] = max(worst_ratio.get((mode, v), 0.0),
                                             statistics.median(maxes) / b[0],
                                             statistics.median(rmses) / b[1])
            print("| %s | %s | %.1f / %.1f mm | %s |" % (p, label, b[0], b[1], " | ".join(cells)))
    print()
    for mode, label in MODES:
        print("%s: largest median ratio to the bound, nominal %.2f, with the model error %.2f"
              % (label, worst_ratio[(mode, "2.0")],
                 max(worst_ratio[(mode, "1.4")], worst_ratio[(mode, "2.6")])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
