#!/usr/bin/python3
"""Spectral radius ρ(T) of the linearised update over a (k, α) grid at a fixed Courant number.

    analysis/rho_map.py [--courant 0.4] [--smpm build/apps/smpm] [--input examples/vibrating_bar.toml]

Runs `smpm spectrum --courant C` (FMPM(k) blended with FMPM(1), m = 1), writes rho_map.csv (the
table behind the figure) and rho_map.png; ρ(T) > 1 marks an unstable (k, α).
"""
import argparse
import csv
import pathlib
import subprocess
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--input", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--courant", type=float, default=0.4)
    ap.add_argument("-o", "--output", default="rho_map.png")
    args = ap.parse_args()
    ks = [1, 2, 3, 4, 6, 8, 12, 16, 24, 40]
    alphas = [1.0, 0.95, 0.9, 0.85, 0.8, 0.7, 0.6, 0.5]
    table = pathlib.Path(args.output).with_suffix(".csv")
    r = subprocess.run([args.smpm, "spectrum", args.input, "--courant", str(args.courant),
                        "--k", ",".join(map(str, ks)), "--alpha", ",".join(map(str, alphas)),
                        "--every", "1", "-o", str(table)], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"rho_map.py: smpm spectrum failed: {r.stderr.strip()}")
    rows = list(csv.DictReader(l for l in open(table) if not l.startswith("#")))
    grid = np.full((len(alphas), len(ks)), np.nan)
    for row in rows:
        grid[alphas.index(float(row["alpha"])), ks.index(int(row["k"]))] = float(row["rho_T"])
    fig, ax = plt.subplots(figsize=(7, 4.5))
    im = ax.imshow(np.log10(np.maximum(grid - 1, 1e-16)), aspect="auto", cmap="magma", origin="lower")
    ax.set_xticks(range(len(ks)), ks)
    ax.set_yticks(range(len(alphas)), alphas)
    ax.set_xlabel("FMPM order k")
    ax.set_ylabel("blending fraction α (with FMPM(1))")
    ax.set_title(f"log10(ρ(T) − 1) at C = {args.courant}  (≤ −6: stable)")
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"{args.output} and {table}")


if __name__ == "__main__":
    main()
