#!/usr/bin/env python3
"""Plot a flagella_sweep result table (results.csv) of one or two parameters.

Usage: plot_sweep_table.py results.csv out.png --param FIELD [--param FIELD2] [--key KEY ...]
                           [--fixed FIELD ...]

One parameter: one panel per key, the key against the parameter (failed points left out).
Two parameters: one heat map per key over the grid. Without --key, up to four numeric summary
columns are drawn (speeds, rates, thresholds first). Exit codes: 0 success, 1 output cannot be
written, 2 bad command line or unusable table.
"""

import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

RUNNER_COLUMNS = {"index", "status", "exit_code", "error", "wall_s"}
PREFERRED = ("speed_mm_s", "threshold_rpm", "omega_h_rpm", "yaw_rate_rad_s", "reached", "max_miss_mm")
MAX_KEYS = 4


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
                   and "wall" not in c and all(number(r[c]) is not None for r in rows)]
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
    for ax, key in zip(axes[0], keys):
        if len(args.param) == 1:
            pts = sorted((number(r[args.param[0]]), number(r[key])) for r in rows
                         if number(r[args.param[0]]) is not None and number(r[key]) is not None)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-")
            ax.set_xlabel(args.param[0])
            ax.set_ylabel(key)
        else:
            xs = sorted({number(r[args.param[0]]) for r in rows})
            ys = sorted({number(r[args.param[1]]) for r in rows})
            grid = [[math.nan] * len(xs) for _ in ys]
            for r in rows:
                v = number(r[key])
                if v is not None:
                    grid[ys.index(number(r[args.param[1]]))][xs.index(number(r[args.param[0]]))] = v
            image = ax.imshow(grid, origin="lower", aspect="auto", interpolation="nearest")
            ax.set_xticks(range(len(xs)), [f"{x:g}" for x in xs])
            ax.set_yticks(range(len(ys)), [f"{y:g}" for y in ys])
            ax.set_xlabel(args.param[0])
            ax.set_ylabel(args.param[1])
            fig.colorbar(image, ax=ax)
        ax.set_title(key)
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
