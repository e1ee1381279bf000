#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Spectral radius ρ(T) of the linearised update over a (k, α) grid at a fixed Courant number.

    analysis/rho_map.py [--courant 0.4] [--input examples/vibrating_bar.toml] [--build build/python]

ρ(T(C)) of FMPM(k) blended with FMPM(1) (m = 1) at the input's initial configuration, from the
Python module sparsempm (LinearizedStep and spectral_radius), or from `smpm spectrum --courant C`
(--smpm) when the module does not import or with --cli. Writes rho_map.csv (the table behind
the figure: k, alpha, blend_every, courant, rho_T to 10 digits, as `smpm spectrum` writes it)
and rho_map.png; ρ(T) > 1 marks an unstable (k, α).
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import smpm_python  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
KS = [1, 2, 3, 4, 6, 8, 12, 16, 24, 40]
ALPHAS = [1.0, 0.95, 0.9, 0.85, 0.8, 0.7, 0.6, 0.5]


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
                rho[k, alpha] = f"{smpm.spectral_radius(T).rho:.10g}"
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
        rows = list(csv.DictReader(l for l in open(out) if not l.startswith("#")))
    return {(int(row["order"]), float(row["blend_alpha"])): row["rho_T"] for row in rows}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--input", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--courant", type=float, default=0.4)
    ap.add_argument("-o", "--output", default="rho_map.png")
    smpm_python.add_arguments(ap)
    args = ap.parse_args()
    smpm = smpm_python.sparsempm(args)
    rho = rho_module(smpm, args) if smpm else rho_cli(args)
    table = pathlib.Path(args.output).with_suffix(".csv")
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["order", "blend_alpha", "blend_every", "courant", "rho_T"])
        w.writerows((k, f"{alpha:g}", 1, args.courant, rho[k, alpha]) for alpha in ALPHAS for k in KS)
    grid = np.array([[float(rho[k, alpha]) for k in KS] for alpha in ALPHAS])
    fig, ax = plt.subplots(figsize=(7, 4.5))
    im = ax.imshow(np.log10(np.maximum(grid - 1, 1e-16)), aspect="auto", cmap="magma", origin="lower")
    ax.set_xticks(range(len(KS)), KS)
    ax.set_yticks(range(len(ALPHAS)), ALPHAS)
    ax.set_xlabel("FMPM order k")
    ax.set_ylabel("blending fraction α (with FMPM(1))")
    ax.set_title(f"log10(ρ(T) − 1) at C = {args.courant}  (≤ −6: stable)")
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"{args.output} and {table} ({'sparsempm ' + smpm.__version__ if smpm else args.smpm})")


if __name__ == "__main__":
    main()
