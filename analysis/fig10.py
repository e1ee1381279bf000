#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 10: the Helmholtz free energy of two disks in an offset impact with friction.

    analysis/fig10.py [--smpm build/apps/smpm] [--cell 1.0] [--jobs 2]
                      [--set section.key=value ...] [-o fig10]

Runs examples/disk_impact.toml with `smpm run` at cell size `cell` (mm; the paper's is 1/3 mm)
for mu = 0, 0.3, 0.6 with FLIP (lumped heat transport) and FMPM(4) (FMPM(4) on the capacity
matrix), two runs at a time, and plots dA(t) = A(t) - A(0), A = U - T S summed over the
particles (the series `helmholtz`; diagnostics.hpp states the free energy it sums). An adiabatic
process between equilibrium states has dA = 0: the impact raises A (the disks' elastic energy)
and it falls back to near zero once they separate, save the stress waves they still carry.
Prints and writes to PREFIX.csv, per run: the peak of dA and its value at the end, in % of the
initial energy U + K. Writes PREFIX.png (a trailing .png of -o is dropped). --set changes an
input entry of every run (--set time.end=0.02 for a short run).
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

MUS = (0.0, 0.3, 0.6)
NAMES = ("FLIP", "FMPM(4)")


def job(smpm, work, mu, name, cell, sets=()):
    out = pathlib.Path(work) / f"mu{mu}_{name.replace('(', '').replace(')', '')}.h5"
    try:
        return disks.run(smpm, out, velocity(name) + [f"contact.0.friction={mu}"] +
                         disks.grid(cell) + list(sets))
    except RuntimeError as e:
        raise RuntimeError(f"mu = {mu}, {name}: {e}") from None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cell", type=float, default=1.0)
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig10", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {(mu, n): pool.submit(job, a.smpm, work, mu, n, a.cell, a.sets)
                   for mu in MUS for n in NAMES}
        res = {k: f.result() for k, f in futures.items()}
    print(f"cell {a.cell} mm: dA = A(t) - A(0) in % of the initial energy")
    print(f"{'mu':>4s} {'update':8s} {'peak %':>8s} {'end %':>8s}")
    rows = []
    for (mu, name), r in sorted(res.items()):
        e0 = r["energy0"]
        dA = 100 * (r["helmholtz"] - r["helmholtz"][0]) / e0
        print(f"{mu:4.1f} {name:8s} {dA.max():8.3f} {dA[-1]:8.3f}")
        rows.append([mu, name, f"{dA.max():.4f}", f"{dA[-1]:.4f}"])
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mu", "update", "dA_peak_percent", "dA_end_percent"])
        w.writerows(rows)
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for i, mu in enumerate(MUS):
        colour = figures.COLOURS[i]
        for name, style in zip(NAMES, ("-", "o")):
            r = res[(mu, name)]
            dA = r["helmholtz"] - r["helmholtz"][0]
            if style == "-":
                ax.plot(r["time"], dA, "-", color=colour, label=f"FLIP, $\\mu$ = {mu}")
            else:
                every = max(1, len(dA) // 30)
                ax.plot(r["time"][::every], dA[::every], "o", ms=3, color=colour, mfc="none",
                        label=f"FMPM(4), $\\mu$ = {mu}")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("$\\Delta A = A(t) - A(0)$ (mJ per mm of thickness)")
    ax.set_title(f"Free energy of the two disks, {a.cell:g} mm cells (FMPM 2026 Fig. 10)")
    ax.legend(ncol=2)
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
