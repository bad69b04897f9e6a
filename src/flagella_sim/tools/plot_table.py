"""What the threshold plot scripts share: the exit codes, reading a CSV table with the columns a
plot needs, and writing the figure (plot_buckling.py, plot_growth.py)."""

import csv
import sys

EXIT_BAD_INPUT = 2
EXIT_WRITE_FAILED = 1


def read_table(path, columns):
    """The rows of a CSV table as dicts; ValueError if it has no rows or lacks a column."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError("no rows")
    for column in columns:
        if column not in rows[0]:
            raise ValueError("missing column " + column)
    return rows


def save(fig, path, script, dpi):
    """Writes the figure; returns the script's exit code (EXIT_WRITE_FAILED with a message)."""
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as e:
        print("%s: cannot write %s: %s" % (script, path, e), file=sys.stderr)
        return EXIT_WRITE_FAILED
    return 0
