#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Truncation error of the FMPM(k) inverse against m̃⁻¹ (FMPM 2026 Eqs. 2, 5; §3.3 blending).

    analysis/truncation.py spectrum.csv [-o truncation.png]

Reads the table of `smpm spectrum` and plots ‖m̃_k⁻¹p − m̃⁻¹p‖/‖m̃⁻¹p‖ against k for each α and
blending period m, with the bound ρ(A)^k from the table's header.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table")
    ap.add_argument("-o", "--output", default="truncation.png")
    args = ap.parse_args()
    try:
        lines = open(args.table).read().splitlines()
    except OSError as e:
        sys.exit(f"truncation.py: {args.table}: {e}")
    header = dict(l[2:].split(" = ") for l in lines if l.startswith("# "))
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    series = {}
    for r in rows:
        series.setdefault((float(r["blend_alpha"]), int(r["blend_every"])), []).append(
            (int(r["order"]), float(r["truncation_error"])))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for (alpha, m), pts in sorted(series.items(), reverse=True):
        pts.sort()
        ax.semilogy([p[0] for p in pts], [p[1] for p in pts], "-o", label=f"α = {alpha:g}, m = {m}")
    rho = float(header.get("rho_A", "nan"))
    ks = sorted({int(r["order"]) for r in rows})
    ax.semilogy(ks, [rho ** k for k in ks], "k:", label=f"ρ(A)^k, ρ(A) = {rho:.4f}")
    ax.set_xscale("log")
    ax.set_xlabel("FMPM order k")
    ax.set_ylabel("relative error against m̃⁻¹p")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"{args.output}: {len(rows)} rows from {args.table}")


if __name__ == "__main__":
    main()
