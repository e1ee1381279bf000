#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Contact 2020 Fig. 1B: the edge of a material against its extrapolated particle centre, and
the power-law fit of the DF contact detection (Eq. 15).

    analysis/df_fit.py [--ppc 2] [-o df_fit]

A semi-infinite 1D material of undeformed uGIMP particles (`ppc` per cell, equal masses) lies
on the -x side of node 0 with its edge at e (cell units). Its extrapolated centre at the node is
s = sum(S_p x_p) / sum(S_p), S_p the uGIMP weight of the node (the average of the linear hat
over the particle). The exact curve d(s) = e is what the DF method needs; the library uses
NairnMPM's power law d(s) = 1 - 2 (-s/L)^r with L = 1 + l_p (the node's support reaches
centres at s = -L). The script reports r fitted by least squares and r pinned so the fit is
exact where the edge sits on the node (d = 0), the point that decides contact between two
like materials, with the largest error of each, and plots both beside the exact curve.
Writes PREFIX.csv and PREFIX.png (a trailing .png of -o is dropped).
"""
import argparse
import csv
import pathlib
import sys

import numpy as np
from scipy.optimize import minimize_scalar

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402


def ugimp(x, lp):
    """uGIMP weight of node 0 (cell 1) for a particle of half-length lp centred at x."""
    a = np.abs(x)
    return np.where(a < lp, 1 - (a * a + lp * lp) / (2 * lp),
                    np.where(a <= 1 - lp, 1 - a,
                             np.where(a < 1 + lp, (1 + lp - a) ** 2 / (4 * lp), 0.0)))


def exact_curve(ppc, samples=2000):
    """(s, d) of the exact curve for edges from just inside the support to one cell past."""
    lp = 0.5 / ppc
    edges = np.linspace(-1 + 1e-9, 1.0, samples)
    s = []
    for e in edges:
        centres = e - lp - 2 * lp * np.arange(0, 4 * ppc + 4)
        w = ugimp(centres, lp)
        s.append((w * centres).sum() / w.sum())
    return np.array(s), edges, 1 + lp


def fit(s, r, L):
    return 1 - 2 * (np.maximum(-s, 0) / L) ** r


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ppc", type=int, default=2)
    figures.add_output(ap, "df_fit", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    s, d, L = exact_curve(a.ppc)
    r_ls = minimize_scalar(lambda r: np.sum((fit(s, r, L) - d) ** 2), bounds=(0.05, 5),
                           method="bounded").x
    s0 = np.interp(0.0, d, s)  # centre position when the edge is on the node
    r_pin = np.log(0.5) / np.log(-s0 / L)
    print(f"uGIMP, {a.ppc} particles per cell: L = {L:.4f} cells, edge on the node at "
          f"s = {s0:.4f}")
    for name, r in (("least squares", r_ls), ("exact at d = 0", r_pin)):
        err = fit(s, r, L) - d
        print(f"  r = {r:.4f} ({name}): largest error {np.abs(err).max():.4f} cells, "
              f"at the contact point {fit(np.array([s0]), r, L)[0]:+.4f} cells")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["s", "d_exact", "d_least_squares", "d_pinned"])
        for row in zip(s, d, fit(s, r_ls, L), fit(s, r_pin, L)):
            w.writerow([f"{v:.6f}" for v in row])
    plt = figures.style()
    fig, (ax, eax) = plt.subplots(2, 1, figsize=(5.5, 6), sharex=True, height_ratios=[2, 1])
    ax.plot(s, d, "k", label="exact (uGIMP)")
    for r, ls, name in ((r_ls, "--", "least squares"), (r_pin, ":", "exact at $d$ = 0")):
        ax.plot(s, fit(s, r, L), ls, label=f"power law, $r$ = {r:.3f} ({name})")
        eax.plot(s, fit(s, r, L) - d, ls, label=f"$r$ = {r:.3f}")
    ax.set_ylabel("edge position $d$ (cells)")
    ax.set_title(f"DF detection: edge against centre, uGIMP, {a.ppc} particles per cell")
    ax.legend()
    eax.axhline(0, color="k", lw=0.8)
    eax.set_xlabel("extrapolated centre $s = (x_i^\\alpha - x_i)/\\Delta x$ (cells)")
    eax.set_ylabel("fit $-$ exact (cells)")
    figures.save_figure(fig, a.out, tables=[a.out + ".csv"])


if __name__ == "__main__":
    main()
