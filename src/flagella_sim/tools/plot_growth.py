#!/usr/bin/env python3
"""Plot the growth rate of the flagellum's slow tilt against the motor rate.

Usage: plot_growth.py growth_rates.csv out.png

The CSV (flagella_buckling --method growth --out DIR) has the columns omega_rpm, sigma_per_s,
sigma_error_per_s, saturated, decayed, trusted, threshold_rpm, threshold_error_rpm. The figure
shows sigma with its one-sigma error bars (open markers: runs too short to trust their sign;
triangles up: runs whose tilt grew past the small-tilt limit early, sigma a lower bound; down:
runs whose tilt had decayed early, sigma an upper bound), the zero line, and the threshold with
its uncertainty.

Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable input table.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)

from plot_table import EXIT_BAD_INPUT, read_table, save  # noqa: E402

COLUMNS = ("omega_rpm", "sigma_per_s", "sigma_error_per_s", "saturated", "decayed", "trusted",
           "threshold_rpm", "threshold_error_rpm")


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        rows = read_table(argv[1], COLUMNS)
        rate = [float(r["omega_rpm"]) for r in rows]
        sigma = [float(r["sigma_per_s"]) for r in rows]
        error = [float(r["sigma_error_per_s"]) for r in rows]
        saturated = [r["saturated"] == "1" for r in rows]
        decayed = [r["decayed"] == "1" for r in rows]
        trusted = [r["trusted"] == "1" for r in rows]
        threshold = rows[0]["threshold_rpm"]
        threshold_error = rows[0]["threshold_error_rpm"]
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_growth.py: cannot read {argv[1]}: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.axhline(0.0, color="0.6", lw=0.8)
    for x, y, e, sat, dec, ok in zip(rate, sigma, error, saturated, decayed, trusted):
        marker = "^" if sat else ("v" if dec else "o")
        ax.errorbar(x, y, yerr=e, fmt=marker, color="C0", mfc="C0" if ok else "white", capsize=3)
    title = "growth rate of the flagellum's slow tilt"
    if threshold:
        t = float(threshold)
        ax.axvline(t, color="C3", lw=1.0)
        if threshold_error:
            te = float(threshold_error)
            ax.axvspan(t - te, t + te, color="C3", alpha=0.15)
            title += f"\nthreshold {t:.3f} +- {te:.3f} rpm"
    ax.set_xlabel("motor rate omega_T [rpm]")
    ax.set_ylabel("sigma [1/s] (> 0: buckling grows)")
    ax.set_title(title)
    fig.tight_layout()
    return save(fig, argv[2], "plot_growth.py", 120)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
