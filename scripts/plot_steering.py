#!/usr/bin/env python3
"""Plot 3-D waypoint steering runs written by flagella_steer (--csv, --json).

The left panel shows, in millimetres, the true head path (solid; for a single run coloured by
controller mode), the controller's estimate (thin dashed), the numbered waypoints with their
tolerance spheres and the start point. Beside it the top (x-y) and side (x-z) views, to scale,
with the tolerance circles; on the right: motor rate [rpm], slider position [mm] and head height
[mm] against time [s], from t = 0 (the start frame's course is measured while "waiting"). The
buckle_turn mode is split into the buckle cycles (the motor off its cruise rate) and the cruise between them (waiting for the
flagellum's phase), told apart by the motor rate.

  plot_steering.py RUN.csv [RUN2.csv ...] [--json RUN.json] --out PLOT.png
                   [--title TEXT] [--tolerance-mm 18]
  plot_steering.py --bag STEERING.bag [--robot flagella] --out PLOT.png

A bag recorded by launch/steering_3d.launch record:=true gives the same figure: the true path
from rod_state, the estimate, mode, motor and slider commands from steering_status, the
waypoints and their tolerance from waypoint_markers; misses are measured on the true path.

Several CSVs are overlaid and labelled by file stem; --json belongs to the first run (the
waypoints are the same for all). The tolerance comes from the JSON's "tolerance_mm" if it has
one, otherwise from --tolerance-mm. Exits 2 with a one-line message if an input is missing,
empty or lacks a column.
"""
import argparse
import csv
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.lines import Line2D
except ImportError as missing_module:
    sys.exit("plot_steering: %s under %s; run it with /usr/bin/python3 (Debian's "
             "python3-matplotlib, python3-numpy)" % (missing_module, sys.executable))

COLUMNS = ["time", "x", "y", "z", "est_x", "est_y", "est_z", "motor", "slider", "mode"]
NUMERIC = COLUMNS[:-1]
MODE_COLOURS = {
    "waiting": "tab:gray",
    "cruise": "tab:blue",
    "buckle_turn": "tab:orange",
    "buckle cycle": "tab:orange",
    "buckle_turn, waiting for phase": "gold",
    "mass_transformer": "tab:green",
    "finished": "tab:purple",
    "fault": "tab:red",
}
RAD_S_TO_RPM = 60.0 / (2.0 * math.pi)
MM = 1e3


class InputError(Exception):
    """A problem with an input file; the message names the file."""


class Run:
    """One run's samples as numpy arrays (SI units as in the CSV) plus its label."""

    def __init__(self, label, columns, modes):
        self.label = label
        self.time = columns["time"]
        self.true_mm = np.column_stack([columns[k] for k in ("x", "y", "z")]) * MM
        self.est_mm = np.column_stack([columns[k] for k in ("est_x", "est_y", "est_z")]) * MM
        self.rpm = columns["motor"] * RAD_S_TO_RPM
        self.slider_mm = columns["slider"] * MM
        self.modes = split_buckle_turns(modes, self.rpm)


def split_buckle_turns(modes, rpm, tolerance=0.05):
    """buckle_turn samples at the cruise rate (the median rate of the cruise samples and of the
    start frame's course measurement, 'waiting') are the wait for the flagellum's phase, the
    others the buckle cycle itself."""
    cruise = [abs(r) for m, r in zip(modes, rpm) if m in ("cruise", "waiting") and r != 0.0]
    if not cruise:
        return list(modes)
    rate = float(np.median(cruise))
    split = []
    for m, r in zip(modes, rpm):
        if m == "buckle_turn":
            m = ("buckle_turn, waiting for phase" if abs(abs(r) - rate) <= tolerance * max(rate, 1e-9)
                 else "buckle cycle")
        split.append(m)
    return split


def read_run(path):
    """Read a flagella_steer CSV into a Run; raises InputError on a bad file."""
    if not os.path.isfile(path):
        raise InputError("%s: no such file" % path)
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames or []
        if not header:
            raise InputError("%s: empty file" % path)
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            raise InputError("%s: missing column(s) %s (expected header %s)"
                             % (path, ", ".join(missing), ",".join(COLUMNS)))
        rows = list(reader)
    if not rows:
        raise InputError("%s: no data rows" % path)
    values = {c: [] for c in NUMERIC}
    modes = []
    for line, row in enumerate(rows, start=2):
        try:
            for c in NUMERIC:
                values[c].append(float(row[c]))
        except (TypeError, ValueError):
            raise InputError("%s: line %d: bad number in column %s" % (path, line, c))
        modes.append((row["mode"] or "").strip())
    columns = {c: np.array(v) for c, v in values.items()}
    label = os.path.splitext(os.path.basename(path))[0]
    return Run(label, columns, modes)


def read_summary(path):
    """Read the flagella_steer JSON result; raises InputError on a bad file."""
    if not os.path.isfile(path):
        raise InputError("%s: no such file" % path)
    try:
        with open(path) as f:
            summary = json.load(f)
    except ValueError as e:
        raise InputError("%s: not valid JSON (%s)" % (path, e))
    if not isinstance(summary, dict):
        raise InputError("%s: expected a JSON object" % path)
    return summary


def read_bag_run(path, robot, sample_interval=0.5):
    """A Run and a summary from a recorded steering session; raises InputError on a bad bag."""
    if not os.path.isfile(path):
        raise InputError("%s: no such file" % path)
    try:
        import rosbag
    except ImportError:
        raise InputError("reading a bag needs ROS's rosbag module: run with /usr/bin/python3 "
                         "after sourcing devel/setup.bash")
    ns = "/" + robot + "/"
    head, status, waypoints, tolerance = [], [], [], None
    topics = [ns + "rod_state", ns + "steering_status", ns + "waypoint_markers"]
    try:
        with rosbag.Bag(path) as bag:
            for topic, msg, _ in bag.read_messages(topics=topics):
                if topic.endswith("rod_state"):
                    p = msg.head_pose.position
                    head.append((msg.header.stamp.to_sec(), p.x, p.y, p.z))
                elif topic.endswith("steering_status"):
                    e = msg.estimated_position
                    status.append((msg.header.stamp.to_sec(), e.x, e.y, e.z, msg.motor_command,
                                   msg.slider_command, msg.mode_name))
                else:
                    spheres = [m for m in msg.markers if m.ns == "waypoints"]
                    waypoints = [(m.pose.position.x, m.pose.position.y, m.pose.position.z)
                                 for m in sorted(spheres, key=lambda m: m.id)]
                    if spheres:
                        tolerance = 0.5 * spheres[0].scale.x
    except Exception as e:  # rosbag raises several unrelated types for a bad file
        raise InputError("%s: cannot read the bag (%s)" % (path, e))
    if not head or not status:
        raise InputError("%s: no rod_state or no steering_status of robot '%s' (record the "
                         "session with launch/steering_3d.launch record:=true)" % (path, robot))
    h = np.array([row[:4] for row in head])
    kept, next_time = [], -math.inf
    for row in status:  # the controller runs at the IMU's rate: one sample per interval
        if row[0] >= next_time:
            kept.append(row)
            next_time = row[0] + sample_interval
    t = np.array([row[0] for row in kept])
    columns = {"time": t - h[0, 0]}
    for k, axis in enumerate("xyz"):
        columns[axis] = np.interp(t, h[:, 0], h[:, 1 + k])
        columns["est_" + axis] = np.array([row[1 + k] for row in kept])
    columns["motor"] = np.array([row[4] for row in kept])
    columns["slider"] = np.array([row[5] for row in kept])
    run = Run(os.path.splitext(os.path.basename(path))[0], columns, [row[6] for row in kept])
    summary = {"mission": "%s (recorded session)" % os.path.basename(path),
               "controller": "mass_transformer", "time_s": float(h[-1, 0] - h[0, 0])}
    if waypoints:
        w = np.array(waypoints)
        misses = [float(np.min(np.linalg.norm(h[:, 1:] - p, axis=1))) * MM for p in w]
        summary.update({"waypoints_m": w.tolist(), "tolerance_mm": tolerance * MM,
                        "miss_mm": misses, "total": len(misses), "max_miss_mm": max(misses),
                        "reached": sum(m <= tolerance * MM for m in misses)})
    return run, summary


def waypoints_mm(summary):
    """The waypoints [mm] as an (N, 3) array (empty without a JSON)."""
    points = (summary or {}).get("waypoints_m") or []
    return np.array(points, dtype=float).reshape(-1, 3) * MM


def format_mm(value):
    return "n/a" if value is None else "%.1f" % value


def outcome(summary):
    """'reached R of N, max miss M mm' from the JSON."""
    return "reached %s of %s, max miss %s mm" % (summary.get("reached", "?"),
                                                  summary.get("total", "?"),
                                                  format_mm(summary.get("max_miss_mm")))


def figure_title(args, summary):
    """The title: --title (or the mission) and, with a JSON, the outcome."""
    lines = []
    heading = args.title or (summary or {}).get("mission")
    if heading:
        lines.append(heading)
    if summary:
        time_s = summary.get("time_s")
        simulated = "" if time_s is None else ", %.1f s simulated" % time_s
        controller = summary.get("controller")
        prefix = "%s: " % controller if controller else ""
        lines.append(prefix + outcome(summary) + simulated)
    return "\n".join(lines) if lines else "steering run"


def mode_segments(modes):
    """Yield (mode, start, end) for runs of equal mode; end is inclusive of the next sample so
    that consecutive segments join up."""
    start = 0
    for i in range(1, len(modes) + 1):
        if i == len(modes) or modes[i] != modes[start]:
            yield modes[start], start, min(i, len(modes) - 1)
            start = i


def draw_path_by_mode(ax, run):
    """The true path of a single run, each segment coloured by its mode; returns legend handles."""
    seen = []
    p = run.true_mm
    for mode, a, b in mode_segments(run.modes):
        colour = MODE_COLOURS.get(mode, "black")
        ax.plot(p[a:b + 1, 0], p[a:b + 1, 1], p[a:b + 1, 2], color=colour, lw=2.0)
        if mode not in seen:
            seen.append(mode)
    return [Line2D([], [], color=MODE_COLOURS.get(m, "black"), lw=2.0, label=m) for m in seen]


def draw_sphere(ax, centre, radius, colour):
    """A wireframe sphere of the given radius [mm] around centre [mm]."""
    u, v = np.mgrid[0:2 * np.pi:16j, 0:np.pi:9j]
    ax.plot_wireframe(centre[0] + radius * np.cos(u) * np.sin(v),
                      centre[1] + radius * np.sin(u) * np.sin(v),
                      centre[2] + radius * np.cos(v),
                      color=colour, lw=0.4, alpha=0.35)


def waypoint_colour(index, misses, tolerance_mm):
    """Green if the JSON's miss distance is within tolerance, red if not, black if unknown."""
    if index >= len(misses):
        return "black"
    miss = misses[index]  # null: never came near (infinite miss)
    return "tab:green" if miss is not None and miss <= tolerance_mm else "tab:red"


def draw_waypoints(ax, points, tolerance_mm, misses):
    """Numbered waypoint markers with tolerance spheres, coloured by reached/missed."""
    for i, p in enumerate(points):
        colour = waypoint_colour(i, misses, tolerance_mm)
        draw_sphere(ax, p, tolerance_mm, colour)
        ax.scatter(*p, marker="X", s=70, color=colour, depthshade=False)
        ax.text(p[0], p[1], p[2] + 0.35 * tolerance_mm, " %d" % (i + 1), fontsize=11,
                fontweight="bold", color=colour)


def set_equal_aspect(ax, arrays, margin_mm, min_fraction=0.4):
    """Axis limits covering all points (plus margin) with a box aspect matching the ranges, so
    a millimetre is as long on every axis. An axis narrower than min_fraction of the widest is
    widened about its centre so that the box stays legible."""
    allp = np.vstack([a for a in arrays if len(a)])
    allp = allp[np.all(np.isfinite(allp), axis=1)]
    lo, hi = allp.min(axis=0) - margin_mm, allp.max(axis=0) + margin_mm
    span = np.maximum(hi - lo, min_fraction * np.max(hi - lo))
    span = np.maximum(span, 1e-6)
    centre = 0.5 * (lo + hi)
    lo, hi = centre - 0.5 * span, centre + 0.5 * span
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(span))


def plot_3d(ax, runs, points, tolerance_mm, misses):
    """The 3-D panel: paths, estimates, waypoints, start."""
    handles = []
    if len(runs) == 1:
        handles += draw_path_by_mode(ax, runs[0])
        colours = ["dimgray"]
    else:
        colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for k, run in enumerate(runs):
            p = run.true_mm
            ax.plot(p[:, 0], p[:, 1], p[:, 2], color=colours[k % len(colours)], lw=2.0,
                    label=run.label)
        handles += [Line2D([], [], color=colours[k % len(colours)], lw=2.0, label=r.label)
                    for k, r in enumerate(runs)]
    for k, run in enumerate(runs):
        e = run.est_mm
        ax.plot(e[:, 0], e[:, 1], e[:, 2], color=colours[k % len(colours)], lw=0.8, ls="--")
    handles.append(Line2D([], [], color="dimgray", lw=0.8, ls="--", label="estimate"))
    start = runs[0].true_mm[0]
    ax.scatter(*start, marker="o", s=60, color="black", depthshade=False)
    ax.text(*start, "  start", fontsize=9)
    handles.append(Line2D([], [], marker="o", color="black", ls="", label="start"))
    draw_waypoints(ax, points, tolerance_mm, misses)
    if len(points):
        handles.append(Line2D([], [], marker="X", color="black", ls="",
                              label="waypoint (±%.0f mm)" % tolerance_mm))
    set_equal_aspect(ax, [r.true_mm for r in runs] + [r.est_mm for r in runs] + [points],
                     tolerance_mm if len(points) else 2.0)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.legend(handles=handles, loc="upper left", fontsize=9)


def plot_view(ax, runs, points, tolerance_mm, misses, axes_pair, title):
    """A 2-D view to scale (equal aspect): paths, estimates, tolerance circles, start."""
    i, j = axes_pair
    names = "xyz"
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, run in enumerate(runs):
        p, e = run.true_mm, run.est_mm
        if len(runs) == 1:
            for mode, a, b in mode_segments(run.modes):
                ax.plot(p[a:b + 1, i], p[a:b + 1, j], color=MODE_COLOURS.get(mode, "black"),
                        lw=1.6)
        else:
            ax.plot(p[:, i], p[:, j], color=colours[k % len(colours)], lw=1.6)
        ax.plot(e[:, i], e[:, j], color="dimgray" if len(runs) == 1 else colours[k % len(colours)],
                lw=0.7, ls="--")
    for n, c in enumerate(points):
        colour = waypoint_colour(n, misses, tolerance_mm)
        ax.add_patch(plt.Circle((c[i], c[j]), tolerance_mm, fill=False, color=colour, lw=1.0))
        ax.plot(c[i], c[j], "X", color=colour, ms=7)
        ax.annotate(str(n + 1), (c[i], c[j]), textcoords="offset points", xytext=(4, 4),
                    color=colour, fontsize=9, fontweight="bold")
    start = runs[0].true_mm[0]
    ax.plot(start[i], start[j], "o", color="black", ms=5)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("%s [mm]" % names[i])
    ax.set_ylabel("%s [mm]" % names[j])
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)


def plot_time_series(axes, runs):
    """Motor rate, slider position and height against time, one line per run."""
    series = [("motor [rpm]", lambda r: r.rpm), ("slider [mm]", lambda r: r.slider_mm),
              ("height z [mm]", lambda r: r.true_mm[:, 2])]
    for ax, (ylabel, values) in zip(axes, series):
        for run in runs:
            ax.plot(run.time, values(run), lw=1.2, label=run.label if len(runs) > 1 else None)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlabel("time [s]")
    if len(runs) > 1:
        axes[0].legend(fontsize=8)


def make_figure(runs, summary, tolerance_mm, title):
    """The whole figure: the 3-D panel left, top and side views, three stacked time plots."""
    fig = plt.figure(figsize=(18, 9), dpi=100)
    grid = fig.add_gridspec(3, 3, width_ratios=[2.0, 1.2, 1.0], wspace=0.25, hspace=0.35)
    ax3d = fig.add_subplot(grid[:, 0], projection="3d")
    misses = (summary or {}).get("miss_mm") or []
    points = waypoints_mm(summary)
    plot_3d(ax3d, runs, points, tolerance_mm, misses)
    plot_view(fig.add_subplot(grid[0:2, 1]), runs, points, tolerance_mm, misses, (0, 1),
              "top view (circles: the tolerance, to scale)")
    plot_view(fig.add_subplot(grid[2, 1]), runs, points, tolerance_mm, misses, (0, 2),
              "side view")
    time_axes = [fig.add_subplot(grid[0, 2])]
    time_axes += [fig.add_subplot(grid[i, 2], sharex=time_axes[0]) for i in (1, 2)]
    plot_time_series(time_axes, runs)
    fig.suptitle(title, fontsize=13)
    fig.subplots_adjust(left=0.02, right=0.98, top=0.91, bottom=0.07)
    return fig


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="*", help="flagella_steer --csv output (repeat to overlay)")
    parser.add_argument("--bag", help="a session recorded by launch/steering_3d.launch record:=true")
    parser.add_argument("--robot", default="flagella", help="robot namespace in the bag")
    parser.add_argument("--json", help="flagella_steer --json output of the first run")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--title", help="title line (default: the JSON's mission)")
    parser.add_argument("--tolerance-mm", type=float, default=18.0,
                        help="waypoint tolerance [mm] if the JSON has no tolerance_mm")
    args = parser.parse_args(argv)
    if bool(args.csv) == bool(args.bag):
        parser.error("give flagella_steer CSV files or one --bag, not both or neither")
    if args.bag and args.json:
        parser.error("--json belongs to a CSV run; a bag carries its own waypoints")
    return args


def main(argv=None):
    args = parse_args(argv)
    try:
        if args.bag:
            run, summary = read_bag_run(args.bag, args.robot)
            runs = [run]
        else:
            runs = [read_run(path) for path in args.csv]
            summary = read_summary(args.json) if args.json else None
    except InputError as e:
        print("plot_steering: %s" % e, file=sys.stderr)
        return 2
    tolerance_mm = (summary or {}).get("tolerance_mm") or args.tolerance_mm
    fig = make_figure(runs, summary, tolerance_mm, figure_title(args, summary))
    try:
        fig.savefig(args.out)
    except OSError as e:
        print("plot_steering: %s: cannot write (%s)" % (args.out, e.strerror or e), file=sys.stderr)
        return 2
    finally:
        plt.close(fig)
    print("plot: %s (%s)" % (args.out, outcome(summary)) if summary else "plot: %s" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
