#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 8: centre-of-mass trajectories of two disks in an offset impact with friction.

    analysis/fig8.py [--smpm build/apps/smpm] [--cell 1.0] [--jobs 2] [--set section.key=value ...]
                     [-o fig8]

Runs examples/disk_impact.toml with `smpm run` at cell size `cell` (mm; the grid keeps its
extent) for mu = 0, 0.3, 0.6 with FLIP, FMPM(1), FMPM(4) and FMPM(8), two runs at a time, and
reports for each: the direction in which each disk leaves (angle of its centre's displacement
over the last quarter of the run, degrees from +x for the left disk and from -x for the right
one; the turn grows with mu), and the largest distance of its trajectories from FLIP's (mm;
the paper: FMPM(4) "essentially identical to FLIP", FMPM(1) "slight deviation", k > 4 as k = 4).
Draws the paper's figure: FLIP solid, FMPM(4) dots on the left disk, FMPM(1) dots on the right,
x shifted by -2 and +2 mm, y relative to the start. Writes PREFIX.csv and PREFIX.png (a
trailing .png of -o is dropped). --set changes an input entry of every run (--set time.end=0.02
for a short run).
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import sys
import tempfile

import numpy as np
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import disks  # noqa: E402
from disks import ROOT, velocity  # noqa: E402
import figures  # noqa: E402
from figures import save_figure  # noqa: E402

MUS = (0.0, 0.3, 0.6)
NAMES = ("FLIP", "FMPM(1)", "FMPM(4)", "FMPM(8)")


def job(smpm, work, mu, name, cell, sets=()):
    out = pathlib.Path(work) / f"mu{mu}_{name.replace('(', '').replace(')', '')}.h5"
    try:
        return disks.run(smpm, out, velocity(name) + [f"contact.0.friction={mu}"] +
                         disks.grid(cell) + list(sets))
    except RuntimeError as e:
        raise RuntimeError(f"mu = {mu}, {name}: {e}") from None


def exit_angles(centre):
    """Degrees below the direction of approach in which each disk leaves (last quarter)."""
    q = len(centre) * 3 // 4
    d = centre[-1] - centre[q]
    left = math.degrees(math.atan2(-d[1], d[0]))
    right = math.degrees(math.atan2(d[3], -d[2]))
    return left, right


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cell", type=float, default=1.0)
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig8", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {(mu, n): pool.submit(job, a.smpm, work, mu, n, a.cell, a.sets)
                   for mu in MUS for n in NAMES}
        res = {k: f.result() for k, f in futures.items()}
    print(f"cell {a.cell} mm: exit angles (deg) and largest distance from FLIP's trajectory (mm)")
    print(f"{'mu':>4s} {'update':8s} {'left deg':>9s} {'right deg':>10s} {'from FLIP mm':>13s}"
          f" {'run s':>6s}")
    rows = []
    for mu in MUS:
        flip = res[(mu, "FLIP")]["centre"]
        for name in NAMES:
            c = res[(mu, name)]["centre"]
            left, right = exit_angles(c)
            # Same steps only when the time steps agree: compare on FLIP's times.
            t, tf = res[(mu, name)]["time"], res[(mu, "FLIP")]["time"]
            dist = max(np.hypot(np.interp(tf, t, c[:, 2 * k]) - flip[:, 2 * k],
                                np.interp(tf, t, c[:, 2 * k + 1]) - flip[:, 2 * k + 1]).max()
                       for k in (0, 1))
            print(f"{mu:4.1f} {name:8s} {left:9.2f} {right:10.2f} {dist:13.4f}"
                  f" {res[(mu, name)]['seconds']:6.1f}")
            rows.append([mu, name, f"{left:.3f}", f"{right:.3f}", f"{dist:.5f}"])
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mu", "update", "left_exit_deg", "right_exit_deg", "max_distance_from_flip_mm"])
        w.writerows(rows)
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for mu in MUS:
        for name, disk, fmt, colour, label in (
                ("FLIP", 0, "-", "k", "FLIP"), ("FLIP", 1, "-", "k", None),
                ("FMPM(4)", 0, ".", "C1", "FMPM(4), left disk"),
                ("FMPM(1)", 1, ".", "C0", "FMPM(1), right disk")):
            c = res[(mu, name)]["centre"]
            shift = -2 if disk == 0 else 2
            every = 1 if fmt == "-" else max(1, len(c) // 40)
            ax.plot(c[::every, 2 * disk] + shift, c[::every, 2 * disk + 1] - c[0, 2 * disk + 1],
                    fmt, color=colour, lw=1, ms=3, label=label if mu == MUS[0] else None)
        c = res[(mu, "FLIP")]["centre"]
        ax.annotate(f"$\\mu$ = {mu}", (c[-1, 0] - 2, c[-1, 1] - c[0, 1]), fontsize=8)
    ax.set_xlabel("centre of mass $x$ (mm; left disk $-$ 2, right disk + 2)")
    ax.set_ylabel("centre of mass $y - y_0$ (mm)")
    ax.set_title("Fig. 8: centres of mass of the two disks, $\\mu$ = " +
                 ", ".join(f"{mu:g}" for mu in MUS))
    ax.legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
