#!/usr/bin/env python3
"""Plot one run of flagella_run: the head's path (in the plane of the two coordinates it spans
most), its speed and yaw rate over time, and for a robot with a flagellum tilt (the helical one)
the tilt with the buckling criterion, from the run's timeseries.csv (and summary.json beside it,
for the title).

Usage: plot_run.py timeseries.csv out.png

Speeds are drawn with their definitions: v is the forward speed along the head's initial axis
(the summary's v is its slope over the steady window), |v| the magnitude of the head's
instantaneous velocity, which includes the wobble of a spinning head.

Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable input table.
"""

import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

REQUIRED_COLUMNS = ("time", "head_x", "head_y", "head_z", "head_axis_x", "head_axis_y",
                    "head_axis_z", "speed", "yaw_rate")
OPTIONAL_COLUMNS = ("flagellum_tilt",)
SLOPE_WINDOW_S = 2.0  # forward speed: least-squares slope of the displacement over this window


def read_table(path):
    """Columns of the table as lists of floats; raises ValueError naming file and row."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        names = reader.fieldnames or []
        missing = [c for c in REQUIRED_COLUMNS if c not in names]
        if missing:
            raise ValueError("%s: missing column(s) %s" % (path, ", ".join(missing)))
        wanted = REQUIRED_COLUMNS + tuple(c for c in OPTIONAL_COLUMNS if c in names)
        columns = {c: [] for c in wanted}
        for row_number, row in enumerate(reader, start=2):
            for c in wanted:
                try:
                    columns[c].append(float(row[c]))
                except (TypeError, ValueError):
                    raise ValueError("%s:%d: %s is not a number: %r" % (path, row_number, c, row[c]))
    if not columns["time"]:
        raise ValueError("%s: no rows" % path)
    return columns


def read_summary(table_path):
    """summary.json beside the table, or {} (the plot then has no verdict in its title)."""
    path = os.path.join(os.path.dirname(os.path.abspath(table_path)), "summary.json")
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def forward_displacement(t):
    """-(x - x_0) . a_0: displacement head first along the initial head axis a_0 [m]."""
    a0 = [t["head_axis_" + c][0] for c in "xyz"]
    x0 = [t["head_" + c][0] for c in "xyz"]
    return [-sum((t["head_" + c][i] - x0[k]) * a0[k] for k, c in enumerate("xyz"))
            for i in range(len(t["time"]))]


def sliding_slope(times, values, window):
    """Least-squares slope of values over a centred window of `window` seconds at each sample."""
    slopes, lo, hi, n = [], 0, 0, len(times)
    for i, ti in enumerate(times):
        while lo < n and times[lo] < ti - window / 2:
            lo += 1
        while hi < n and times[hi] <= ti + window / 2:
            hi += 1
        ts, vs = times[lo:hi], values[lo:hi]
        if len(ts) < 3:
            slopes.append(float("nan"))
            continue
        tm, vm = sum(ts) / len(ts), sum(vs) / len(vs)
        den = sum((a - tm) ** 2 for a in ts)
        slopes.append(sum((a - tm) * (b - vm) for a, b in zip(ts, vs)) / den if den > 0 else 0.0)
    return slopes


def title_of(summary, table_path):
    """Config, robot, motor rate and, for a robot whose summary has a buckling verdict, it."""
    if not summary:
        return os.path.basename(table_path)
    parts = [os.path.basename(str(summary.get("config", table_path))), str(summary.get("robot", ""))]
    if "omega_T_rpm" in summary:
        parts.append("omega_T = %.3g rpm" % summary["omega_T_rpm"])
    if "flagellum_tilt_max_deg" in summary:
        verdict = "BUCKLED" if summary.get("buckled") else "straight"
        parts.append("%s: flagellum tilt max %.2f deg (criterion %.0f deg)" % (
            verdict, summary["flagellum_tilt_max_deg"], summary.get("buckling_tilt_deg", 15.0)))
    return ", ".join(p for p in parts if p)


def draw_path(ax, t):
    # the two world axes along which the head moved most (a granular robot swims along z)
    span = {a: max(t["head_" + a]) - min(t["head_" + a]) for a in "xyz"}
    first, second = sorted(sorted("xyz", key=lambda a: -span[a])[:2])
    ax.plot([1e3 * v for v in t["head_" + first]], [1e3 * v for v in t["head_" + second]],
            "tab:blue")
    ax.plot(1e3 * t["head_" + first][0], 1e3 * t["head_" + second][0], "go", label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("%s [mm]" % first)
    ax.set_ylabel("%s [mm]" % second)
    ax.set_title("head path, %s-%s plane" % (first, second))
    ax.legend(fontsize=8)


def draw_speed(ax, t, summary):
    forward = sliding_slope(t["time"], forward_displacement(t), SLOPE_WINDOW_S)
    ax.plot(t["time"], [1e3 * v for v in t["speed"]], color="0.7", lw=0.8,
            label="|v| of the head, instantaneous")
    ax.plot(t["time"], [1e3 * v for v in forward], "tab:blue",
            label="v along the initial head axis (slope over %.0f s)" % SLOPE_WINDOW_S)
    if "speed_mm_s" in summary and "steady_window_s" in summary:
        a, b = summary["steady_window_s"]
        ax.plot([a, b], [summary["speed_mm_s"]] * 2, "k--",
                label="summary v = %.4g mm/s (steady window)" % summary["speed_mm_s"])
    ax.set_xlabel("t [s]")
    ax.set_ylabel("speed [mm/s]")
    ax.legend(fontsize=7)


def draw_tilt(ax, t, summary):
    ax.plot(t["time"], [math.degrees(v) for v in t["flagellum_tilt"]], "tab:red")
    criterion = summary.get("buckling_tilt_deg")
    if criterion is not None:
        ax.axhline(criterion, color="k", ls=":", label="buckled above %.0f deg" % criterion)
        ax.legend(fontsize=7)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("flagellum tilt from the head axis [deg]")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("table")
    parser.add_argument("png")
    args = parser.parse_args()
    try:
        t = read_table(args.table)
    except (OSError, ValueError) as e:
        print("plot_run: %s" % e, file=sys.stderr)
        return 2
    summary = read_summary(args.table)
    # the tilt panel for a robot with a flagellum tilt (its summary has the buckling verdict; without
    # a summary, a tilt column that is not all zero)
    tilted = "flagellum_tilt" in t and ("flagellum_tilt_max_deg" in summary or
                                        any(v != 0.0 for v in t["flagellum_tilt"]))
    panels = 4 if tilted else 3
    fig, axes = plt.subplots(1, panels, figsize=(4.4 * panels, 4.4))
    draw_path(axes[0], t)
    draw_speed(axes[1], t, summary)
    axes[2].plot(t["time"], [math.degrees(w) for w in t["yaw_rate"]], "tab:orange")
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel("yaw rate [deg/s]")
    if tilted:
        draw_tilt(axes[3], t, summary)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title_of(summary, args.table), fontsize=10)
    fig.tight_layout()
    try:
        fig.savefig(args.png, dpi=120)
    except OSError as e:
        print("plot_run: cannot write %s: %s" % (args.png, e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
