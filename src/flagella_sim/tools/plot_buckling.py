#!/usr/bin/env python3
"""Plot a buckling-threshold sweep table written by flagella_buckling --sweep.

Usage: plot_buckling.py buckling_sweep.csv out.png

The CSV has the columns parameter, value, buckling_threshold_rpm, bracket_low_rpm,
bracket_high_rpm, runs, found, message. The figure shows the threshold against the swept value
with the final bracket as an error bar; values without a threshold are marked on the axis.

Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable input table.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

from plot_table import EXIT_BAD_INPUT, read_table, save  # noqa: E402

COLUMNS = ("parameter", "value", "buckling_threshold_rpm", "bracket_low_rpm", "bracket_high_rpm")


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        rows = read_table(argv[1], COLUMNS)
    except (OSError, ValueError) as e:
        print("plot_buckling.py: cannot use %s: %s" % (argv[1], e), file=sys.stderr)
        return EXIT_BAD_INPUT
    found = [r for r in rows if r["buckling_threshold_rpm"]]
    missing = [float(r["value"]) for r in rows if not r["buckling_threshold_rpm"]]
    x = [float(r["value"]) for r in found]
    y = [float(r["buckling_threshold_rpm"]) for r in found]
    low = [yi - float(r["bracket_low_rpm"]) for yi, r in zip(y, found)]
    high = [float(r["bracket_high_rpm"]) - yi for yi, r in zip(y, found)]
    fig, ax = plt.subplots(figsize=(6.0, 4.5))
    ax.errorbar(x, y, yerr=[low, high], marker="o", capsize=3, label="threshold (bracket)")
    if missing:
        ax.plot(missing, [0.0] * len(missing), "rx", label="no threshold found")
    ax.set_xlabel(rows[0]["parameter"])
    ax.set_ylabel("buckling threshold [rpm]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return save(fig, argv[2], "plot_buckling.py", 150)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
