#!/usr/bin/env python3
"""Plot a recorded path-following session: the reference path (as the controller anchored it)
and the true head path, with the camera fixes. Prints the cross-track error.
  plot_path_following.py SESSION.bag --out square.png [--robot flagella] [--tail-length 0.11]
      [--bound bound.json]
--bound: flagella_tracking_bound's --json for the same path and calibration; the bound is then
printed beside the result, in the title and in the summary."""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from path_tracking import tracking_errors  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import rosbag  # noqa: E402

FINISHED = 2


def read_bag(bag_path, robot):
    ns = "/" + robot + "/"
    reference, head, fixes, status = [], [], [], []
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(
                topics=[ns + "reference_path", ns + "rod_state", ns + "camera_fix", ns + "controller_status"]):
            if topic.endswith("reference_path"):
                reference = [(p.pose.position.x, p.pose.position.y) for p in msg.poses]
            elif topic.endswith("rod_state"):
                p = msg.head_pose.position
                head.append((msg.header.stamp.to_sec(), p.x, p.y))
            elif topic.endswith("camera_fix"):
                fixes.append((msg.point.x, msg.point.y))
            else:
                status.append((msg.header.stamp.to_sec(), msg.mode, msg.controller))
    return reference, head, fixes, status


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bag")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--robot", default="flagella", help="robot namespace in the bag")
    parser.add_argument("--tail-length", type=float, default=0.11, help="l [m], the unit of the printed errors")
    parser.add_argument("--shown-as", help="the plot's path to print (when the caller moves it there afterwards)")
    parser.add_argument("--summary", help="also write the figures as JSON here")
    parser.add_argument("--bound", help="tracking bound JSON (flagella_tracking_bound --json)")
    args = parser.parse_args()
    bound = None
    if args.bound:
        with open(args.bound) as f:
            bound = json.load(f)
        for key in ("bound_max_mm", "bound_rms_mm"):
            if not isinstance(bound.get(key), (int, float)) or not bound[key] > 0:
                sys.exit("plot_path_following: %s: '%s' must be a positive number" % (args.bound, key))

    reference, head, fixes, status = read_bag(args.bag, args.robot)
    if not reference or not head:
        sys.exit("plot_path_following: %s has no reference_path or no rod_state of robot '%s'"
                 % (args.bag, args.robot))
    # The run: from the first RUNNING status to FINISHED (or the end of the bag).
    start = next((t for t, mode, _ in status if mode != 0), head[0][0])
    end = next((t for t, mode, _ in status if mode == FINISHED), head[-1][0])
    run = [(x, y) for t, x, y in head if start <= t <= end]
    max_err, rms_err = tracking_errors(run, reference)
    finished = any(mode == FINISHED for _, mode, _ in status)
    controller = status[-1][2] if status else "unknown"

    fig, ax = plt.subplots(figsize=(7, 7))
    ax.plot([1e3 * x for x, _ in reference], [1e3 * y for _, y in reference], "k--", lw=1.5, label="reference path")
    ax.plot([1e3 * x for _, x, _ in head], [1e3 * y for _, _, y in head], "tab:blue", lw=1.5, label="head path (true)")
    if fixes:
        ax.plot([1e3 * x for x, _ in fixes], [1e3 * y for _, y in fixes], ".", color="tab:orange", ms=2,
                alpha=0.5, label="camera fixes")
    ax.plot(1e3 * head[0][1], 1e3 * head[0][2], "go", label="start")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    bound_text = ""
    if bound:
        bound_text = ("tracking bound max %.1f mm, RMS %.1f mm (result / bound: %.2f, %.2f)"
                      % (bound["bound_max_mm"], bound["bound_rms_mm"], 1e3 * max_err / bound["bound_max_mm"],
                         1e3 * rms_err / bound["bound_rms_mm"]))
    ax.set_title("%s: max cross-track %.1f mm (%.2f l), RMS %.1f mm (%.2f l)%s%s"
                 % (controller, 1e3 * max_err, max_err / args.tail_length, 1e3 * rms_err,
                    rms_err / args.tail_length, "" if finished else ", NOT finished",
                    "\n" + bound_text if bound_text else ""), fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)

    figures = {"controller": controller, "finished": finished, "duration_s": end - start,
               "max_cross_track_m": max_err, "rms_cross_track_m": rms_err,
               "max_cross_track_tail_lengths": max_err / args.tail_length,
               "rms_cross_track_tail_lengths": rms_err / args.tail_length,
               "head_samples": len(run), "camera_fixes": len(fixes)}
    if bound:
        figures.update({"bound_max_cross_track_m": 1e-3 * bound["bound_max_mm"],
                        "bound_rms_cross_track_m": 1e-3 * bound["bound_rms_mm"],
                        "max_over_bound": 1e3 * max_err / bound["bound_max_mm"],
                        "rms_over_bound": 1e3 * rms_err / bound["bound_rms_mm"]})
    print("path following (%s): %s in %.0f s of simulated time; cross-track error max %.1f mm (%.2f l), "
          "RMS %.1f mm (%.2f l)%s; plot: %s"
          % (controller, "complete" if finished else "NOT complete", end - start, 1e3 * max_err,
             max_err / args.tail_length, 1e3 * rms_err, rms_err / args.tail_length,
             "; " + bound_text if bound_text else "", args.shown_as or args.out))
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump(figures, f, indent=2)
    return 0 if finished else 1


if __name__ == "__main__":
    sys.exit(main())
