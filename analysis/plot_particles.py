#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Particles of one frame coloured by a field.

    analysis/plot_particles.py run.h5 --frame N --field stress_xx [--units input|mm-ms-g|SI]
                               [-o PREFIX]

Fields: vx, vy, vz, speed, stress_xx, stress_xy, stress_yy, ..., pressure, mass, volume,
material, J (det F). 1D runs are drawn as field against x, others as points coloured by the
field, with a colour bar as long as the drawing (below it when the body is wide: a bar 20 times
longer than high gets a bar along it, not one 20 times the body's height) whose ticks share one
power of ten. Writes PREFIX.png (default: <run>_<frame>_<field>.png; a trailing .png of -o is
dropped). The labels' units are the run file's (output.units) unless --units names others.
"""
import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402

AXES = "xyz"


def label(name, units):
    """The axis or colour-bar label of a field: its symbol and unit."""
    u = figures.UNITS[units]
    if name == "speed":
        return f"speed $|v|$ ({u['velocity']})"
    if len(name) == 2 and name[0] == "v":
        return f"velocity $v_{name[1]}$ ({u['velocity']})"
    if name.startswith("stress_"):
        return f"stress $\\sigma_{{{name[7:]}}}$ ({u['stress']})"
    return {"pressure": f"pressure $-\\mathrm{{tr}}\\,\\sigma/3$ ({u['stress']})",
            "mass": f"mass $m_p$ ({u['mass']})", "volume": f"volume $V_p$ ({u['volume']})",
            "material": "material id", "J": "volume ratio $J = \\det F$"}[name]


def field(g, name, d):
    """The field `name` of the particle arrays `g` (a frame of read_run) of a d-D run."""
    if name in ("mass", "volume", "material"):
        return g[name].astype(float)
    V, S, F = g["V"], g["stress"], g["F"]
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


def coloured_points(plt, X, c, what):
    """Points at X coloured by c, drawn to scale, with a colour bar labelled `what` as long as
    the drawing beside it (tall bodies) or below it (bodies more than twice as wide as high),
    its ticks in one power of ten (118000 MPa reads 1.18 × 10⁵)."""
    from matplotlib import ticker
    width, height = np.ptp(X[:, 0]) or 1.0, np.ptp(X[:, 1]) or 1.0
    wide = width > 2 * height
    fig, ax = plt.subplots(figsize=(7, 3.2) if wide else (7, 5))
    sc = ax.scatter(X[:, 0], X[:, 1], c=c, s=4)
    ax.set_aspect("equal")
    ax.grid(False)
    with plt.rc_context({"axes.grid": False}):  # a colour bar has no grid
        if wide:  # a bar along the body, as wide as the drawing
            bar = fig.colorbar(sc, ax=ax, label=what, orientation="horizontal", fraction=0.1,
                               pad=0.3, aspect=40)
        else:  # beside it, as tall as the drawing (fraction 0.046: the axes' height)
            bar = fig.colorbar(sc, ax=ax, label=what, fraction=0.046 * height / width,
                               pad=0.04)
    formatter = ticker.ScalarFormatter(useMathText=True)
    formatter.set_powerlimits((-3, 4))
    bar.formatter = formatter
    bar.locator = ticker.MaxNLocator(6)
    bar.update_ticks()
    return fig, ax


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--frame", type=int, default=-1,
                    help="frame number (default: the last; negative: counted from the last)")
    ap.add_argument("--field", default="speed")
    figures.add_output(ap, None, "PREFIX.png (default: <run>_<frame>_<field>)")
    figures.add_units(ap)
    args = ap.parse_args()
    try:
        run = figures.read_run(args.run)
    except OSError as e:
        sys.exit(f"plot_particles.py: {args.run}: cannot open ({e})")
    except ValueError as e:  # an HDF5 file that is no run file
        sys.exit(f"plot_particles.py: {e}")
    frames = run.frames  # the complete frames' numbers
    if args.frame < 0 and -len(frames) <= args.frame:
        index = args.frame
    elif args.frame in frames:
        index = frames.index(args.frame)
    else:
        sys.exit(f"plot_particles.py: {args.run}: no frame {args.frame} "
                 + (f"(frames {frames[0]} to {frames[-1]})" if frames else "(no complete frame)"))
    name = f"{frames[index]:06d}"
    g = run.particles(index)
    X = g["X"]
    d = X.shape[1]
    try:
        c = field(g, args.field, d)
    except KeyError:
        sys.exit(f"plot_particles.py: unknown field '{args.field}' for a {d}D run")
    t = g["@time"]
    prefix = figures.output_prefix(
        args.out or f"{pathlib.Path(args.run).with_suffix('').as_posix()}_{name}_{args.field}")
    units = figures.units_of(args.units, run)
    length, time_unit = figures.UNITS[units]["length"], figures.UNITS[units]["time"]
    plt = figures.style()
    if d == 1:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        ax.plot(X[:, 0], c, ".")
        ax.set_xlabel(f"$x$ ({length})")
        ax.set_ylabel(label(args.field, units))
    else:
        fig, ax = coloured_points(plt, X, c, label(args.field, units))
        ax.set_xlabel(f"$x$ ({length})")
        ax.set_ylabel(f"$y$ ({length})")
    ax.set_title(f"{pathlib.Path(args.run).name}, frame {name}, $t$ = {t:g} ({time_unit})")
    png = figures.save_figure(fig, prefix, report=False)
    print(f"{png}: {len(c)} particles, {args.field} in [{c.min():.4g}, {c.max():.4g}]")


if __name__ == "__main__":
    main()
