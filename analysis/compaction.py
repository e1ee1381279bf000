#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Compaction of elliptical objects in a box by a piston (contact 2020 §4, Fig. 6), at a
resolution that runs in about a minute.

    analysis/compaction.py [--smpm build/apps/smpm] [--objects 15] [--seed 1] [--jobs 2]
                           [--set section.key=value ...] [-o compaction]

Places `objects` random, non-overlapping, axis-aligned ellipses (semi-axes 2.5-6 mm) in a
40 x 40 mm box, each its own material (the hyperelastic material of contact 2020 Eq. 18,
K = 2450 MPa, G = 940 MPa, all the same), with frictional contact (Coulomb mu = 0.2) between
every pair, and pushes a piston down at 10 mm/ms until the box is 30% shorter. It runs the
same packing with grid contact (AG normals with CP = 0.8, and with DF) and with logistic
regression (LR normals and d_LR), and reports for each the piston's mean axial stress (mean sigma_yy of the particles)
and the interpenetration: the fraction of particles whose centre lies inside the deformed
domain (the ellipse inscribed in the initial domain, carried by F) of a particle of another
object. Writes PREFIX.toml (the input), PREFIX.csv and PREFIX.png (the final particles, x and
y in mm, each object in its own colour, named in the legend by its material, object0, ...; a
trailing .png of -o is dropped), and keeps the runs as
PREFIX_0.h5, PREFIX_1.h5, PREFIX_2.h5. --set changes an entry of every run (after the method's
own; --set time.end=0.2 for a short run).
"""
import argparse
import concurrent.futures
import csv
import pathlib
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from figures import read_run, run_smpm  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
BOX, CELL, SPEED, STRAIN = 40.0, 1.0, 10.0, 0.45
METHODS = {
    "AG, CP = 0.8": ["contact.0.normal=AG", "contact.0.detection=CP"],
    "AG, DF": ["contact.0.normal=AG", "contact.0.detection=DF"],
    "LR, d_LR": [],
}


def packing(n, seed):
    """n non-overlapping axis-aligned ellipses (centre, semi-axes) inside the box."""
    rng = np.random.default_rng(seed)
    placed = []
    for _ in range(20000):
        if len(placed) == n:
            break
        a, b = rng.uniform(2.5, 6.0, 2)
        c = rng.uniform([a + 0.5, b + 0.5], [BOX - a - 0.5, BOX - b - 0.5])
        ok = True
        for (c2, a2, b2) in placed:  # sample the boundary of the new ellipse, with a margin
            t = np.linspace(0, 2 * np.pi, 64)
            pts = c + np.c_[(a + 0.5) * np.cos(t), (b + 0.5) * np.sin(t)]
            if np.any(((pts[:, 0] - c2[0]) / (a2 + 0.5)) ** 2 + ((pts[:, 1] - c2[1]) / (b2 + 0.5)) ** 2 < 1) or \
                    np.hypot(*(c - c2)) < max(a, b, a2, b2):
                ok = False
                break
        if ok:
            placed.append((c, a, b))
    if len(placed) < n:
        raise SystemExit(f"could place only {len(placed)} of {n} ellipses; ask for fewer")
    return placed


def input_text(objects):
    lines = [
        "# Compaction of elliptical objects by a piston (contact 2020 Fig. 6), written by",
        "# analysis/compaction.py (15 objects, seed 1): each object its own material (the",
        "# hyperelastic material of contact 2020 Eq. 18; units mm, ms, g, MPa), Coulomb friction",
        "# mu = 0.2 with LR normals and d_LR between all, in a 40 x 40 mm box on rollers, a piston",
        "# pushing down at 10 mm/ms to 45% compaction. GIMP, USL, FLIP, C = 0.4.",
        "# How to run:  build/apps/smpm run examples/compaction.toml",
        "#              analysis/compaction.py (this packing with AG + CP, AG + DF and LR, and the",
        "#              interpenetration of each: the fraction of particles inside another object)",
        "# What to look at: the interpenetration at the end. Claimed (asserted by",
        "# tests/cli/test_compaction.py): grid contact leaves 0.72% (AG normals, CP = 0.8) and",
        "# 0.97% (AG, DF) of the particles inside another object, logistic regression none",
        "# (contact 2020 Fig. 6: LR removes the interpenetration of grid methods).",
        "[grid]", "dim = 2", "origin = [-4.0, -4.0]", f"cell_size = [{CELL}, {CELL}]",
        f"cells = [{int((BOX + 8) / CELL)}, {int((BOX + 8) / CELL)}]", ""]
    for k, (c, a, b) in enumerate(objects):
        lines += ["[[material]]", f'name = "object{k}"', 'model = "hyperelastic"',
                  "density = 0.001", "youngs = 2500.2", "poisson = 0.3299", "",
                  "[[body]]", f'material = "object{k}"', 'region = "ellipse"',
                  f"center = [{c[0]:.6f}, {c[1]:.6f}]", f"semi_axes = [{a:.6f}, {b:.6f}]",
                  "ppc = [2, 2]", ""]
    end = STRAIN * BOX / SPEED
    lines += ["[[contact]]   # every pair", 'law = "coulomb"', "friction = 0.2", 'normal = "LR"',
              'detection = "LR"', "",
              "[[bc]]", 'plane = { axis = "y", at = 0.0 }', 'fixed = ["y"]', "",
              "[[bc]]", 'plane = { axis = "x", at = 0.0 }', 'fixed = ["x"]', "",
              "[[bc]]", f'plane = {{ axis = "x", at = {BOX} }}', 'fixed = ["x"]', "",
              "[[bc]]   # the piston",
              f'wall = {{ normal = [0.0, 1.0], position = "{BOX} - {SPEED}*t", velocity = {-SPEED}, '
              'gradient = 0.0, depth_cells = 1.0 }', "",
              "[time]", "courant = 0.4", f"end = {end}", "",
              "[step]", 'scheme = "USL"', 'velocity = "FLIP"', 'shape = "gimp"', "",
              "[output]", f"every = {end / 6}", 'units = "mm-ms-g"', ""]
    return "\n".join(lines)


def interpenetration(X, F, r0, mat):
    """Fraction of particles whose centre is inside the deformed domain of a particle of
    another object (the ellipse of half-lengths r0 carried by F)."""
    tree = cKDTree(X)
    reach = 2.0 * r0.max() * max(1.0, np.abs(F).max())
    inside = np.zeros(len(X), bool)
    for p, q in tree.query_pairs(reach, output_type="ndarray"):
        if mat[p] == mat[q]:
            continue
        for a, b in ((p, q), (q, p)):  # is a's centre inside b's domain?
            Fb = F[b].reshape(2, 2)
            y = np.linalg.solve(Fb, X[a] - X[b]) / r0[b]
            if y @ y < 1:
                inside[a] = True
    return inside.mean()


def object_colours(n):
    """n colours, one for each object (object k takes the k-th): matplotlib's tab20, its ten
    strong colours first and then their ten light ones, so that up to 20 objects never share a
    colour (tab10, the first ten, was reused past ten objects); beyond 20, n colours spread
    over the turbo colour map."""
    import matplotlib
    import matplotlib.colors
    if n <= 20:
        tab = matplotlib.colormaps["tab20"].colors
        return [matplotlib.colors.to_hex(c) for c in (list(tab[0::2]) + list(tab[1::2]))[:n]]
    turbo = matplotlib.colormaps["turbo"]
    return [matplotlib.colors.to_hex(turbo(0.05 + 0.9 * i / (n - 1))) for i in range(n)]


def draw_objects(ax, X, mat, colours, size):
    """The particles at X on `ax`, each in the colour of its object (colours[mat])."""
    import matplotlib.colors
    ax.scatter(X[:, 0], X[:, 1], c=mat, cmap=matplotlib.colors.ListedColormap(colours),
               vmin=-0.5, vmax=len(colours) - 0.5, s=size)


def objects_legend(fig, colours, ncol):
    """A legend under the figure (left out of its tight layout, so that the panels keep their
    size) that names the object of each colour by its material name in the input (object0,
    object1, ...)."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], ls="none", marker="o", ms=6, color=c, label=f"object{k}")
               for k, c in enumerate(colours)]
    return fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=ncol,
                      title="objects (materials of the input), one colour each",
                      columnspacing=1.0, handletextpad=0.2)


def run(smpm, src, out, sets):
    r, secs = run_smpm(smpm, src, out, sets)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip())
    g = read_run(out).particles(-1)  # the last frame
    X, F, r0, mat = g["X"], g["F"], g["half_length"], g["material"]
    stress = g["stress"][:, 3].mean()
    t = g["@time"]
    return {"stress": stress, "interpenetration": interpenetration(X, F, r0, mat),
            "seconds": secs, "X": X, "mat": mat, "compaction": SPEED * t / BOX}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--objects", type=int, default=15)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "compaction", "PREFIX.toml, PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    src = pathlib.Path(a.out + ".toml")
    src.write_text(input_text(packing(a.objects, a.seed)))
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, src, pathlib.Path(f"{a.out}_{i}.h5"), v + a.sets)
                   for i, (k, v) in enumerate(METHODS.items())}
        results = {k: f.result() for k, f in futures.items()}
    compaction = min(r["compaction"] for r in results.values())
    print(f"{a.objects} objects compacted by {100 * compaction:.0f}%:")
    print(f"{'method':16s} {'mean sigma_yy':>14s} {'interpenetration':>17s} {'run (s)':>8s}")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["method", "mean_sigma_yy", "interpenetration", "seconds"])
        for k, r in results.items():
            print(f"{k:16s} {r['stress']:14.2f} {100 * r['interpenetration']:16.2f}% {r['seconds']:8.1f}")
            w.writerow([k, f"{r['stress']:.6g}", f"{r['interpenetration']:.6g}", f"{r['seconds']:.2f}"])
    plt = figures.style()
    height = 4.1 * (1 - compaction) + 1.3  # panels as high as the compacted box, and titles
    fig, axes = plt.subplots(1, len(results), figsize=(4.6 * len(results), height), sharey=True)
    colours = object_colours(a.objects)
    for ax, (k, r) in zip(np.atleast_1d(axes), results.items()):
        draw_objects(ax, r["X"], r["mat"], colours, 2)
        piston = BOX * (1 - r["compaction"])
        ax.plot([0, 0, BOX, BOX], [piston, 0, 0, piston], color="k", lw=1)  # box on rollers
        ax.plot([0, BOX], [piston, piston], color="gray", lw=3)  # the piston
        ax.set_aspect("equal")
        ax.grid(False)
        ax.set_title(f"{k}: {100 * r['interpenetration']:.2f}% interpenetrating,\n"
                     f"mean $\\sigma_{{yy}}$ = {r['stress']:.3g} MPa")
        ax.set_xlabel("$x$ (mm)")
    np.atleast_1d(axes)[0].set_ylabel("$y$ (mm)")
    objects_legend(fig, colours, ncol=min(a.objects, 8))
    fig.suptitle(f"{a.objects} objects compacted by {100 * compaction:.0f}% "
                 "(contact 2020 Fig. 6)")
    figures.save_figure(fig, a.out, tables=[f"{a.out}.toml", f"{a.out}.csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
