#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Particles of one frame coloured by a field.

    analysis/plot_particles.py run.h5 --frame N --field stress_xx [-o out.png]

Fields: vx, vy, vz, speed, stress_xx, stress_xy, stress_yy, ..., pressure, mass, volume,
material, J (det F). 1D runs are drawn as field against x.
"""
import argparse
import pathlib
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

AXES = "xyz"


def field(g, name, d):
    if name in ("mass", "volume", "material"):
        return g[name][:].astype(float)
    V, S, F = g["V"][:], g["stress"][:], g["F"][:]
    if name == "speed":
        return np.linalg.norm(V, axis=1)
    if len(name) == 2 and name[0] == "v" and name[1] in AXES[:d]:
        return V[:, AXES.index(name[1])]
    if name.startswith("stress_") and len(name) == 9:
        a, b = AXES.find(name[7]), AXES.find(name[8])
        if 0 <= a < d and 0 <= b < d:
            return S[:, a * d + b]
    if name == "pressure":
        return -np.trace(S.reshape(-1, d, d), axis1=1, axis2=2) / 3.0
    if name == "J":
        return np.linalg.det(F.reshape(-1, d, d))
    raise KeyError(name)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--frame", type=int, default=-1, help="frame number (default: the last)")
    ap.add_argument("--field", default="speed")
    ap.add_argument("-o", "--output")
    args = ap.parse_args()
    try:
        f = h5py.File(args.run, "r")
    except OSError as e:
        sys.exit(f"plot_particles.py: {args.run}: cannot open ({e})")
    with f:
        frames = sorted(f["particles"].keys())
        name = frames[args.frame] if args.frame < 0 else f"{args.frame:06d}"
        if name not in f["particles"]:
            sys.exit(f"plot_particles.py: {args.run}: no frame {args.frame} (frames 0 to {len(frames) - 1})")
        g = f["particles"][name]
        X = g["X"][:]
        d = X.shape[1]
        try:
            c = field(g, args.field, d)
        except KeyError:
            sys.exit(f"plot_particles.py: unknown field '{args.field}' for a {d}D run")
        t = g.attrs["time"]
    out = pathlib.Path(args.output or f"{pathlib.Path(args.run).with_suffix('').as_posix()}_{name}_{args.field}.png")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    if d == 1:
        ax.plot(X[:, 0], c, ".")
        ax.set_xlabel("x")
        ax.set_ylabel(args.field)
    else:
        sc = ax.scatter(X[:, 0], X[:, 1], c=c, s=4, cmap="viridis")
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        fig.colorbar(sc, ax=ax, label=args.field)
    ax.set_title(f"{pathlib.Path(args.run).name}, frame {name}, t = {t:g}")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"{out}: {len(c)} particles, {args.field} in [{c.min():.4g}, {c.max():.4g}]")


if __name__ == "__main__":
    main()
