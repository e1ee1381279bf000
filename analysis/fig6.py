#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 6: the contact force of Coulomb friction with contact detection.

    analysis/fig6.py [--build build/python] [--friction 0.8] [--tractions 0,1,2]
                     [--range -2,4] [-o fig6]

Evaluates the library's contact law at one node (sparsempm.contact_momentum_change, the code
every contact step runs) for Δp(0) = −N_c n̂ + T_c t̂ with A_c Δt = 1, so that |Δp| is
‖f_c‖/A_c: for N_c over `range` and each tangential stick traction T_c of `tractions`, with the
materials touching (separation < 0). The paper's curve is

    ‖f_c‖/A_c = √(N_c² + min(T_c, μ N_c)²)  (N_c > 0),   0  (N_c ≤ 0),

whose T_c = 0 curve is also frictionless contact's for every T_c. Prints the largest difference
between the library and that formula (round-off), writes PREFIX.csv (N_c, T_c, the library's
‖f_c‖/A_c, the formula's, stick or slip) and PREFIX.png.
"""
import argparse
import csv
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from smpm_python import add_arguments, sparsempm  # noqa: E402


def paper(n_c, t_c, mu):
    """FMPM 2026's ‖f_c‖/A_c of a contact node with δ_n < 0 (the equation of its Fig. 6)."""
    return math.hypot(n_c, min(t_c, mu * n_c)) if n_c > 0 else 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_arguments(ap)
    ap.add_argument("--friction", type=float, default=0.8)
    ap.add_argument("--tractions", default="0,1,2")
    ap.add_argument("--range", default="-2,4")
    figures.add_output(ap, "fig6", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    smpm = sparsempm(a)
    if smpm is None:
        sys.exit("fig6.py: needs the Python module sparsempm (--build DIR)")
    lo, hi = (float(v) for v in a.range.split(","))
    tractions = [float(v) for v in a.tractions.split(",")]
    mu = a.friction
    count = 601
    normal, tangent = [0.0, 1.0], [1.0, 0.0]  # n̂ from α to β; t̂ along x
    rows, curves, worst = [], {}, 0.0
    for t_c in tractions:
        xs, ys = [], []
        for j in range(count):
            n_c = lo + (hi - lo) * j / (count - 1)
            dp0 = [t_c * tangent[0] - n_c * normal[0], t_c * tangent[1] - n_c * normal[1]]
            _, dp = smpm.contact_momentum_change(dp0, normal, "coulomb", mu, -1.0)
            force = math.hypot(*dp)
            expected = paper(n_c, t_c, mu)
            worst = max(worst, abs(force - expected))
            state = "none" if n_c <= 0 else ("stick" if t_c <= mu * n_c else "slip")
            rows.append([f"{n_c:.6g}", f"{t_c:g}", f"{force:.12g}", f"{expected:.12g}", state])
            xs.append(n_c)
            ys.append(force)
        curves[t_c] = (xs, ys)
    print(f"mu = {mu:g}: largest |library - formula| over {len(rows)} points: {worst:.3g}")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["N_c", "T_c", "force_per_area", "paper_force_per_area", "state"])
        w.writerows(rows)
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for i, (t_c, (xs, ys)) in enumerate(curves.items()):
        label = f"$T_c$ = {t_c:g}" + (" (and frictionless, any $T_c$)" if t_c == 0 else "")
        ax.plot(xs, ys, color=f"C{i}", label=label)
        if 0 < t_c and mu > 0 and t_c / mu < hi:  # where slip turns to stick: μ N_c = T_c
            n_s = t_c / mu
            ax.plot([n_s], [paper(n_s, t_c, mu)], "o", color=f"C{i}", mfc="none")
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel("contact pressure $N_c$ (stress units)")
    ax.set_ylabel("contact force per area $\\Vert f_c\\Vert / A_c$ (stress units)")
    ax.set_title(f"Coulomb friction with contact detection, $\\mu$ = {mu:g} (FMPM 2026 Fig. 6)")
    ax.legend(title="open circles: slip turns to stick")
    figures.save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
