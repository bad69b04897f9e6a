#!/usr/bin/python3
"""Plot a model-discovery report: measured data vs the calibrated baseline model vs the extended
model, one panel per output.
  plot_identification.py REPORT_DIR
Reads REPORT_DIR/plot_data.csv and REPORT_DIR/report.json (written by flagella_identify) and writes
REPORT_DIR/report.png. Exits 1 with a one-line error naming the file on a missing/invalid input."""
import csv
import json
import math
import os
import sys
import textwrap

SYSTEM_PYTHON = "/usr/bin/python3"

try:
    import matplotlib
    import numpy as np
except ImportError:
    # Called as plain `python3`, which may be a pyenv interpreter without matplotlib: retry once
    # with the system python (python3-matplotlib, python3-numpy).
    if (os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON)
            and os.access(SYSTEM_PYTHON, os.X_OK)
            and not os.environ.get("PLOT_IDENTIFICATION_REEXEC")):
        os.environ["PLOT_IDENTIFICATION_REEXEC"] = "1"
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
    print(f"error: matplotlib/numpy not importable by {sys.executable}", file=sys.stderr)
    sys.exit(1)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

OUTPUT_ORDER = ["v", "omega_h", "omega_t", "omega_yr", "R_yr", "tilt", "x", "y", "z",
                "axis_x", "axis_y", "axis_z", "head_turns", "tail_turns"]
RAD_PER_S_TO_RPM = 60.0 / (2.0 * math.pi)
COLUMNS = ["kind", "source", "row", "output", "omega_T_rpm", "session_time_s", "run_time_s",
           "held_out", "data", "sigma", "baseline", "extended"]
FLOAT_COLUMNS = ["omega_T_rpm", "session_time_s", "run_time_s", "data", "sigma", "baseline",
                 "extended"]
EXTENDED_COLOUR = "tab:red"
BASELINE_COLOUR = "0.55"
DATA_COLOUR = "black"
MAX_COLUMNS = 4


class InputError(Exception):
    pass


def display_unit(output):
    """(unit label, scale from SI) as in flagella_identify's displayUnit()."""
    if output == "v":
        return "mm/s", 1e3
    if output in ("omega_h", "omega_t"):
        return "rpm", RAD_PER_S_TO_RPM
    if output == "omega_yr":
        return "rad/s", 1.0
    if output == "tilt":
        return "deg", 180.0 / math.pi
    if output in ("R_yr", "x", "y", "z"):
        return "mm", 1e3
    if output.startswith("axis_"):
        return "", 1.0
    if "turns" in output:
        return "turns", 1.0
    return "", 1.0


def parse_float(text):
    # C++ %g may write nan/inf/-nan; Python's float() accepts those spellings.
    return float(text.strip())


def read_plot_data(path):
    if not os.path.isfile(path):
        raise InputError(f"{path}: file not found")
    rows = []
    try:
        with open(path, newline="") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if header is None:
                raise InputError(f"{path}: empty file")
            header = [h.strip() for h in header]
            missing = [c for c in COLUMNS if c not in header]
            if missing:
                raise InputError(f"{path}: missing column(s) {', '.join(missing)}")
            index = {c: header.index(c) for c in COLUMNS}
            for line_number, fields in enumerate(reader, start=2):
                if not fields or all(not x.strip() for x in fields):
                    continue
                if len(fields) < len(header):
                    raise InputError(f"{path}: line {line_number} has {len(fields)} fields, "
                                     f"expected {len(header)}")
                try:
                    r = {"kind": fields[index["kind"]].strip(),
                         "source": int(fields[index["source"]]),
                         "row": int(fields[index["row"]]),
                         "output": fields[index["output"]].strip(),
                         "held_out": int(fields[index["held_out"]]) != 0}
                    for c in FLOAT_COLUMNS:
                        r[c] = parse_float(fields[index[c]])
                except ValueError as e:
                    raise InputError(f"{path}: line {line_number}: {e}") from None
                if r["kind"] not in ("table", "series"):
                    raise InputError(f"{path}: line {line_number}: unknown kind '{r['kind']}'")
                rows.append(r)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"{path}: {e}") from None
    if not rows:
        raise InputError(f"{path}: no data rows")
    return rows


def read_report(path):
    if not os.path.isfile(path):
        raise InputError(f"{path}: file not found")
    try:
        with open(path) as f:
            report = json.load(f)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise InputError(f"{path}: invalid JSON ({e})") from None
    if not isinstance(report, dict):
        raise InputError(f"{path}: top level is not a JSON object")
    return report


def as_float(value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return float("nan")
    return v


def fmt(value, digits=3):
    return f"{value:.{digits}g}" if math.isfinite(value) else "n/a"


def title_text(report):
    verdict = str(report.get("verdict", "unknown verdict"))
    causes = report.get("named_causes") or []
    if not isinstance(causes, list):
        causes = [causes]
    gain = report.get("gain") if isinstance(report.get("gain"), dict) else {}
    before = as_float(gain.get("held_out_rms_z_before"))
    after = as_float(gain.get("held_out_rms_z_after"))
    g = as_float(gain.get("gain"))
    head = "Verdict: " + verdict
    if causes:
        head += " \u2014 " + " + ".join(str(c) for c in causes)
    gain_text = f"{100.0 * g:+.1f} %" if math.isfinite(g) else "n/a"
    head += f"\nheld-out RMS z {fmt(before)} \u2192 {fmt(after)} (gain {gain_text})"
    return head


def signature_lines(report, width):
    diag = report.get("baseline_diagnosis")
    signatures = diag.get("signatures") if isinstance(diag, dict) else None
    if not isinstance(signatures, list) or not signatures:
        return ["Baseline signatures: none"]
    lines = ["Baseline signatures:"]
    for s in signatures[:3]:
        if not isinstance(s, dict):
            continue
        label = ", ".join(str(s[k]) for k in ("kind", "output") if s.get(k))
        text = (f"[{label}] " if label else "") + str(s.get("text", ""))
        wrapped = textwrap.wrap(text, width=width, subsequent_indent="    ") or [""]
        lines.extend(["\u2022 " + wrapped[0]] + wrapped[1:])
    if len(signatures) > 3:
        lines.append(f"(+{len(signatures) - 3} more in report.md)")
    return lines


def panels_of(rows):
    """[(output, kind)] in display order; an output measured both as table and as series gets two
    panels because their x axes differ."""
    present = []
    for r in rows:
        key = (r["output"], r["kind"])
        if key not in present:
            present.append(key)
    order = {name: i for i, name in enumerate(OUTPUT_ORDER)}
    first_seen = {}
    for output, _ in present:
        first_seen.setdefault(output, len(first_seen))
    # known outputs in the fixed order, unknown ones after them in order of appearance
    return sorted(present, key=lambda k: (order.get(k[0], len(OUTPUT_ORDER) + first_seen[k[0]]),
                                          0 if k[1] == "table" else 1))


def columns(rows, scale):
    """Display-unit arrays of one panel's rows."""
    d = np.array([r["data"] for r in rows]) * scale
    s = np.abs(np.array([r["sigma"] for r in rows]) * scale)
    s = np.where(np.isfinite(s), s, 0.0)
    b = np.array([r["baseline"] for r in rows]) * scale
    e = np.array([r["extended"] for r in rows]) * scale
    return d, s, b, e


def robust_ylim(rows, scale, show_extended):
    """Y limits covering the data (with error bars) and the predictions that are not wildly off
    scale (e.g. the 1 km 'straight swimming' radius R_yr); None if nothing is finite."""
    d, s, b, e = columns(rows, scale)
    lo_d, hi_d = d - s, d + s
    finite = np.isfinite(lo_d) & np.isfinite(hi_d)
    preds = np.concatenate([b, e] if show_extended else [b])
    preds = preds[np.isfinite(preds)]
    if finite.any():
        lo, hi = float(np.min(lo_d[finite])), float(np.max(hi_d[finite]))
    elif preds.size:
        lo, hi = float(np.min(preds)), float(np.max(preds))
    else:
        return None
    span = max(hi - lo, 1e-12, 0.05 * max(abs(lo), abs(hi)))
    allowed_lo, allowed_hi = lo - 1.5 * span, hi + 1.5 * span
    inside = preds[(preds >= allowed_lo) & (preds <= allowed_hi)]
    if inside.size:
        lo, hi = min(lo, float(inside.min())), max(hi, float(inside.max()))
    pad = 0.06 * max(hi - lo, span * 0.5)
    return lo - pad, hi + pad


def off_scale(values, ylim):
    """(values with off-scale entries set to NaN, mask below, mask above)."""
    if ylim is None:
        none = np.zeros(values.shape, dtype=bool)
        return values, none, none
    with np.errstate(invalid="ignore"):
        below, above = values < ylim[0], values > ylim[1]
    return np.where(below | above, np.nan, values), below, above


def mark_off_scale(ax, x, below, above, ylim, colour):
    """Arrow-head markers on the panel edge for predictions beyond the y limits."""
    if ylim is None:
        return 0
    inset = 0.015 * (ylim[1] - ylim[0])
    if above.any():
        ax.plot(x[above], np.full(above.sum(), ylim[1] - inset), "^", color=colour, ms=6,
                ls="none", zorder=6, clip_on=False)
    if below.any():
        ax.plot(x[below], np.full(below.sum(), ylim[0] + inset), "v", color=colour, ms=6,
                ls="none", zorder=6, clip_on=False)
    return int(above.sum() + below.sum())


def plot_table(ax, rows, scale, show_extended, ylim):
    x = np.array([r["omega_T_rpm"] for r in rows])
    d, s, b, e = columns(rows, scale)
    held = np.array([r["held_out"] for r in rows], dtype=bool)
    b_in, b_below, b_above = off_scale(b, ylim)
    e_in, e_below, e_above = off_scale(e, ylim)

    # thin guide lines per table (source) when its omega_T values are unique, so curves read;
    # off-scale predictions break the line
    for src in sorted({r["source"] for r in rows}):
        idx = np.array([i for i, r in enumerate(rows) if r["source"] == src])
        xs = x[idx]
        if idx.size < 2 or np.unique(xs).size != xs.size:
            continue
        order = idx[np.argsort(xs)]
        ax.plot(x[order], b_in[order], "-", color=BASELINE_COLOUR, lw=0.8, alpha=0.7, zorder=2)
        if show_extended:
            ax.plot(x[order], e_in[order], "-", color=EXTENDED_COLOUR, lw=0.8, alpha=0.6,
                    zorder=3)

    measured = np.isfinite(x) & np.isfinite(d)
    for mask, face in ((~held & measured, DATA_COLOUR), (held & measured, "white")):
        if mask.any():
            ax.errorbar(x[mask], d[mask], yerr=s[mask], fmt="o", ms=5, mfc=face,
                        mec=DATA_COLOUR, ecolor=DATA_COLOUR, elinewidth=0.9, capsize=2.5, zorder=4)
    ax.plot(x, b_in, "x", color=BASELINE_COLOUR, ms=7, mew=1.5, ls="none", zorder=5)
    hidden = mark_off_scale(ax, x, b_below, b_above, ylim, BASELINE_COLOUR)
    if show_extended:
        ax.plot(x, e_in, "+", color=EXTENDED_COLOUR, ms=9, mew=1.6, ls="none", zorder=6)
        hidden += mark_off_scale(ax, x, e_below, e_above, ylim, EXTENDED_COLOUR)
    if np.isfinite(d).any() and np.nanmin(d) < 0.0 < np.nanmax(d):
        ax.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    ax.set_xlabel("motor command \u03c9$_T$ [rpm]")
    return hidden


def plot_series(ax, rows, scale, show_extended, ylim):
    sources = sorted({r["source"] for r in rows})
    first_held, t_max, hidden = math.inf, -math.inf, 0
    for src in sources:
        sub = sorted((r for r in rows if r["source"] == src), key=lambda r: r["run_time_s"])
        t = np.array([r["run_time_s"] for r in sub])
        d, _, b, e = columns(sub, scale)
        held = np.array([r["held_out"] for r in sub], dtype=bool)
        if held.any():
            first_held = min(first_held, float(t[held].min()))
        if np.isfinite(t).any():
            t_max = max(t_max, float(np.nanmax(t)))
        b_in, b_below, b_above = off_scale(b, ylim)
        ax.plot(t, d, ".", color=DATA_COLOUR, ms=2.5, alpha=0.75, zorder=3)
        ax.plot(t, b_in, "-", color=BASELINE_COLOUR, lw=1.3, zorder=4)
        hidden += int(b_below.sum() + b_above.sum())
        if show_extended:
            e_in, e_below, e_above = off_scale(e, ylim)
            ax.plot(t, e_in, "-", color=EXTENDED_COLOUR, lw=1.3, zorder=5)
            hidden += int(e_below.sum() + e_above.sum())
    if math.isfinite(first_held) and math.isfinite(t_max):
        ax.axvspan(first_held, max(t_max, first_held), color="tab:orange", alpha=0.12, lw=0,
                   zorder=0)
    ax.set_xlabel("time in run [s]")
    if len(sources) > 1:
        ax.text(0.01, 0.01, f"{len(sources)} runs overlaid", transform=ax.transAxes,
                fontsize=7, color="0.4", va="bottom")
    return hidden


def legend_handles(kinds, extended_differs):
    handles = []
    if "table" in kinds:
        handles += [Line2D([], [], marker="o", color=DATA_COLOUR, ls="none", mfc=DATA_COLOUR,
                           label="data \u00b1 1\u03c3 (training)"),
                    Line2D([], [], marker="o", color=DATA_COLOUR, ls="none", mfc="white",
                           label="data \u00b1 1\u03c3 (held out)")]
    if "series" in kinds:
        handles += [Line2D([], [], marker=".", color=DATA_COLOUR, ls="none", label="series data"),
                    Patch(color="tab:orange", alpha=0.2, label="held-out part of run")]
    handles.append(Line2D([], [], marker="x" if "table" in kinds else None, color=BASELINE_COLOUR,
                          ls="-" if "series" in kinds else "none", mew=1.5,
                          label="calibrated baseline"))
    if extended_differs:
        handles.append(Line2D([], [], marker="+" if "table" in kinds else None,
                              color=EXTENDED_COLOUR, ls="-" if "series" in kinds else "none",
                              ms=9, mew=1.6, label="extended model"))
    else:
        handles.append(Line2D([], [], color="none", label="(extended = baseline: no effect named)"))
    return handles


def make_figure(rows, report, out_path):
    panels = panels_of(rows)
    n = len(panels)
    ncols = min(MAX_COLUMNS, n)
    nrows = int(math.ceil(n / ncols))
    extended_differs = any(
        not (r["extended"] == r["baseline"]
             or (math.isnan(r["extended"]) and math.isnan(r["baseline"]))
             or abs(r["extended"] - r["baseline"]) <= 1e-12 * max(1.0, abs(r["baseline"])))
        for r in rows)

    panel_w, panel_h = 4.0, 3.3
    fig_w = max(8.0, panel_w * ncols)
    title = title_text(report)
    # 8 pt monospace is about 0.067 in per character
    sig_lines = signature_lines(report, int((fig_w - 0.4) / 0.067))
    # header, in inches from the top: title lines, then the legend rows, then the panel titles
    handles = legend_handles({k for _, k in panels}, extended_differs)
    entry_w = max(0.6 + 0.075 * len(h.get_label()) for h in handles)
    legend_cols = max(1, min(len(handles), int((fig_w - 0.4) // entry_w)))
    legend_rows = int(math.ceil(len(handles) / legend_cols))
    legend_top_in = 0.2 + 0.25 * (title.count("\n") + 1)
    header_in = legend_top_in + 0.5 + 0.22 * legend_rows
    footer_in = 0.55 + 0.16 * len(sig_lines)
    fig_h = panel_h * nrows + header_in + footer_in
    fig, axes = plt.subplots(nrows, ncols, figsize=(fig_w, fig_h), dpi=100, squeeze=False)

    for i, (output, kind) in enumerate(panels):
        ax = axes[i // ncols][i % ncols]
        sub = [r for r in rows if r["output"] == output and r["kind"] == kind]
        unit, scale = display_unit(output)
        ylim = robust_ylim(sub, scale, extended_differs)
        plot = plot_table if kind == "table" else plot_series
        hidden = plot(ax, sub, scale, extended_differs, ylim)
        if ylim is not None:
            ax.set_ylim(*ylim)
        if hidden:
            ax.text(0.99, 0.985, f"{hidden} prediction(s) off scale", transform=ax.transAxes,
                    fontsize=7, color="0.35", ha="right", va="top")
        both_kinds = sum(1 for o, _ in panels if o == output) > 1
        held_n = sum(1 for r in sub if r["held_out"])
        name = output + (f" ({kind})" if both_kinds else "")
        ax.set_title(f"{name}   [{len(sub)} pts, {held_n} held out]", fontsize=10)
        ax.set_ylabel(f"{output} [{unit}]" if unit else output)
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.tick_params(labelsize=8)
    for j in range(n, nrows * ncols):
        axes[j // ncols][j % ncols].axis("off")

    fig.suptitle(title, fontsize=13, y=1.0 - 0.12 / fig_h, va="top")
    fig.legend(handles=handles, loc="upper center", ncol=legend_cols, fontsize=9, frameon=False,
               bbox_to_anchor=(0.5, 1.0 - legend_top_in / fig_h))
    fig.text(0.01, 0.01, "\n".join(sig_lines), fontsize=8, family="monospace", va="bottom",
             ha="left", color="0.2")
    top = 1.0 - header_in / fig_h
    bottom = (footer_in + 0.15) / fig_h
    fig.subplots_adjust(left=0.06 if ncols > 2 else 0.09, right=0.985, top=top, bottom=bottom,
                        wspace=0.32, hspace=0.45)
    fig.savefig(out_path, dpi=100)
    plt.close(fig)


def main(argv):
    if len(argv) != 2:
        print("usage: plot_identification.py REPORT_DIR", file=sys.stderr)
        return 1
    directory = argv[1]
    csv_path = os.path.join(directory, "plot_data.csv")
    json_path = os.path.join(directory, "report.json")
    out_path = os.path.join(directory, "report.png")
    try:
        rows = read_plot_data(csv_path)
        report = read_report(json_path)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    try:
        make_figure(rows, report, out_path)
    except OSError as e:
        print(f"error: {out_path}: {e}", file=sys.stderr)
        return 1
    print(f"wrote {out_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
