#!/usr/bin/env python3
"""Plot one run of flagella_run: the head's path (in the plane of the two coordinates it spans
most) and its speed and yaw rate over time, from the run's timeseries.csv.

Usage: plot_run.py timeseries.csv out.png

Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable input table.
"""

import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

REQUIRED_COLUMNS = ("time", "head_x", "head_y", "head_z", "speed", "yaw_rate")


def read_table(path):
    """Columns of the table as lists of floats; raises ValueError naming file and row."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in REQUIRED_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise ValueError("%s: missing column(s) %s" % (path, ", ".join(missing)))
        columns = {c: [] for c in REQUIRED_COLUMNS}
        for row_number, row in enumerate(reader, start=2):
            for c in REQUIRED_COLUMNS:
                try:
                    columns[c].append(float(row[c]))
                except (TypeError, ValueError):
                    raise ValueError("%s:%d: %s is not a number: %r" % (path, row_number, c, row[c]))
    if not columns["time"]:
        raise ValueError("%s: no rows" % path)
    return columns


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
    fig, (ax_path, ax_speed, ax_yaw) = plt.subplots(1, 3, figsize=(13.0, 4.2))
    # the two world axes along which the head moved most (a granular robot swims along z)
    span = {a: max(t["head_" + a]) - min(t["head_" + a]) for a in "xyz"}
    first, second = sorted(sorted("xyz", key=lambda a: -span[a])[:2])
    ax_path.plot([1e3 * v for v in t["head_" + first]], [1e3 * v for v in t["head_" + second]],
                 "tab:blue")
    ax_path.plot(1e3 * t["head_" + first][0], 1e3 * t["head_" + second][0], "go", label="start")
    ax_path.set_aspect("equal", adjustable="datalim")
    ax_path.set_xlabel("%s [mm]" % first)
    ax_path.set_ylabel("%s [mm]" % second)
    ax_path.set_title("head path, %s-%s plane" % (first, second))
    ax_path.legend(fontsize=8)
    ax_speed.plot(t["time"], [1e3 * v for v in t["speed"]], "tab:blue")
    ax_speed.set_xlabel("t [s]")
    ax_speed.set_ylabel("speed [mm/s]")
    ax_yaw.plot(t["time"], [math.degrees(w) for w in t["yaw_rate"]], "tab:orange")
    ax_yaw.set_xlabel("t [s]")
    ax_yaw.set_ylabel("yaw rate [deg/s]")
    for ax in (ax_path, ax_speed, ax_yaw):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    try:
        fig.savefig(args.png, dpi=120)
    except OSError as e:
        print("plot_run: cannot write %s: %s" % (args.png, e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
