#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 12A: critical Courant number against FMPM order k.

    analysis/fig12a.py stability.csv [--low-dissipation low.csv] [-o fig12a]

Reads the table written by `smpm stability` (the CSV behind the figure) and draws two panels
that share the C* axis: (A) FMPM(k), with FLIP and the exact inverse m̃⁻¹ (the limit k → ∞)
as horizontal lines; (B) FMPM(k) blended with FMPM(1) and with FMPM(2), and periodic FMPM(k).
Spectral predictions (minimum over the configurations examined) are dashed with open circles,
bisection over full runs solid with squares, and the values reported in the paper are stars.
With --low-dissipation, a second table (`smpm stability --method simulation
--max-energy-change F`) adds the largest C with low dissipation as dotted lines. A cell "none"
(no C holds) or empty (not searched) leaves a gap. Each panel has one legend for the series
(colours) and one for the methods (line styles). Writes PREFIX.png (a trailing .png of -o is
dropped: -o fig12a.png writes fig12a.png).
"""
import argparse
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402

# Values quoted in FMPM 2026 §3.3 for this bar (simulation, ±0.005).
PAPER = {
    "FMPM(k)": [(1, 0.86), (4, 0.539), (40, 0.25), (80, 0.24)],
    "blended with FMPM(1), α = 0.8": [(80, 0.51)],
    "blended with FMPM(2), α = 0.8": [(80, 0.40)],
    "periodic, C_X = 2": [(80, 0.40)],
}
PAPER_FLIP = 0.84
FLIP_COLOUR, EXACT_COLOUR = "#555555", "#882255"
# How each method is drawn: (line style, marker, marker face).
STYLE = {"spectral": ("--", "o", "none"), "simulation": ("-", "s", None),
         "simulation, low dissipation": (":", "x", None)}


def num(s):
    """A table cell as a number: NaN where it is empty (not searched) or "none" (no C holds)."""
    return float(s) if s not in ("", "none", None) else math.nan


def read(path):
    """The rows of a table of `smpm stability` (figures.read_table: its earlier column names
    too)."""
    try:
        return figures.read_table(path)
    except OSError as e:
        sys.exit(f"{pathlib.Path(sys.argv[0]).name}: {path}: {e}")


def name_of(r):
    """The series of a row: FLIP, exact, FMPM(k), blended with FMPM(m), or periodic."""
    if r["velocity"] in ("FLIP", "exact"):
        return r["velocity"]
    alpha, every, cx = num(r["blend_alpha"]), int(r["blend_every"] or 1), num(r["periodic_cx"])
    if not math.isnan(cx):
        return f"periodic, C_X = {cx:g}"
    if alpha < 1:
        return f"blended with FMPM({every}), α = {alpha:g}"
    return "FMPM(k)"


def mathtext(name):
    """A series name with its symbols in mathtext (α, C_X)."""
    return name.replace("α", "$\\alpha$").replace("C_X", "$C_X$")


def series_of(rows, column):
    """{series: [(k, value)]} of the FMPM rows, and {FLIP | exact: value}, for one column."""
    series, lines = {}, {}
    for r in rows:
        name = name_of(r)
        if name in ("FLIP", "exact"):
            lines[name] = num(r[column])
        else:
            series.setdefault(name, []).append((int(r["order"]), num(r[column])))
    return {k: sorted(v) for k, v in series.items()}, lines


def draw_series(ax, pts, colour, method, **kw):
    """One series against k in the style of its method; False when it has no value."""
    if not any(not math.isnan(v) for _, v in pts):
        return False
    ls, marker, face = STYLE[method]
    ax.plot([k for k, _ in pts], [v for _, v in pts], ls=ls, marker=marker, color=colour,
            mfc=face or colour, ms=4, **kw)
    return True


def legends(ax, colours, methods):
    """Two legends below the panel: the series by colour (left), the methods by line style and
    the paper's star (right)."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=c, lw=2.5, alpha=0.3 if "as in A" in n else 1, label=n)
               for n, c in colours]
    first = ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.0, -0.13),
                      title="series")
    ax.add_artist(first)
    handles = []
    for m in methods:
        if m == "paper":
            handles.append(Line2D([], [], ls="none", marker="*", ms=10, color="w", mec="k",
                                  label="paper (simulation)"))
        else:
            ls, marker, face = STYLE[m]
            handles.append(Line2D([], [], ls=ls, marker=marker, color="k", mfc=face or "k",
                                  ms=4, label=m))
    ax.legend(handles=handles, loc="upper right", bbox_to_anchor=(1.0, -0.13), title="method")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table")
    ap.add_argument("--low-dissipation", help="table of smpm stability --max-energy-change")
    figures.add_output(ap, "fig12a")
    args = ap.parse_args()
    rows = read(args.table)
    columns = {"spectral": series_of(rows, "critical_courant"),
               "simulation": series_of(rows, "simulation_courant")}
    if args.low_dissipation:
        low = read(args.low_dissipation)
        columns["simulation, low dissipation"] = series_of(low, "simulation_courant")
    names = sorted({n for s, _ in columns.values() for n in s})
    colour = {n: f"C{i}" for i, n in enumerate(["FMPM(k)"] + [n for n in names if n != "FMPM(k)"])}
    plt = figures.style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 6.6), sharey=True)
    shown = {a: [], b: []}  # the methods drawn on each panel
    for method, (series, lines) in columns.items():
        for name, pts in series.items():
            ax = a if name == "FMPM(k)" else b
            if draw_series(ax, pts, colour[name], method) and method not in shown[ax]:
                shown[ax].append(method)
        if method == "simulation" and "FMPM(k)" in series:  # panel A's curve, for reference
            draw_series(b, series["FMPM(k)"], colour["FMPM(k)"], method, alpha=0.3, zorder=1)
        for name, c in (("FLIP", FLIP_COLOUR), ("exact", EXACT_COLOUR)):
            v = lines.get(name, math.nan)
            if not math.isnan(v):
                a.axhline(v, ls=STYLE[method][0], color=c, lw=1.2)
                if method not in shown[a]:
                    shown[a].append(method)
    stars = {}  # (panel, k, C*): the series with that paper value, drawn side by side
    for name, pts in PAPER.items():
        for k, v in pts:
            stars.setdefault((a if name == "FMPM(k)" else b, k, v), []).append(name)
    for (ax, k, v), which in stars.items():
        for i, name in enumerate(which):
            shift = 1.08 ** (i - (len(which) - 1) / 2)
            ax.plot([k * shift], [v], "*", ms=13, color=colour.get(name, "k"), mec="k", zorder=5)
        if "paper" not in shown[ax]:
            shown[ax].append("paper")
    # FLIP does not depend on k: its paper value is a star at the right end of its lines.
    a.plot([1.0], [PAPER_FLIP], "*", ms=13, color=FLIP_COLOUR, mec="k", zorder=5,
           transform=a.get_yaxis_transform(), clip_on=False)

    def has(name):
        return any(not math.isnan(lines.get(name, math.nan)) for _, lines in columns.values())

    panel_a = [("FMPM($k$)", colour["FMPM(k)"])]
    if has("FLIP"):
        panel_a.append(("FLIP (its paper value: the star at the right edge)", FLIP_COLOUR))
    if has("exact"):
        panel_a.append(("exact $\\tilde m^{-1}$ ($k \\to \\infty$)", EXACT_COLOUR))
    order = list(STYLE) + ["paper"]
    legends(a, panel_a, [m for m in order if m in shown[a]])
    panel_b = [(mathtext(n), colour[n]) for n in names if n != "FMPM(k)"]
    if any(not math.isnan(v) for _, v in columns["simulation"][0].get("FMPM(k)", [])):
        panel_b.append(("FMPM($k$), simulation (as in A)", colour["FMPM(k)"]))
    legends(b, panel_b, [m for m in order if m in shown[b]])
    orders = sorted({k for s, _ in columns.values() for pts in s.values() for k, _ in pts} |
                    {k for pts in PAPER.values() for k, _ in pts})
    for ax, title in ((a, "(A) FMPM($k$), FLIP and the exact inverse"),
                      (b, "(B) blended and periodic FMPM($k$)")):
        ax.set_xscale("log")
        ax.set_xticks(orders, [str(k) for k in orders])
        ax.minorticks_off()
        ax.set_xlabel("FMPM order $k$")
        ax.set_title(title)
    a.set_ylabel("critical Courant number $C^*$")
    fig.suptitle("Free-vibrating bar: critical Courant number (FMPM 2026 Fig. 12A)")
    png = figures.save_figure(fig, figures.output_prefix(args.out), report=False)
    print(f"{png}: {len(rows)} rows from {args.table}")


if __name__ == "__main__":
    main()
