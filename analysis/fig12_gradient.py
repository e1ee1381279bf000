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
One row of panels per problem: (A) FMPM(k), FLIP and the exact update, (B) FMPM(k) blended with
FMPM(1) and FMPM(2) and periodic FMPM(k), with the velocity-gradient transfer drawn in full and
the standard transfer faded; with an APIC table, (C) APIC's FMPM(k), FLIP and exact update in
full beside the velocity-gradient transfer's faded. Colours are the series as in fig12a.py;
spectral C* dashed with open circles, simulation C* solid with squares. The paper's preliminary claims (FMPM 2026 §3.3: FLIP's limit rises to
C = 1 and FMPM(k) plateaus at C = 0.60) are thin black lines.

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


def draw(rows, problems):
    """The figure: one row of two panels per problem, three with an APIC table."""
    from matplotlib.lines import Line2D
    plt = figures.style()
    apic = any(r[1] == "APIC" for r in rows)
    cols = 3 if apic else 2
    fig, axes = plt.subplots(len(problems), cols, figsize=(6 * cols, 4.2 * len(problems) + 2.4),
                             sharey=True, squeeze=False)
    names = sorted({r[2] for r in rows} - {"FLIP", "exact", "FMPM(k)"})
    colour = {n: f"C{i}" for i, n in enumerate(["FMPM(k)"] + names)}
    colour["FLIP"], colour["exact"] = FLIP_COLOUR, EXACT_COLOUR
    lines = [n for n in ("FLIP", "exact") if any(r[2] == n for r in rows)]

    def plot(mine, a, b, alpha):  # FLIP and the exact update as lines, FMPM(k) on a, the rest on b
        for method, column in METHODS:
            ls, marker, face = STYLE[method]
            for r in mine:  # FLIP and the exact update do not depend on k
                if r[2] in lines and not math.isnan(r[4][column]):
                    a.axhline(r[4][column], ls=ls, color=colour[r[2]], lw=1.2, alpha=alpha)
            for name in ["FMPM(k)"] + names:
                pts = sorted((r[3], r[4][column]) for r in mine if r[2] == name)
                if not any(not math.isnan(v) for _, v in pts):
                    continue
                ax = a if name == "FMPM(k)" else b
                if ax is not None:
                    ax.plot([k for k, _ in pts], [v for _, v in pts], ls=ls, marker=marker,
                            color=colour[name], mfc=face or colour[name], ms=4, alpha=alpha)

    for (problem, _), row in zip(problems, axes):
        a, b = row[0], row[1]
        mine = {t: [r for r in rows if r[0] == problem and r[1] == t] for t in TRANSFERS}
        plot(mine["standard"], a, b, FADED)
        plot(mine["velocity gradient"], a, b, 1)
        titles = [(a, f"(A) {problem}: FMPM($k$), FLIP and exact"),
                  (b, f"(B) {problem}: blended and periodic FMPM($k$)")]
        if apic:
            plot(mine["velocity gradient"], row[2], None, FADED)
            plot(mine["APIC"], row[2], None, 1)
            titles.append((row[2], f"(C) {problem}: APIC, FMPM($k$), FLIP and exact"))
        orders = sorted({r[3] for r in rows if r[0] == problem and r[3] is not None})
        for ax, title in titles:
            for level, _ in CLAIMS:
                ax.axhline(level, color="k", lw=0.8, ls=(0, (1, 3)))
            ax.set_xscale("log")
            ax.set_xticks(orders, [str(k) for k in orders])
            ax.minorticks_off()
            ax.set_xlabel("FMPM order $k$")
            ax.set_title(title)
        a.set_ylabel("critical Courant number $C^*$")
    # Legends under the last row: the series (colours), and how they are drawn.
    a, b = axes[-1][0], axes[-1][1]
    label = {"exact": "exact $\\tilde m^{-1}$ (standard), $\\tilde m_L^{-1}$ (gradient)" +
             (", $\\tilde m_A^{-1}$ (APIC)" if apic else "")}
    series = [Line2D([], [], color=colour[n], lw=2.5,
                     label=label.get(n, mathtext(n).replace("(k)", "($k$)")))
              for n in lines + ["FMPM(k)"] + names]
    a.legend(handles=series, loc="upper left", bbox_to_anchor=(0.0, -0.16), title="series")
    how = [Line2D([], [], ls=STYLE[m][0], marker=STYLE[m][1], color="k", mfc=STYLE[m][2] or "k",
                  ms=4, label=m) for m, _ in METHODS]
    how += [Line2D([], [], color="k", lw=2.5, label="velocity-gradient transfer" +
                   (" (A, B); APIC (C)" if apic else "")),
            Line2D([], [], color="k", lw=2.5, alpha=FADED, label="standard transfer" +
                   (" (A, B); velocity gradient (C)" if apic else "")),
            Line2D([], [], color="k", lw=0.8, ls=(0, (1, 3)),
                   label="paper's preliminary claims (1, 0.60)")]
    b.legend(handles=how, loc="upper right", bbox_to_anchor=(1.0, -0.16), title="drawn as")
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
