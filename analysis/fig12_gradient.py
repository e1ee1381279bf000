#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 12A with and without velocity gradients: does C* reach 1?

    analysis/fig12_gradient.py --problem bar bar_standard.csv bar_gradient.csv [bar_apic.csv] \
                               [--problem plate plate_standard.csv plate_gradient.csv ...] \
                               [-o fig12_gradient]

Each --problem names a problem and two or three tables written by `smpm stability --method
both` on the same input: one with the standard transfer, one with `--set
step.transfer=velocity_gradient` (Wallstedt & Guilkey 2007) and optionally one with `--set
step.transfer=apic` (Jiang et al. 2015; docs/studies/gradient-transfers.md).
One column of panels per problem: (A) FMPM(k), FLIP and the exact update, (B) FMPM(k) blended
with FMPM(1) and FMPM(2) and periodic FMPM(k), with the velocity-gradient transfer drawn in full
and the standard transfer faded; with an APIC table, (C) APIC's FMPM(k), FLIP and exact update
in full beside the velocity-gradient transfer's faded. Each series has its own colour (of the
shared palette, figures.COLOURS) and its own marker; spectral C* is dashed with open markers,
simulation C* solid with filled ones. The paper's preliminary claims (FMPM 2026 §3.3: FLIP's
limit rises to C = 1 and FMPM(k) plateaus at C = 0.60) are thin black dotted lines.

Writes PREFIX.png and PREFIX.csv (one row per problem, series, order and transfer: the two C*
and the total energy change of the simulation at its C*), and prints the summary table of the
docs/studies/gradient-transfers.md (order 80 for the blended and periodic series).
"""
import argparse
import csv
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from fig12a import EXACT_COLOUR, FLIP_COLOUR, STYLE, mathtext, name_of, num, read  # noqa: E402

TRANSFERS = ("standard", "velocity gradient", "APIC")
FADED = 0.35  # the standard transfer's opacity
# The colours (of the shared palette, figures.COLOURS, FMPM(k) taking the first), markers and
# marker sizes of the blended and periodic series, in the order of their names: the three of
# panel B are the palette's rose, green and olive, which stay apart (the purple next in the
# cycle is too close to the rose, and to the exact update's wine), and each is drawn over the
# one before with a smaller marker, so that where their C* coincide (the velocity-gradient
# transfer's, near 1) every marker still shows around the next.
SERIES_STYLES = [(figures.COLOURS[1], "^", 9), (figures.COLOURS[2], "D", 6),
                 (figures.COLOURS[5], "s", 4), (figures.COLOURS[4], "v", 3),
                 (figures.COLOURS[3], "P", 3), (figures.COLOURS[7], "X", 3)]
CLAIMS = ((1.0, "FLIP → 1"), (0.60, "FMPM(k) plateau 0.60"))  # FMPM 2026 §3.3, preliminary
METHODS = (("spectral", "critical_courant"), ("simulation", "simulation_courant"))
# The rows of the printed summary: (series, order); None: FLIP's and the exact update's rows.
SUMMARY = [("FLIP", None), ("exact", None), ("FMPM(k)", 1), ("FMPM(k)", 4), ("FMPM(k)", 16), ("FMPM(k)", 80),
           ("blended with FMPM(1), α = 0.8", 80), ("blended with FMPM(2), α = 0.8", 80),
           ("periodic, C_X = 2", 80)]


def collect(problems):
    """[(problem, transfer, series, order or None, {column: value})] of every row of the
    tables: FLIP, FMPM(k) and its variants, and the exact update (m̃⁻¹ or m̃_L⁻¹) if present."""
    out = []
    for problem, paths in problems:
        for transfer, path in zip(TRANSFERS, paths):
            for r in read(path):
                name = name_of(r)
                order = None if name in ("FLIP", "exact") else int(r["order"])
                values = {c: num(r[c]) for _, c in METHODS}
                values["energy_change"] = num(r["energy_change"])
                out.append((problem, transfer, name, order, values))
    return out


def series_styles(names):
    """{series: (colour, marker, marker size)}: FMPM(k) and the blended and periodic series
    (`names`) each in its own colour of the shared palette and its own marker (SERIES_STYLES),
    so that the series of panel B stay apart where their lines cross or lie together; FLIP and
    the exact update (lines, no marker) in theirs."""
    styles = {"FMPM(k)": (figures.COLOURS[0], "o", 6)}
    styles.update(zip(names, SERIES_STYLES))
    styles["FLIP"], styles["exact"] = (FLIP_COLOUR, None, 0), (EXACT_COLOUR, None, 0)
    return styles


def draw(rows, problems):
    """The figure: one column per problem, with (A) and (B) above each other, and (C) below
    them with an APIC table."""
    from matplotlib.lines import Line2D
    plt = figures.style()
    apic = any(r[1] == "APIC" for r in rows)
    nrows, ncols = (3 if apic else 2), len(problems)
    # A column per problem (two for the bar and the plate, not a row of three panels each), so
    # that the docs, which show the figure about 700 px wide, show each panel large enough to
    # tell its series apart.
    fig = plt.figure(figsize=(5.2 * ncols, 3.3 * nrows + 2.6))
    grid = fig.add_gridspec(nrows, ncols)
    names = sorted({r[2] for r in rows} - {"FLIP", "exact", "FMPM(k)"})
    if len(names) > len(SERIES_STYLES):
        sys.exit(f"fig12_gradient.py: {len(names)} blended and periodic series; "
                 f"styles for {len(SERIES_STYLES)}")
    style = series_styles(names)
    lines = [n for n in ("FLIP", "exact") if any(r[2] == n for r in rows)]

    def plot(mine, a, b, alpha):  # FLIP and the exact update as lines, FMPM(k) on a, the rest on b
        faded = alpha < 1
        for method, column in METHODS:
            ls, _, face = STYLE[method]
            for r in mine:  # FLIP and the exact update do not depend on k
                if r[2] in lines and not math.isnan(r[4][column]):
                    a.axhline(r[4][column], ls=ls, color=style[r[2]][0], lw=1.2, alpha=alpha)
            for name in ["FMPM(k)"] + names:
                pts = sorted((r[3], r[4][column]) for r in mine if r[2] == name)
                if not any(not math.isnan(v) for _, v in pts):
                    continue
                ax = a if name == "FMPM(k)" else b
                if ax is not None:
                    colour, marker, size = style[name]
                    # spectral: dashed, open markers; simulation: solid, filled markers
                    ax.plot([k for k, _ in pts], [v for _, v in pts], ls=ls, marker=marker,
                            color=colour, mfc="white" if face == "none" else colour,
                            ms=0.75 * size if faded else size, lw=1.2 if faded else 1.8,
                            alpha=alpha)

    axes = {}
    for j, (problem, _) in enumerate(problems):  # created problem by problem: A, B, C of each
        for i in range(nrows):
            axes[i, j] = fig.add_subplot(grid[i, j], sharey=axes.get((0, 0)))
    for j, (problem, _) in enumerate(problems):
        a, b = axes[0, j], axes[1, j]
        mine = {t: [r for r in rows if r[0] == problem and r[1] == t] for t in TRANSFERS}
        plot(mine["standard"], a, b, FADED)
        plot(mine["velocity gradient"], a, b, 1)
        titles = [(a, f"(A) {problem}: FMPM($k$), FLIP and exact"),
                  (b, f"(B) {problem}: blended and periodic FMPM($k$)")]
        if apic:
            c = axes[2, j]
            plot(mine["velocity gradient"], c, None, FADED)
            plot(mine["APIC"], c, None, 1)
            titles.append((c, f"(C) {problem}: APIC, FMPM($k$), FLIP and exact"))
        orders = sorted({r[3] for r in rows if r[0] == problem and r[3] is not None})
        for ax, title in titles:
            for level, _ in CLAIMS:
                ax.axhline(level, color="k", lw=0.8, ls=(0, (1, 3)))
            ax.set_xscale("log")
            ax.set_xticks(orders, [str(k) for k in orders])
            ax.minorticks_off()
            ax.set_xlabel("FMPM order $k$")
            ax.set_title(title)
            if j == 0:
                ax.set_ylabel("critical Courant number $C^*$")
            else:  # the C* axis is shared: its numbers on the left column only
                ax.tick_params(labelleft=False)
    # Legends under the last row: the series (colour and marker), and how they are drawn.
    a, b = axes[nrows - 1, 0], axes[nrows - 1, ncols - 1]
    label = {"exact": "exact $\\tilde m^{-1}$ (standard), $\\tilde m_L^{-1}$ (gradient)" +
             (", $\\tilde m_A^{-1}$ (APIC)" if apic else "")}
    series = [Line2D([], [], color=style[n][0], lw=2, marker=style[n][1], ms=max(style[n][2], 5),
                     label=label.get(n, mathtext(n).replace("(k)", "($k$)")))
              for n in lines + ["FMPM(k)"] + names]
    how = [Line2D([], [], ls=STYLE[m][0], marker="o", color="k",
                  mfc="white" if STYLE[m][2] == "none" else "k", ms=6, lw=1.8, label=m)
           for m, _ in METHODS]
    how += [Line2D([], [], color="k", lw=1.8, label="velocity-gradient transfer" +
                   (" (A, B); APIC (C)" if apic else "")),
            Line2D([], [], color="k", lw=1.2, alpha=FADED, label="standard transfer" +
                   (" (A, B); velocity gradient (C)" if apic else "")),
            Line2D([], [], color="k", lw=0.8, ls=(0, (1, 3)),
                   label="paper's preliminary claims (1, 0.60)")]
    if ncols > 1:
        a.legend(handles=series, loc="upper left", bbox_to_anchor=(0.0, -0.2),
                 title="series (colour and marker)")
        b.legend(handles=how, loc="upper right", bbox_to_anchor=(1.0, -0.2), title="drawn as")
    else:  # one problem: the two legends one above the other
        first = a.legend(handles=series, loc="upper left", bbox_to_anchor=(0.0, -0.2),
                         title="series (colour and marker)")
        a.add_artist(first)
        a.legend(handles=how, loc="upper left", bbox_to_anchor=(0.0, -1.0), title="drawn as")
    fig.suptitle("Critical Courant number with and without velocity gradients "
                 "(FMPM 2026 §3.3, Fig. 12A)")
    return fig


def write_table(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["problem", "series", "order", "transfer", "critical_courant",
                    "simulation_courant", "energy_change"])
        for problem, transfer, name, order, v in rows:
            w.writerow([problem, name, "" if order is None else order, transfer] +
                       ["" if math.isnan(v[c]) else f"{v[c]:.4g}"
                        for c in ("critical_courant", "simulation_courant", "energy_change")])


def summary(rows, problems):
    """The table of docs/studies/gradient-transfers.md: per problem and series, C* (spectral / simulation) for each transfer
    and the energy change of the simulation at its C*."""
    def cell(v):
        return "–" if math.isnan(v) else f"{v:.3f}"

    present = [t for t in TRANSFERS if any(r[1] == t for r in rows)]
    lines = ["| problem | series | " +
             " | ".join(f"{t}: spectral / simulation (ΔE)" for t in present) + " |",
             "| --- | --- | " + " | ".join("---" for _ in present) + " |"]
    for problem, _ in problems:
        for name, order in SUMMARY:
            found = {r[1]: r[4] for r in rows if r[0] == problem and r[2] == name and r[3] == order}
            if not found:
                continue
            label = name if order is None or name != "FMPM(k)" else f"FMPM({order})"
            if order is not None and name != "FMPM(k)":
                label = f"{name}, k = {order}"
            parts = []
            for t in present:
                v = found.get(t)
                if v is None:
                    parts.append("–")
                    continue
                de = v["energy_change"]
                parts.append(f"{cell(v['critical_courant'])} / {cell(v['simulation_courant'])}" +
                             ("" if math.isnan(de) else f" ({100 * de:+.1f}%)"))
            lines.append(f"| {problem} | {label} | " + " | ".join(parts) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problem", nargs="+", action="append", required=True,
                    metavar="NAME STANDARD_CSV GRADIENT_CSV [APIC_CSV]",
                    help="a problem and its two or three smpm stability tables (repeatable)")
    figures.add_output(ap, "fig12_gradient", "PREFIX.png and PREFIX.csv")
    args = ap.parse_args()
    problems = [(p[0], tuple(p[1:])) for p in args.problem]
    if len({name for name, _ in problems}) != len(problems):
        sys.exit("fig12_gradient.py: --problem: each problem is named once")
    if any(len(paths) not in (2, 3) for _, paths in problems) or \
            len({len(paths) for _, paths in problems}) != 1:
        sys.exit("fig12_gradient.py: --problem: NAME STANDARD_CSV GRADIENT_CSV [APIC_CSV], "
                 "the same tables for every problem")
    rows = collect(problems)
    prefix = figures.output_prefix(args.out)
    fig = draw(rows, problems)
    write_table(rows, f"{prefix}.csv")
    figures.save_figure(fig, prefix, tables=[f"{prefix}.csv"])
    print(summary(rows, problems))


if __name__ == "__main__":
    main()
