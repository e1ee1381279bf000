#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 9: energy lost by an offset impact of two disks with Coulomb friction.

    analysis/fig9.py [--smpm build/apps/smpm] [--cell 1.0] [--jobs 2] [--set section.key=value ...]
                     [-o fig9]

Runs examples/disk_impact.toml with `smpm run` at cell size `cell` (mm; the grid keeps its
extent) for mu = 0, 0.3, 0.6 with FLIP, FMPM(1), FMPM(2) and FMPM(4) (Fig. 9A), and for
mu = 0.3 with FMPM(k), k = 1 ... 8 (Fig. 9B), two runs at a time, with heat conduction (the
example's C_V, kappa, T0; FLIP with the lumped transport, FMPM(k) with FMPM(k) on the capacity
matrix). For each run it reports the energy lost, 1 - (U + K)(end) / (U + K)(0) in % with
U = W + Q (strain energy and heat; FMPM 2026 Fig. 9), the heat Q gained and the frictional work
in % of the initial energy (equal: the heat comes from friction alone), the highest
temperature reached, and the left disk's centre-of-mass displacement at the end (the
deflection grows with mu). Panel A draws the energy lost by each update as bars grouped by
update (one per mu), panel B against the order k as a line.
Writes PREFIX.csv and PREFIX.png (a trailing .png of -o is dropped). --set changes an input
entry of every run (--set time.end=0.02 for a short run). The trajectories of Fig. 8 are
analysis/fig8.py.
"""
import argparse
import concurrent.futures
import csv
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import disks  # noqa: E402
from disks import ROOT, velocity  # noqa: E402
import figures  # noqa: E402
from figures import save_figure  # noqa: E402


NAMES = ["FLIP", "FMPM(1)", "FMPM(2)", "FMPM(4)"]


def cases():
    out = {}
    for mu in (0.0, 0.3, 0.6):
        for name in NAMES:
            out[(mu, name)] = velocity(name) + [f"contact.0.friction={mu}"]
    for k in (3, 5, 6, 7, 8):
        out[(0.3, f"FMPM({k})")] = velocity(f"FMPM({k})") + ["contact.0.friction=0.3"]
    return out


def job(smpm, work, key, sets, cell, extra=()):
    mu, name = key
    out = pathlib.Path(work) / f"mu{mu}_{name.replace('(', '').replace(')', '')}.h5"
    try:
        return disks.run(smpm, out, sets + disks.grid(cell) + list(extra))
    except RuntimeError as e:
        raise RuntimeError(f"{key}: {e}") from None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cell", type=float, default=1.0)
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig9", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    todo = cases()
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(job, a.smpm, work, k, v, a.cell, a.sets) for k, v in todo.items()}
        res = {k: f.result() for k, f in futures.items()}
    print(f"cell {a.cell} mm: energy lost 1 - (U + K)/(U + K)_0 in %, U = W + Q")
    print(f"{'mu':>4s} {'update':8s} {'lost %':>8s} {'heat %':>7s} {'friction %':>11s}"
          f" {'T max (K)':>9s} {'left disk dx, dy (mm)':>24s} {'|momentum|':>11s} {'run s':>6s}")
    rows = []
    for (mu, name), r in sorted(res.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        c = r["centre"]
        dx, dy = c[-1, 0] - c[0, 0], c[-1, 1] - c[0, 1]
        print(f"{mu:4.1f} {name:8s} {r['lost']:8.3f} {r['heat']:7.2f} {r['friction']:11.2f}"
              f" {r['t_max']:9.1f} {dx:11.3f} {dy:11.3f} {r['momentum']:11.2e} {r['seconds']:6.1f}")
        rows.append([mu, name, f"{r['lost']:.4f}", f"{r['heat']:.4f}", f"{r['friction']:.4f}",
                     f"{r['t_max']:.3f}", f"{dx:.4f}", f"{dy:.4f}"])
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mu", "update", "energy_lost_percent", "heat_percent", "friction_percent",
                    "temperature_max_K", "left_dx_mm", "left_dy_mm"])
        w.writerows(rows)
    plt = figures.style()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    # A: the updates are categories, so bars grouped by update (one per mu, labelled with its
    # value), not lines between them.
    mus = (0.0, 0.3, 0.6)
    width = 0.8 / len(mus)
    top = 0
    for j, mu in enumerate(mus):
        lost = [res[(mu, n)]["lost"] for n in NAMES]
        bars = axes[0].bar([i + (j - (len(mus) - 1) / 2) * width for i in range(len(NAMES))], lost,
                           width, color=f"C{j}", label=f"$\\mu$ = {mu}")
        axes[0].bar_label(bars, fmt="%.1f", fontsize=7, padding=1)
        top = max([top] + lost)
    axes[0].set_xticks(range(len(NAMES)), NAMES)
    axes[0].grid(False, axis="x")
    axes[0].set_ylim(min(0, axes[0].get_ylim()[0]), 1.1 * top if top > 0 else None)
    axes[0].set_title("Fig. 9A: energy lost by each update")
    axes[0].set_xlabel("velocity update")
    axes[0].set_ylabel("energy lost $1 - (U + K)/(U + K)_0$ (%)")
    axes[0].legend(title="Coulomb friction")
    ks = list(range(1, 9))
    axes[1].plot(ks, [res[(0.3, f"FMPM({k})")]["lost"] for k in ks], "o-", label="FMPM(k)")
    axes[1].axhline(res[(0.3, "FLIP")]["lost"], color="k", lw=0.8, label="FLIP")
    axes[1].set_title("Fig. 9B: FMPM($k$), $\\mu$ = 0.3")
    axes[1].set_xlabel("FMPM order $k$")
    axes[1].set_ylabel("energy lost $1 - (U + K)/(U + K)_0$ (%)")
    axes[1].legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
