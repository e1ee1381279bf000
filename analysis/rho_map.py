#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Spectral radius ρ(T) of the linearised update over a (k, α) grid at a fixed Courant number.

    analysis/rho_map.py [--courant 0.6] [--input examples/vibrating_bar.toml] [--build build/python]
                        [-o rho_map]

ρ(T(C)) of FMPM(k) blended with FMPM(1) (m = 1) at the input's initial configuration, from the
Python module sparsempm (LinearizedStep and spectral_radius), or from `smpm spectrum --courant C`
(--smpm) when the module does not import or with --cli. Writes PREFIX.csv (the table behind
the figure: k, alpha, blend_every, courant, rho_T to 10 digits, as `smpm spectrum` writes it)
and PREFIX.png (a trailing .png of -o is dropped); ρ(T) > 1 + 10⁻⁶ marks an unstable (k, α).
The default C = 0.6 lies between the limits of the unblended orders at this configuration, so
the map shows where blending restores stability; at C ≤ 0.5 every cell of the bar is stable.
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
import smpm_python  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
KS = [1, 2, 3, 4, 6, 8, 12, 16, 24, 40]
ALPHAS = [1.0, 0.95, 0.9, 0.85, 0.8, 0.7, 0.6, 0.5]
TOL = 1e-6  # ρ ≤ 1 + TOL is stable, as critical_courant counts it


def rho_module(smpm, args):
    """{(k, α): ρ(T)} from the module, with the options `smpm spectrum` gives each row."""
    rho = {}
    try:
        model = smpm.Model.from_toml(args.input)
        for alpha in ALPHAS:
            for k in KS:
                o = model.options.copy()
                o.velocity, o.order, o.blend_alpha, o.blend_every, o.periodic_cx = "FMPM", k, alpha, 1, 0.0
                T = smpm.LinearizedStep(model, o, args.courant)
                rho[k, alpha] = f"{smpm.spectral_radius(T).rho_T:.10g}"
    except smpm.InputError as e:
        sys.exit(f"rho_map.py: {e}")
    return rho


def rho_cli(args):
    """{(k, α): ρ(T)} from the table of `smpm spectrum --courant`."""
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "spectrum.csv"
        r = subprocess.run([args.smpm, "spectrum", args.input, "--courant", str(args.courant),
                            "--order", ",".join(map(str, KS)), "--blend-alpha", ",".join(map(str, ALPHAS)),
                            "--blend-every", "1", "-o", str(out)], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"rho_map.py: smpm spectrum failed: {r.stderr.strip()}")
        rows = figures.read_table(out)
    return {(int(row["order"]), float(row["blend_alpha"])): row["rho_T"] for row in rows}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--input", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--courant", type=float, default=0.6)
    figures.add_output(ap, "rho_map", "PREFIX.csv and PREFIX.png")
    smpm_python.add_arguments(ap)
    args = ap.parse_args()
    prefix = figures.output_prefix(args.out)
    smpm = smpm_python.sparsempm(args)
    rho = rho_module(smpm, args) if smpm else rho_cli(args)
    table = prefix + ".csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["order", "blend_alpha", "blend_every", "courant", "rho_T"])
        w.writerows((k, f"{alpha:g}", 1, args.courant, rho[k, alpha]) for alpha in ALPHAS for k in KS)
    grid = np.array([[float(rho[k, alpha]) for k in KS] for alpha in ALPHAS])
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    top = max(grid.max(), 1 + 1e-3)
    im = ax.imshow(grid, aspect="auto", cmap="magma_r", origin="upper", vmin=1, vmax=top)
    stable = grid <= 1 + TOL
    for (i, j), r in np.ndenumerate(grid):  # each cell's value; "1" where stable
        dark = (r - 1) / (top - 1) > 0.55
        ax.text(j, i, "1" if stable[i, j] else f"{r:.2f}", ha="center", va="center", fontsize=7,
                color="white" if dark else "black")
    for i in range(len(ALPHAS)):  # the frontier: edges between a stable and an unstable cell
        for j in range(len(KS)):
            if j + 1 < len(KS) and stable[i, j] != stable[i, j + 1]:
                ax.plot([j + 0.5, j + 0.5], [i - 0.5, i + 0.5], color="#44AA99", lw=2.5)
            if i + 1 < len(ALPHAS) and stable[i, j] != stable[i + 1, j]:
                ax.plot([j - 0.5, j + 0.5], [i + 0.5, i + 0.5], color="#44AA99", lw=2.5)
    ax.grid(False)
    ax.set_xticks(range(len(KS)), KS)
    ax.set_yticks(range(len(ALPHAS)), [f"{a:g}" for a in ALPHAS])
    ax.set_xlabel("FMPM order $k$")
    ax.set_ylabel("blending fraction $\\alpha$ (with FMPM(1))")
    ax.set_title(f"$\\rho(T)$ at $C$ = {args.courant:g}: {int(stable.sum())} of {stable.size} "
                 f"stable ($\\rho \\leq 1 + 10^{{-6}}$; the line is the frontier)")
    fig.colorbar(im, ax=ax, label="spectral radius $\\rho(T)$ of the linearised step")
    png = figures.save_figure(fig, prefix, report=False)
    print(f"{png} and {table} ({'sparsempm ' + smpm.__version__ if smpm else args.smpm})")


if __name__ == "__main__":
    main()
