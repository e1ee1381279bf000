#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 12A: critical Courant number against FMPM order k.

    analysis/fig12a.py stability.csv [--low-dissipation low.csv] [-o fig12a.png]

Reads the table written by `smpm stability` (the CSV behind the figure) and plots C* against k
for FMPM(k), FMPM(k) blended with FMPM(1) and with FMPM(2), and periodic FMPM(k), with FLIP and
the exact inverse as horizontal lines: spectral predictions (minimum over the configurations
examined) dashed, bisection over full runs solid, and the values reported in the paper as
stars. With --low-dissipation, a second table (`smpm stability --method simulation
--max-energy-change F`) adds the largest C with low dissipation as dotted lines.
"""
import argparse
import csv
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Values quoted in FMPM 2026 §3.3 for this bar (simulation, ±0.005).
PAPER = {
    "FMPM": [(1, 0.86), (4, 0.539), (40, 0.25), (80, 0.24)],
    "blend 1 (α=0.8)": [(80, 0.51)],
    "blend 2 (α=0.8)": [(80, 0.40)],
    "periodic (C_X=2)": [(80, 0.40)],
}


def num(s):
    """A table cell as a number: NaN where it is empty (not searched) or "none" (no C holds)."""
    return float(s) if s not in ("", "none", None) else math.nan


def read(path):
    try:
        return list(csv.DictReader(open(path)))
    except OSError as e:
        sys.exit(f"fig12a.py: {path}: {e}")


def name_of(r):
    alpha, every, cx = num(r["blend_alpha"]), int(r["blend_every"] or 1), num(r["periodic_cx"])
    if not math.isnan(cx):
        return f"periodic (C_X={cx:g})"
    if alpha < 1:
        return f"blend {every} (α={alpha:g})"
    return "FMPM"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table")
    ap.add_argument("--low-dissipation", help="table of smpm stability --max-energy-change")
    ap.add_argument("-o", "--output", default="fig12a.png")
    args = ap.parse_args()
    rows = read(args.table)
    low = {}
    if args.low_dissipation:
        for r in read(args.low_dissipation):
            if r["velocity"] == "FMPM":
                low.setdefault(name_of(r), []).append((int(r["order"]), num(r["c_simulation"])))
    series = {}
    flip = None
    exact = None
    for r in rows:
        if r["velocity"] == "FLIP":
            flip = r
            continue
        if r["velocity"] == "exact":
            exact = r
            continue
        name = name_of(r)
        series.setdefault(name, []).append((int(r["order"]), num(r["c_spectral"]), num(r["c_simulation"])))
    fig, ax = plt.subplots(figsize=(10, 5))
    colors = {}
    for i, (name, pts) in enumerate(sorted(series.items())):
        pts.sort()
        c = f"C{i}"
        colors[name] = c
        k = [p[0] for p in pts]
        if any(not math.isnan(p[1]) for p in pts):
            ax.plot(k, [p[1] for p in pts], "--o", color=c, mfc="none", label=f"{name}, spectral")
        if any(not math.isnan(p[2]) for p in pts):
            ax.plot(k, [p[2] for p in pts], "-s", color=c, label=f"{name}, simulation")
    for name, pts in low.items():
        pts = sorted(p for p in pts if not math.isnan(p[1]))
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ":x", color=colors.get(name, "k"),
                    label=f"{name}, simulation, |ΔE| ≤ limit")
    for name, pts in PAPER.items():
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "*", ms=12, color=colors.get(name, "k"),
                mec="k", label=f"{name}, paper" if name in colors else None)
    if flip:
        for col, style in (("c_spectral", "--"), ("c_simulation", "-")):
            v = num(flip[col])
            if not math.isnan(v):
                ax.axhline(v, ls=style, color="gray", label=f"FLIP, {col[2:]} ({v:.3f})")
        ax.axhline(0.84, ls=":", color="k", label="FLIP, paper (0.84)")
    if exact:  # the consistent-mass inverse m~^-1, the limit k -> infinity
        for col, style in (("c_spectral", "--"), ("c_simulation", "-")):
            v = num(exact[col])
            if not math.isnan(v):
                ax.axhline(v, ls=style, color="purple", label=f"exact m̃⁻¹, {col[2:]} ({v:.3f})")
    ax.set_xscale("log")
    ax.set_xlabel("FMPM order k")
    ax.set_ylabel("critical Courant number C*")
    ax.set_title("Free-vibrating bar (FMPM 2026 Fig. 12A)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"{args.output}: {len(rows)} rows from {args.table}")


if __name__ == "__main__":
    main()
