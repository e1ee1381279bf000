#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The two waves of a bar pushed into plastic flow (examples/plastic_bar.toml): strain and
plastic strain along the bar against the elastic–plastic closed form.

    analysis/plastic_bar.py [--smpm build/apps/smpm] [--set section.key=value ...]
                            [-o plastic_bar]

Runs the example with `smpm run` and draws, at its last frame, the compressive strain 1 − F_xx
of the particles against X beside the two-wave solution of uniaxial strain (Simo & Hughes 1998,
Box 9.1, perfect plasticity): the elastic precursor at ε_HEL = σ_y/(2G) reaching c_e t,
c_e = √((K + 4G/3)/ρ), and the plastic front at ε_HEL + (v₀ − c_e ε_HEL)/c_p reaching c_p t,
c_p = √(K/ρ); below it, the equivalent plastic strain, (2/3)(ε − ε_HEL) behind the plastic front
and zero ahead of it.
Prints where each front is found (the last particle whose strain exceeds the middle of its
jump) against c t, and writes PREFIX.png and PREFIX.csv (X, strain, plastic strain, the closed
form); a trailing .png of -o is dropped. --set changes an input entry (e.g. --set time.end=50).
"""
import argparse
import csv
import pathlib
import sys
import tempfile
import tomllib

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "plastic_bar.toml"


def with_overrides(doc, sets):
    """The parsed input `doc` with the --set overrides applied as smpm applies them (entries of
    [[material]] and [[bc]] by index or name): the run file stores them as comments only."""
    for key, value in figures.set_values(sets).items():
        *path, last = key.split(".")
        node = doc
        for part in path:
            if isinstance(node, list):
                node = node[int(part)] if part.isdigit() else \
                    next(e for e in node if e.get("name") == part)
            else:
                node = node.setdefault(part, {})
        node[last] = value
    return doc


def closed_form(material, v0, t):
    """(ε_HEL, c_e, ε_plastic, c_p) of the bar: uniaxial strain, elastic–perfectly plastic."""
    E, nu, rho, sy = (material[k] for k in ("youngs", "poisson", "density", "yield_stress"))
    K, G = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    ce, cp = np.sqrt((K + 4 * G / 3) / rho), np.sqrt(K / rho)
    e_hel = sy / (2 * G)
    return e_hel, ce, e_hel + (v0 - ce * e_hel) / cp, cp


def front(X, strain, level):
    """The largest X at which the strain exceeds `level`."""
    return float(X[strain > level].max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default="smpm", help="the smpm program (default: on the PATH)")
    figures.add_sets(ap)
    figures.add_output(ap, "plastic_bar")
    a = ap.parse_args()
    prefix = figures.output_prefix(a.out)
    with tempfile.TemporaryDirectory() as work:
        out = pathlib.Path(work) / "plastic_bar.h5"
        r, seconds = figures.run_smpm(a.smpm, EXAMPLE, out, a.sets)
        if r.returncode != 0:
            sys.exit(f"plastic_bar.py: smpm run failed: {r.stderr.strip()}")
        run = figures.read_run(out)
        p = run.particles(-1)
        doc = with_overrides(tomllib.loads(EXAMPLE.read_text()), a.sets)
    t = float(p["@time"])
    X, strain = p["X"][:, 0], 1 - p["F"][:, 0]
    eps_p = p["plastic_strain"]
    order = np.argsort(X)
    X, strain, eps_p = X[order], strain[order], eps_p[order]
    v0 = abs(float(doc["bc"][0]["velocity"]["value"]))  # the end pushed into the bar
    e_hel, ce, e_pl, cp = closed_form(doc["material"][0], v0, t)
    x0 = float(doc["body"][0]["min"][0])
    exact = np.where(X - x0 < cp * t, e_pl, np.where(X - x0 < ce * t, e_hel, 0.0))
    # ε̄ᵖ = √(2/3) ‖εᵖ‖ with εᵖ = (2/3)(ε − ε_HEL) diag(1, −½, −½) in uniaxial strain (small
    # strain): ε̄ᵖ = (2/3)(ε − ε_HEL)
    exact_p = np.where(X - x0 < cp * t, 2 * (e_pl - e_hel) / 3, 0.0)
    found_e = front(X, strain, e_hel / 2) - x0
    found_p = front(X, strain, (e_hel + e_pl) / 2) - x0

    plt = figures.style()
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, height_ratios=[2, 1])
    ax.plot(X, strain, ".", ms=3, label="particles")
    ax.plot(X, exact, "k--", lw=1.2, label="closed form: precursor $\\varepsilon_{HEL}$ at $c_e t$,"
            " plastic front at $c_p t$")
    ax.set_ylabel("strain $1 - F_{xx}$ (dimensionless)")
    ax.set_title(f"Elastic–plastic bar at $t$ = {t:g}: two waves (J2, uniaxial strain)")
    # The scale of the waves: the particles at the driven end, off it, are counted.
    lo, hi = -0.25 * e_pl, 1.6 * e_pl
    off = int(((strain < lo) | (strain > hi)).sum())
    ax.set_ylim(lo, hi)
    if off:
        ax.text(0.01, 0.03, f"{off} particles at the driven end off the scale", fontsize=9,
                transform=ax.transAxes)
    ax.legend(loc="upper right")
    bx.plot(X, eps_p, ".", ms=3, color=figures.COLOURS[1], label="particles")
    bx.plot(X, exact_p, "k--", lw=1.2, label="closed form $\\frac{2}{3}(\\varepsilon - "
            "\\varepsilon_{HEL})$ behind $c_p t$")
    bx.set_xlabel("position $X$ (input units)")
    bx.set_ylabel("$\\bar\\varepsilon^p$ (dimensionless)")
    bx.set_ylim(-0.1 * e_pl, 1.1 * e_pl)
    bx.legend(loc="upper right")
    with open(f"{prefix}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["X", "strain", "plastic_strain", "closed_form", "closed_form_plastic"])
        w.writerows(zip(X, strain, eps_p, exact, exact_p))
    figures.save_figure(fig, prefix, [f"{prefix}.csv"])
    print(f"precursor at {found_e:.2f} against c_e t = {ce * t:.2f}; plastic front at "
          f"{found_p:.2f} against c_p t = {cp * t:.2f} (run {seconds:.1f} s)")


if __name__ == "__main__":
    main()
