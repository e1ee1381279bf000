#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 11: energy lost by the two-disk impact against cell size and Courant number.

    analysis/fig11.py [--smpm build/apps/smpm] [--cells 2,1,0.5] [--courants 0.1,0.2,0.4]
                      [--cell-b 1] [--periodic-cx 0.8] [--jobs 2]
                      [--set section.key=value ...] [-o fig11]

Runs examples/disk_impact.toml (mu = 0.3) with `smpm run`: A, at C = 0.2 for each cell size
(mm; the grid keeps its extent) with FLIP and FMPM(4), each by USL and USL+; B, at cells of
`cell-b` mm (the paper's 1/3 mm: --cell-b 0.3333333333333333) for each Courant number with
FLIP, FMPM(4) and periodic FMPM(4) (FMPM on the steps that complete a Courant budget C_X,
the paper's 0.8) by USL. A run that fails (unstable) is a gap in its curve and a row with its
message. The energy lost is
1 - (U + K)(end) / (U + K)(0) in %, U = W + Q the strain energy and the heat of the run's heat
transport (negative: the run gained energy). Writes
PREFIX.csv and PREFIX.png (a trailing .png of -o is dropped); --set changes an input entry of
every run (--set time.end=0.02 for a short run). The paper's finest cells (0.05 mm) are out of
reach here; add 0.333 to --cells for the paper's standard resolution (about 30 s a run).
"""
import argparse
import concurrent.futures
import csv
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import disks  # noqa: E402
from disks import ROOT, grid, velocity  # noqa: E402
import figures  # noqa: E402
from figures import save_figure  # noqa: E402

UPDATES = {name: velocity(name) for name in ("FLIP", "FMPM(4)")}
PERIODIC = "periodic FMPM(4)"


def run(smpm, work, tag, sets):
    """(energy lost in %, "") or (nan, the command's message) when the run fails."""
    try:
        return disks.run(smpm, pathlib.Path(work) / (tag + ".h5"),
                         ["contact.0.friction=0.3"] + sets)["lost"], ""
    except RuntimeError as e:
        return float("nan"), str(e)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--cells", default="2,1,0.5")
    ap.add_argument("--courants", default="0.1,0.2,0.4")
    ap.add_argument("--cell-b", type=float, default=1.0)
    ap.add_argument("--periodic-cx", type=float, default=0.8)
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig11", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    cells = [float(c) for c in a.cells.split(",")]
    courants = [float(c) for c in a.courants.split(",")]
    todo = {}
    for cell in cells:
        for name, sets in UPDATES.items():
            for update in ("USL", "USL+"):
                todo[("A", cell, name, update)] = sets + grid(cell) + [f"step.scheme={update}"]
    updates_b = dict(UPDATES)
    updates_b[PERIODIC] = velocity("FMPM(4)") + [f"step.periodic_cx={a.periodic_cx}"]
    for c in courants:
        for name, sets in updates_b.items():
            todo[("B", c, name, "USL")] = sets + grid(a.cell_b) + [f"time.courant={c}"]
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, f"r{i}", v + a.sets)
                   for i, (k, v) in enumerate(todo.items())}
        res = {k: f.result() for k, f in futures.items()}
    rows = []
    print("A: energy lost (%) against cell size, C = 0.2, mu = 0.3")
    print(f"{'cell mm':>8s} " + " ".join(f"{n + ' ' + u:>14s}" for n in UPDATES
                                           for u in ("USL", "USL+")))
    for cell in cells:
        vals = [res[("A", cell, n, u)][0] for n in UPDATES for u in ("USL", "USL+")]
        print(f"{cell:8.3f} " + " ".join(f"{v:14.3f}" for v in vals))
    print(f"B: energy lost (%) against C, {a.cell_b:g} mm cells, USL, mu = 0.3 (C_X = "
          f"{a.periodic_cx:g})")
    print(f"{'C':>8s} " + " ".join(f"{n:>17s}" for n in updates_b))
    for c in courants:
        print(f"{c:8.2f} " + " ".join(f"{res[('B', c, n, 'USL')][0]:17.3f}" for n in updates_b))
    for (panel, x, name, update), (lost, err) in res.items():
        rows.append([panel, x, name, update, f"{lost:.4f}", err])
        if err:
            print(f"{panel} {x} {name} {update} failed: {err}")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["panel", "cell_or_courant", "velocity", "scheme", "energy_lost_percent",
                    "error"])
        w.writerows(rows)
    plt = figures.style()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for i, name in enumerate(UPDATES):  # a colour per update, a line style per scheme
        for update, style in (("USL", "o-"), ("USL+", "s--")):
            axes[0].plot(cells, [res[("A", c, name, update)][0] for c in cells], style,
                         color=f"C{i}", label=f"{name} {update}")
    # Panel B's scale holds the runs that kept their energy within 5% (gained) to 20% (lost);
    # a run beyond it (unstable, but not stopped) is a triangle at the edge with its value, and
    # a run that failed a cross at the top.
    values_b = [res[("B", c, n, "USL")][0] for c in courants for n in updates_b]
    shown = [v for v in values_b if -5 <= v <= 20] or [0.0]
    lo, hi = min(shown + [0.0]), max(shown)
    pad = 0.15 * (hi - lo) + 0.1
    lo, hi = lo - pad, hi + pad
    for i, name in enumerate(updates_b):
        ys = [res[("B", c, name, "USL")][0] for c in courants]
        inside = [y if lo <= y <= hi else float("nan") for y in ys]
        axes[1].plot(courants, inside, "o-", color=f"C{i}",
                     label=name + (f", $C_X$ = {a.periodic_cx:g}" if name == PERIODIC else ""))
        for c, y in zip(courants, ys):
            if y != y:  # failed
                axes[1].plot([c], [hi - 0.02 * (hi - lo) * (1 + i)], "x", color=f"C{i}", ms=8)
            elif not lo <= y <= hi:
                edge = lo if y < lo else hi
                axes[1].plot([c], [edge], "v" if y < lo else "^", color=f"C{i}", ms=8)
                axes[1].annotate(f"{y:.1f}%", (c, edge), textcoords="offset points",
                                 xytext=(-30, 8 if y < lo else -14), color=f"C{i}")
    axes[1].set_ylim(lo, hi)
    axes[1].text(0.02, 0.97, "x: the run failed", transform=axes[1].transAxes, va="top")
    axes[0].set_xlabel("cell size $\\Delta x$ (mm)")
    axes[0].set_title("Fig. 11A: $C$ = 0.2, $\\mu$ = 0.3")
    axes[0].set_ylabel("energy lost $1 - (U + K)/(U + K)_0$ (%)")
    axes[1].set_xlabel("Courant number $C$")
    axes[1].set_title(f"Fig. 11B: {a.cell_b:.3g} mm cells, USL, $\\mu$ = 0.3")
    axes[1].set_ylabel("energy lost $1 - (U + K)/(U + K)_0$ (%)")
    for ax in axes:
        ax.axhline(0, color="k", lw=0.6)
        ax.legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
