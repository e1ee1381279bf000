#!/usr/bin/python3
"""FMPM 2026 Figs. 8 and 9: an offset impact of two disks with Coulomb friction.

    analysis/fig9.py [--smpm build/apps/smpm] [--cell 1.0] [--jobs 2] [-o fig9]

Runs examples/disk_impact.toml with `smpm run` at cell size `cell` (mm; the grid keeps its
extent) for mu = 0, 0.3, 0.6 with FLIP, FMPM(1), FMPM(2) and FMPM(4) (Figs. 8 and 9A), and for
mu = 0.3 with FMPM(k), k = 1 ... 8 (Fig. 9B), two runs at a time. For each run it reports the
energy lost, 1 - (K + W + Q_friction)(end) / (K + W)(0) in % (the paper's U + K without heat
conduction: the frictional work stays as heat), the frictional work in % of the initial energy,
and each disk's centre-of-mass displacement at the end (the deflection grows with mu).
Writes <out>.csv and <out>.png (the trajectories of Fig. 8 and the losses of Fig. 9).
"""
import argparse
import concurrent.futures
import csv
import pathlib
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from figures import save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "disk_impact.toml"
EXTENT = (56.0, 48.0)  # the example's grid, mm


def updates():
    yield "FLIP", ["scheme.velocity=FLIP"]
    for k in (1, 2, 4):
        yield f"FMPM({k})", ["scheme.velocity=FMPM", f"scheme.order={k}"]


def cases():
    out = {}
    for mu in (0.0, 0.3, 0.6):
        for name, sets in updates():
            out[(mu, name)] = sets + [f"contact.0.friction={mu}"]
    for k in (3, 5, 6, 7, 8):
        out[(0.3, f"FMPM({k})")] = ["scheme.velocity=FMPM", f"scheme.order={k}",
                                   "contact.0.friction=0.3"]
    return out


def run(smpm, work, key, sets, cell):
    mu, name = key
    out = pathlib.Path(work) / f"mu{mu}_{name.replace('(', '').replace(')', '')}.h5"
    grid = [f"grid.cell_size=[{cell}, {cell}]",
            f"grid.cells=[{round(EXTENT[0] / cell)}, {round(EXTENT[1] / cell)}]"]
    args = [smpm, "run", str(INPUT), "-o", str(out), "-q"]
    for s in sets + grid:
        args += ["--set", s]
    start = time.time()
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{key}: {r.stderr.strip()}")
    with h5py.File(out, "r") as f:
        s = f["series"]
        e = s["kinetic"][:] + s["strain"][:]
        friction = s["friction"][:]
        centre = s["material_centre"][:]
        momentum = np.abs(s["momentum"][:]).max()
    return {"lost": 100 * (1 - (e[-1] + friction[-1]) / e[0]),
            "friction": 100 * friction[-1] / e[0], "centre": centre,
            "momentum": momentum, "seconds": time.time() - start}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cell", type=float, default=1.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("-o", "--out", default="fig9")
    a = ap.parse_args()
    todo = cases()
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, k, v, a.cell) for k, v in todo.items()}
        res = {k: f.result() for k, f in futures.items()}
    print(f"cell {a.cell} mm: energy lost 1 - (K + W + Q_friction)/E0 in %")
    print(f"{'mu':>4s} {'update':8s} {'lost %':>8s} {'friction %':>11s} {'left disk dx, dy (mm)':>24s}"
          f" {'|momentum|':>11s} {'run s':>6s}")
    rows = []
    for (mu, name), r in sorted(res.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        c = r["centre"]
        dx, dy = c[-1, 0] - c[0, 0], c[-1, 1] - c[0, 1]
        print(f"{mu:4.1f} {name:8s} {r['lost']:8.3f} {r['friction']:11.2f} {dx:11.3f} {dy:11.3f}"
              f" {r['momentum']:11.2e} {r['seconds']:6.1f}")
        rows.append([mu, name, f"{r['lost']:.4f}", f"{r['friction']:.4f}", f"{dx:.4f}", f"{dy:.4f}"])
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mu", "update", "energy_lost_percent", "friction_percent", "left_dx_mm",
                    "left_dy_mm"])
        w.writerows(rows)
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    colours = {0.0: "C0", 0.3: "C1", 0.6: "C2"}
    for (mu, name), r in res.items():
        if name not in ("FLIP", "FMPM(1)", "FMPM(4)"):
            continue
        c = r["centre"]
        style = {"FLIP": "-", "FMPM(4)": ":", "FMPM(1)": "--"}[name]
        for disk in (0, 1):
            axes[0].plot(c[:, 2 * disk] + (-2 if disk == 0 else 2),
                         c[:, 2 * disk + 1] - c[0, 2 * disk + 1], style, color=colours[mu],
                         label=f"mu = {mu}, {name}" if disk == 0 else None, lw=1)
    axes[0].set_title("Fig. 8: centres of mass (left disk x - 2, right x + 2 mm)")
    axes[0].set_xlabel("x (mm)")
    axes[0].set_ylabel("y - y0 (mm)")
    axes[0].legend(fontsize=6)
    for mu in (0.0, 0.3, 0.6):
        names = [n for n, _ in updates()]
        axes[1].plot(names, [res[(mu, n)]["lost"] for n in names], "o-", label=f"mu = {mu}")
    axes[1].set_title("Fig. 9A: energy lost (%)")
    axes[1].legend(fontsize=8)
    ks = list(range(1, 9))
    axes[2].plot(ks, [res[(0.3, f"FMPM({k})")]["lost"] for k in ks], "o-", label="FMPM(k)")
    axes[2].axhline(res[(0.3, "FLIP")]["lost"], color="k", lw=0.8, label="FLIP")
    axes[2].set_title("Fig. 9B: energy lost (%), mu = 0.3")
    axes[2].set_xlabel("k")
    axes[2].legend(fontsize=8)
    save_figure(fig, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
