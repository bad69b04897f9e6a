#!/usr/bin/env python3
"""Plot a motor-speed sweep table produced by the flagella simulator.

Usage: plot_sweep.py table.csv out.png [--title T]

The CSV must have a header with at least the columns
    n_tails, omega_T_rpm, omega_h_rpm, omega_t_rpm, speed_mm_s
(extra columns are ignored; empty cells are treated as missing values). The figure has two
panels, swimming speed v (the summary's: slope of the displacement along the head's initial
axis) and head rotation rate omega_h against the motor rate omega_T, with one line per number
of tails. With a `buckled` column (1/0, helical robot), buckled runs are marked with a red x.

Exit codes: 0 success, 1 output cannot be written, 2 bad command line or unusable input table.
"""

import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be selected first)
import numpy as np  # noqa: E402

REQUIRED_COLUMNS = ("n_tails", "omega_T_rpm", "omega_h_rpm", "omega_t_rpm", "speed_mm_s")
OPTIONAL_COLUMNS = ("buckled",)
EXIT_BAD_INPUT = 2
EXIT_WRITE_FAILED = 1
FIGURE_SIZE_IN = (11.0, 4.5)
DPI = 150


class TableError(Exception):
    """Problem with the input table; the message is shown to the user."""


def parse_cell(text, path, line, column):
    """Float value of a cell, or NaN if it is empty or 'nan'. Raises TableError otherwise."""
    text = (text or "").strip()
    if not text:
        return float("nan")
    try:
        return float(text)
    except ValueError:
        raise TableError(f"{path}:{line}: column '{column}' has non-numeric value '{text}'")


def read_table(path):
    """Required columns of the table as a dict of numpy arrays (NaN = missing)."""
    try:
        handle = open(path, newline="", encoding="utf-8-sig")
    except OSError as err:
        raise TableError(f"cannot open '{path}': {err.strerror}")
    with handle:
        reader = csv.reader(handle)
        header = next(reader, None)
        if header is None:
            raise TableError(f"{path}: file is empty (expected a CSV header)")
        header = [name.strip() for name in header]
        missing = [name for name in REQUIRED_COLUMNS if name not in header]
        if missing:
            raise TableError(
                f"{path}: missing required column{'s' if len(missing) > 1 else ''} "
                f"{', '.join(repr(m) for m in missing)} (header: {', '.join(header)})")
        wanted = REQUIRED_COLUMNS + tuple(n for n in OPTIONAL_COLUMNS if n in header)
        index = {name: header.index(name) for name in wanted}
        columns = {name: [] for name in wanted}
        for row in reader:
            if not any(cell.strip() for cell in row):
                continue  # blank line
            line = reader.line_num
            for name, i in index.items():
                cell = row[i] if i < len(row) else ""
                columns[name].append(parse_cell(cell, path, line, name))
    return {name: np.asarray(values, dtype=float) for name, values in columns.items()}


def tails_label(n):
    return f"n = {int(n)}" if float(n).is_integer() else f"n = {n:g}"


def plot(table, table_path, out_path, title):
    n_tails = table["n_tails"]
    omega_T = table["omega_T_rpm"]
    usable = np.isfinite(n_tails) & np.isfinite(omega_T)
    if not np.any(usable):
        raise TableError(f"{table_path}: no rows with both n_tails and omega_T_rpm present")

    panels = (("speed_mm_s", "v along the initial head axis (mm/s)", "Swimming speed"),
              ("omega_h_rpm", r"$\omega_h$ (rpm)", "Head rotation rate"))
    fig, axes = plt.subplots(1, 2, figsize=FIGURE_SIZE_IN)
    for ax, (column, ylabel, panel_title) in zip(axes, panels):
        y = table[column]
        for n in np.unique(n_tails[usable]):
            sel = usable & (n_tails == n) & np.isfinite(y)
            if not np.any(sel):
                continue
            order = np.argsort(omega_T[sel], kind="stable")
            ax.plot(omega_T[sel][order], y[sel][order], "o-", label=tails_label(n))
        if "buckled" in table:
            marked = usable & np.isfinite(y) & (table["buckled"] == 1)
            if np.any(marked):
                ax.plot(omega_T[marked], y[marked], "x", color="tab:red", markersize=10,
                        markeredgewidth=2, label="buckled (flagellum tilt > criterion)")
        ax.set_xlabel(r"$\omega_T$ (rpm)")
        ax.set_ylabel(ylabel)
        ax.set_title(panel_title)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend()
        else:
            ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center", va="center")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out_path, dpi=DPI)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Plot v and omega_h against omega_T from a sweep table, one line per n_tails.")
    parser.add_argument("table", help="input CSV table")
    parser.add_argument("output", help="output image (e.g. out.png)")
    parser.add_argument("--title", default=None, help="figure title")
    args = parser.parse_args(argv)
    try:
        plot(read_table(args.table), args.table, args.output, args.title)
    except TableError as err:
        print(f"plot_sweep.py: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as err:
        print(f"plot_sweep.py: error: cannot write '{args.output}': {err}", file=sys.stderr)
        return EXIT_WRITE_FAILED
    return 0


if __name__ == "__main__":
    sys.exit(main())
