#!/usr/bin/env python3
"""Plot a flagella_sweep result table (results.csv) of one or two parameters.

Usage: plot_sweep_table.py results.csv out.png --param FIELD [--param FIELD2] [--key KEY ...]
                           [--fixed FIELD ...]

One parameter: one panel per key, the key against the parameter (failed points left out).
Two parameters: one heat map per key over the grid. Without --key, up to four numeric summary
columns that vary over the sweep are drawn (speeds, rates, thresholds first; constants such as
the criterion or the robot's length are left out). Axes carry units: config fields in SI are
shown in the unit a user thinks in (mm, MPa), columns by their suffix (_mm_s, _rpm, _deg, _s).
Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable table.
"""

import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

RUNNER_COLUMNS = {"index", "status", "exit_code", "error", "wall_s"}
PREFERRED = ("speed_mm_s", "buckling_threshold_rpm", "threshold_rpm", "omega_h_rpm", "yaw_rate_rad_s", "reached", "max_miss_mm")
MAX_KEYS = 4

# Config fields a sweep varies: (label, unit, factor from the config's SI value).
FIELD_LABELS = {
    "robot.filament_radius": ("filament radius r0", "mm", 1e3),
    "robot.helix_radius": ("helix radius R_t", "mm", 1e3),
    "robot.pitch": ("pitch lambda", "mm", 1e3),
    "robot.edge_length": ("edge length", "mm", 1e3),
    "robot.hook_length": ("hook length L_h", "mm", 1e3),
    "robot.head_radius": ("head radius", "mm", 1e3),
    "robot.tail_length": ("tail length L", "mm", 1e3),
    "robot.youngs_modulus": ("Young's modulus E", "MPa", 1e-6),
    "robot.pitch_count": ("pitch count", "", 1.0),
    "robot.n_tails": ("number of tails", "", 1.0),
    "motor.omega_rpm": ("motor rate omega_T", "rpm", 1.0),
    "medium.viscosity": ("viscosity mu", "Pa s", 1.0),
    "effects.rss.eps_ratio": ("eps / r0", "", 1.0),
    "simulation.duration": ("run length", "s", 1.0),
    "simulation.dt": ("time step dt", "s", 1.0),
}
# Result columns by suffix: (suffix, unit); the longest matching suffix wins.
SUFFIX_UNITS = (("_mm_s", "mm/s"), ("_rad_s", "rad/s"), ("_rpm", "rpm"), ("_deg", "deg"),
                ("_mm", "mm"), ("_m", "m"), ("_s", "s"))


def field_axis(name):
    """(axis label, factor) of a swept config field."""
    label, unit, factor = FIELD_LABELS.get(name, (name, "", 1.0))
    if name in FIELD_LABELS:
        label = f"{label} ({name})"
    return (f"{label} [{unit}]" if unit else label), factor


def column_label(name):
    """A result column's label with its unit from the suffix: speed_mm_s -> speed [mm/s]."""
    for suffix, unit in SUFFIX_UNITS:
        if name.endswith(suffix) and len(name) > len(suffix):
            return f"{name[:-len(suffix)].replace('_', ' ')} [{unit}]"
    return name.replace("_", " ")


def varies(rows, column):
    values = {number(r[column]) for r in rows}
    return len(values) > 1


def number(text):
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("table")
    parser.add_argument("png")
    parser.add_argument("--param", action="append", required=True)
    parser.add_argument("--key", action="append", default=[])
    parser.add_argument("--fixed", action="append", default=[], help="parameters held fixed (not plotted)")
    args = parser.parse_args()
    if len(args.param) > 2:
        sys.exit("plot_sweep_table: at most two --param")
    with open(args.table, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("status") == "ok"]
    if not rows:
        print("plot_sweep_table: no successful points to plot", file=sys.stderr)
        return 2
    columns = list(rows[0].keys())
    for p in args.param:
        if p not in columns:
            print(f"plot_sweep_table: no column '{p}'", file=sys.stderr)
            return 2
    keys = args.key
    if not keys:
        numeric = [c for c in columns if c not in RUNNER_COLUMNS and c not in args.param
                   and c not in args.fixed
                   and "wall" not in c and all(number(r[c]) is not None for r in rows)
                   and varies(rows, c)]
        keys = [c for c in PREFERRED if c in numeric] + [c for c in numeric if c not in PREFERRED]
        keys = keys[:MAX_KEYS]
    for k in keys:
        if k not in columns:
            print(f"plot_sweep_table: no column '{k}'", file=sys.stderr)
            return 2
    if not keys:
        print("plot_sweep_table: no numeric column to plot", file=sys.stderr)
        return 2
    fig, axes = plt.subplots(1, len(keys), figsize=(4.5 * len(keys), 4.0), squeeze=False)
    x_label, x_factor = field_axis(args.param[0])
    for ax, key in zip(axes[0], keys):
        if len(args.param) == 1:
            pts = sorted((number(r[args.param[0]]) * x_factor, number(r[key])) for r in rows
                         if number(r[args.param[0]]) is not None and number(r[key]) is not None)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-")
            ax.set_xlabel(x_label)
            ax.set_ylabel(column_label(key))
        else:
            y_label, y_factor = field_axis(args.param[1])
            xs = sorted({number(r[args.param[0]]) for r in rows})
            ys = sorted({number(r[args.param[1]]) for r in rows})
            grid = [[math.nan] * len(xs) for _ in ys]
            for r in rows:
                v = number(r[key])
                if v is not None:
                    grid[ys.index(number(r[args.param[1]]))][xs.index(number(r[args.param[0]]))] = v
            image = ax.imshow(grid, origin="lower", aspect="auto", interpolation="nearest")
            ax.set_xticks(range(len(xs)), [f"{x * x_factor:g}" for x in xs])
            ax.set_yticks(range(len(ys)), [f"{y * y_factor:g}" for y in ys])
            ax.set_xlabel(x_label)
            ax.set_ylabel(y_label)
            fig.colorbar(image, ax=ax, label=column_label(key))
        ax.set_title(column_label(key))
        if len(args.param) == 1:
            ax.grid(alpha=0.3)
    fig.tight_layout()
    try:
        fig.savefig(args.png, dpi=120)
    except OSError as e:
        print(f"plot_sweep_table: cannot write {args.png}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
