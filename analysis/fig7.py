#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 7: temperatures of two disks in an offset impact with friction.

    analysis/fig7.py [--smpm build/apps/smpm] [--cell 1.0] [--transport lumped|FMPM]
                     [--times 0.04,0.08,0.12,0.16] [--set section.key=value ...] [-o fig7]

Runs examples/disk_impact.toml with `smpm run` (mu = 0.6, FMPM(4) mechanics: the paper's Fig. 7)
with heat by `transport`: lumped (the default, NairnMPM's conduction: the lumped update, the
friction heat in its rate) or FMPM (FMPM(4) on the capacity matrix, which undershoots 300 K
beside the contact unless --set step.transport_limiter=fct) at cell size `cell` (mm; the grid
keeps its extent; the paper's is 1/3 mm; the peak rises as 1/cell, docs/studies/heat.md) and draws the
particles coloured by temperature at the frames nearest each of `times` (ms), from the lowest
temperature drawn (300 K unless the transport undershoots) to the highest, black to red as the
paper,
with an arrow at each disk's centre along its velocity. Prints and writes to PREFIX.csv, per
frame: time, the lowest, highest and capacity-weighted mean temperature, the heat Q and the
frictional work (mJ; equal, the heat comes from friction alone). Writes PREFIX.png (a trailing
.png of -o is dropped). --set changes an input entry of the run (--set time.end=0.02 for a short
run).
"""
import argparse
import csv
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import disks  # noqa: E402
from disks import ROOT, velocity  # noqa: E402
import figures  # noqa: E402
from figures import read_run, save_figure  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cell", type=float, default=1.0)
    ap.add_argument("--transport", choices=("lumped", "FMPM"), default="lumped")
    ap.add_argument("--times", default="0.04,0.08,0.12,0.16")
    figures.add_sets(ap)
    figures.add_output(ap, "fig7", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    times = [float(t) for t in a.times.split(",")]
    with tempfile.TemporaryDirectory() as work:
        out = pathlib.Path(work) / "fig7.h5"
        sets = (velocity("FMPM(4)", a.transport) + ["contact.0.friction=0.6"] +
                disks.grid(a.cell) + a.sets)
        try:
            r = disks.run(a.smpm, out, sets)
        except RuntimeError as e:
            sys.exit(f"fig7.py: {e}")
        run = read_run(out)
        frames = sorted({int(np.argmin(np.abs(np.asarray(run.times) - t))) for t in times})
        snaps = [run.particles(k) for k in frames]
        s = run.series
    t_hot = max(float(p["temperature"].max()) for p in snaps)
    # The scale starts at the lowest temperature drawn, so that an undershoot below the initial
    # 300 K (FMPM(k) transport without transport_limiter = "fct") shows rather than clips.
    t_cold = min(300.0, min(float(p["temperature"].min()) for p in snaps))
    heat = "lumped" if a.transport == "lumped" else "FMPM(4)"
    print(f"cell {a.cell} mm, mu = 0.6, FMPM(4), {heat} transport: highest temperature of the "
          f"run {r['t_max']:.1f} K (paper, 1/3 mm: 456 K); lowest {t_cold:.2f} K; U + K lost "
          f"{r['lost']:.2f}%")
    print(f"{'t (ms)':>8s} {'T min':>8s} {'T max':>8s} {'T mean':>8s} {'Q (mJ)':>9s}"
          f" {'friction (mJ)':>13s}")
    rows = []
    for k, p in zip(frames, snaps):
        step = int(np.searchsorted(s["t"], run.times[k] - 1e-12))
        T = p["temperature"]
        row = [run.times[k], T.min(), T.max(), s["temperature_mean"][step],
               s["heat"][step] - s["heat"][0], s["friction"][step]]
        print(f"{row[0]:8.3f} {row[1]:8.2f} {row[2]:8.2f} {row[3]:8.3f} {row[4]:9.3f}"
              f" {row[5]:13.3f}")
        rows.append([f"{v:.6g}" for v in row])
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["t_ms", "temperature_min_K", "temperature_max_K", "temperature_mean_K",
                    "heat_mJ", "friction_mJ"])
        w.writerows(rows)
    plt = figures.style()
    fig, axes = plt.subplots(1, len(snaps), figsize=(3.2 * len(snaps) + 1, 3.6), sharey=True,
                             squeeze=False)
    axes = axes[0]
    for ax, k, p in zip(axes, frames, snaps):
        X, T = p["X"], p["temperature"]
        order = np.argsort(T)  # the hottest drawn last, on top
        im = ax.scatter(X[order, 0], X[order, 1], c=T[order], s=2, cmap="hot", vmin=t_cold,
                        vmax=max(t_hot, t_cold + 1), linewidths=0, rasterized=True)
        for m in (0, 1):  # each disk's centre and velocity
            sel = p["material"] == m
            c = X[sel].mean(axis=0)
            v = p["V"][sel].mean(axis=0)
            ax.annotate("", xy=c + 0.08 * v, xytext=c,
                        arrowprops=dict(arrowstyle="->", color="tab:cyan", lw=1.5))
        ax.set_aspect("equal")
        ax.set_title(f"t = {run.times[k]:.3f} ms")
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    fig.colorbar(im, ax=axes[-1], label="temperature (K)")
    fig.suptitle(f"Two disks, $\\mu$ = 0.6, FMPM(4), {heat} transport, {a.cell:g} mm cells "
                 "(FMPM 2026 Fig. 7)")
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
