#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Buzzi, Pedroso & Giacomini's caveats on MPM as one script: the vibrating point and bar
against their closed forms (Figs. 9-10, 15, 17-18) and the ordering of the boundary conditions
(Figs. 23-24).

    analysis/buzzi.py [--smpm build/apps/smpm] [--jobs 2] [-o buzzi]

Runs `smpm run` (linear hats: Buzzi's MPM) on
  A. the single-point vibration (examples/single_point_vibration.toml: E = 4 pi^2, rho = 1,
     L = 1, v0 = 0.1; v = v0 cos(2 pi t)), USF and USL, dt = 0.001 (Figs. 9, 10);
  B. the same point with USF at dt = 0.1, 0.01, 0.001 and 0.0001 (Fig. 15): the largest error of
     v over t in [0, 2], which falls to the error of the semi-discrete point (its mass and
     stiffness follow its position), and the largest difference from a run at dt = 1e-5, which
     falls at first order in dt;
  C. the continuum bar in its first mode (examples/bar_mode1.toml: E = 10, rho = 1, L = 1,
     v(x, 0) = v0 sin(pi x / 2); the centre of mass moves with (2/pi) v0 cos(w1 t),
     w1 = (pi/2) sqrt(E/rho)), USF, dt = 0.001, with 3 or 7 points in one cell (2 nodes) or one
     point per cell on 3 or 7 cells (4 or 8 nodes) (Figs. 17, 18);
  D. that bar on 7 cells (8 nodes) with the boundary conditions imposed "correct"ly (BC1 + BC2)
     and "improper"ly (BC2 + BC3 without BC1: step.bc_ordering = "improper") (Figs. 23, 24),
     and the largest difference between the two.
The error of a run is the largest |v_cm - exact| over its frames (every 0.01 time units) in % of
the amplitude. Writes PREFIX.csv (one row per run: panel, case, dt, error, the difference of B and D, energy change)
and
PREFIX.png (a trailing .png of -o is dropped).
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
import figures  # noqa: E402
from figures import read_run, run_smpm, save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
POINT = ROOT / "examples" / "single_point_vibration.toml"
BAR = ROOT / "examples" / "bar_mode1.toml"
V0_POINT, W_POINT = 0.1, 2 * math.pi        # Buzzi Eq. 32: v = v0 cos(w t), w = sqrt(E/rho)/L
V0_BAR, W_BAR = 0.01, math.pi / 2 * math.sqrt(10.0)  # Eqs. 34-37: w1 = (pi / 2L) sqrt(E/rho)
BAR_END = 2 * (2 * math.pi / W_BAR)          # two periods


def point(scheme, dt):
    """Overrides of the single point with `scheme` and time step dt (C = dt c / dx, c = 2 pi)."""
    return POINT, [f"step.scheme={scheme}", f"time.courant={dt * W_POINT!r}",
                   "output.every=0.01", "time.land_on_frames=false"]


def bar(points, cells, ordering="correct"):
    """Overrides of the continuum bar on `cells` linear cells over [0, 1] (cells + 1 nodes) with
    `points` particles in all, USF, dt = 0.001."""
    h = 1.0 / cells
    return BAR, ["step.shape=linear", "grid.origin=[0.0]", f"grid.cell_size=[{h!r}]",
                 f"grid.cells=[{cells}]", f"body.0.ppc=[{points // cells}]",
                 f"time.courant={1e-3 * math.sqrt(10.0) / h!r}", f"time.end={BAR_END!r}",
                 "output.every=0.01", "time.land_on_frames=false",
                 f"step.bc_ordering={ordering}"]


def run(smpm, work, tag, src, sets, exact, amplitude):
    """(times, v_cm, exact, largest error in % of the amplitude, energy change in %)."""
    out = pathlib.Path(work) / (tag + ".h5")
    r, _ = run_smpm(smpm, src, out, sets)
    if r.returncode != 0:
        raise RuntimeError(f"{src.name} {' '.join(sets)}: {r.stderr.strip()}")
    result = read_run(out)
    t, v = [], []
    for k in range(len(result.times)):
        p = result.particles(k)
        t.append(float(p["@time"]))
        v.append(float((p["mass"] * p["V"][:, 0]).sum() / p["mass"].sum()))
    t, v = np.array(t), np.array(v)
    e = exact(t)
    total = result.series["total"]
    return (t, v, e, 100 * np.abs(v - e).max() / amplitude,
            100 * (total[-1] - total[0]) / total[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_output(ap, "buzzi", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    point_exact = (lambda t: V0_POINT * np.cos(W_POINT * t), V0_POINT)
    bar_exact = (lambda t: 2 / math.pi * V0_BAR * np.cos(W_BAR * t), 2 / math.pi * V0_BAR)
    todo = {}
    for scheme in ("USF", "USL"):
        todo[("A", f"single point, {scheme}", 1e-3)] = point(scheme, 1e-3) + point_exact
    for dt in (0.1, 0.01, 1e-3, 1e-4, 1e-5):
        todo[("B", "single point, USF", dt)] = point("USF", dt) + point_exact
    for points, cells in ((3, 1), (7, 1), (3, 3), (7, 7)):
        todo[("C", f"{points} points, {cells + 1} nodes", 1e-3)] = bar(points, cells) + bar_exact
    for ordering in ("correct", "improper"):
        todo[("D", f"7 points, 8 nodes, {ordering} BCs", 1e-3)] = \
            bar(7, 7, ordering) + bar_exact
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, f"r{i}", *v)
                   for i, (k, v) in enumerate(todo.items())}
        try:
            res = {k: f.result() for k, f in futures.items()}
        except RuntimeError as e:
            sys.exit(f"buzzi.py: {e}")
    # B: the difference from the finest run at the frames' times; D: improper against correct.
    reference = res[("B", "single point, USF", 1e-5)]
    correct = res[("D", "7 points, 8 nodes, correct BCs", 1e-3)]
    difference = {}
    for key, r in res.items():
        if key[0] == "B" and key[2] > 1e-5:
            difference[key] = 100 * np.abs(r[1] - np.interp(r[0], reference[0], reference[1])).max() / V0_POINT
        elif key[0] == "D" and "improper" in key[1]:
            difference[key] = 100 * np.abs(r[1] - correct[1]).max() / (2 / math.pi * V0_BAR)
    rows = [[panel, case, f"{dt:g}", f"{r[3]:.4g}",
             f"{difference[(panel, case, dt)]:.4g}" if (panel, case, dt) in difference else "",
             f"{r[4]:.4g}"] for (panel, case, dt), r in res.items()]
    print(f"{'panel':5s} {'case':34s} {'dt':>7s} {'error %':>9s} {'difference %':>13s} "
          f"{'energy %':>10s}")
    for row in rows:
        print(f"{row[0]:5s} {row[1]:34s} {row[2]:>7s} {float(row[3]):9.4g} {row[4]:>13s} "
              f"{float(row[5]):10.4g}")
    b = [(k[2], d) for k, d in difference.items() if k[0] == "B"]
    orders = [math.log10(e1 / e2) / math.log10(d1 / d2) for (d1, e1), (d2, e2) in zip(b, b[1:])]
    print("B: order in dt of the difference from dt = 1e-5: " +
          ", ".join(f"{o:.2f}" for o in orders))
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["panel", "case", "dt", "error_percent", "difference_percent",
                    "energy_change_percent"])
        w.writerows(rows)
    plt = figures.style()
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    titles = {"A": "A. one point, dt = 0.001 (Buzzi Figs. 9-10)",
              "C": "C. bar, USF: points and nodes (Figs. 17-18)",
              "D": "D. bar, 7 points, 8 nodes: BC ordering (Figs. 23-24)"}
    for ax, panel in zip((axes[0, 0], axes[1, 0], axes[1, 1]), "ACD"):
        exact_drawn = False
        for i, ((p, case, _), r) in enumerate((k, v) for k, v in res.items() if k[0] == panel):
            if not exact_drawn:
                ax.plot(r[0], r[2], "k-", lw=2.5, alpha=0.35, label="exact")
                exact_drawn = True
            d = difference.get((p, case, 1e-3))
            more = f"; {d:.2g}% from correct" if d is not None else ""
            ax.plot(r[0], r[1], color=f"C{i}", label=f"{case} ({r[3]:.2g}%{more})")
        ax.set_title(titles[panel])
        ax.set_xlabel("time $t$ (Buzzi's units)")
        ax.set_ylabel("velocity of the centre of mass (Buzzi's units)")
        ax.legend(fontsize="small", title="largest error, % of the amplitude")
    ax = axes[0, 1]
    errors = [(k[2], r[3]) for k, r in res.items() if k[0] == "B"]
    ax.loglog([d for d, _ in errors], [e for _, e in errors], "o-", label="against $v_0 \\cos \\omega t$")
    ax.loglog([d for d, _ in b], [e for _, e in b], "s-", label="against $\\Delta t = 10^{-5}$")
    d0, e0 = b[-1]
    ax.loglog([d for d, _ in b], [e0 * d / d0 for d, _ in b], "k:", label="first order")
    ax.set_xlabel("time step $\\Delta t$ (Buzzi's units)")
    ax.set_ylabel("largest velocity difference (% of $v_0$)")
    ax.set_title("B. one point: the time step (Buzzi Fig. 15)")
    ax.legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
