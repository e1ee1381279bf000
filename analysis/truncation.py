#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Truncation error of the FMPM(k) inverse against m̃⁻¹ (FMPM 2026 Eqs. 2, 5; §3.3 blending).

    analysis/truncation.py spectrum.csv [-o truncation]

Reads the table of `smpm spectrum` and plots ‖m̃_k⁻¹p − m̃⁻¹p‖/‖m̃⁻¹p‖ against k for each α and
blending period m, with the bound ρ(A)^k from the table's header. Writes PREFIX.png (a trailing
.png of -o is dropped).
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table")
    figures.add_output(ap, "truncation")
    args = ap.parse_args()
    try:
        lines = open(args.table).read().splitlines()
    except OSError as e:
        sys.exit(f"truncation.py: {args.table}: {e}")
    rows = figures.read_table(lines)
    series = {}
    for r in rows:
        series.setdefault((float(r["blend_alpha"]), int(r["blend_every"])), []).append(
            (int(r["order"]), float(r["truncation_error"])))
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for (alpha, m), pts in sorted(series.items(), reverse=True):
        pts.sort()
        name = "unblended" if alpha == 1 else f"$\\alpha$ = {alpha:g}, $m$ = {m}"
        ax.semilogy([p[0] for p in pts], [p[1] for p in pts], "-o", label=name)
    rho = float(rows[0]["rho_A"]) if rows else float("nan")
    ks = sorted({int(r["order"]) for r in rows})
    ax.semilogy(ks, [rho ** k for k in ks], "k:", label=f"$\\rho(A)^k$, $\\rho(A)$ = {rho:.4f}")
    ax.set_xscale("log")
    ax.set_xlabel("FMPM order $k$")
    ax.set_ylabel("relative error $\\Vert\\tilde m_k^{-1}p - \\tilde m^{-1}p\\Vert"
                  " \\,/\\, \\Vert\\tilde m^{-1}p\\Vert$")
    ax.set_title("Truncation error of FMPM($k$) (FMPM 2026 Eqs. 2, 5)")
    ax.legend()
    png = figures.save_figure(fig, figures.output_prefix(args.out), report=False)
    print(f"{png}: {len(rows)} rows from {args.table}")


if __name__ == "__main__":
    main()
