#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""C* and dissipation of FMPM's polynomial family against the number of products with m̃.

    analysis/polynomials.py [--smpm SMPM] [--bar BAR.toml] [--plate PLATE.toml]
                            [--orders 2,3,4,6,8,12,16] [--courant 0.1] [--shifts 4]
                            [--set section.key=value ...] [-o polynomials]

Every member of the family applies v⁺ = q(m⁻¹m̃) m⁻¹ p⁺ with k − 1 products with m̃
(docs/studies/polynomials.md): FMPM(k) (the series), FMPM(k) blended with FMPM(1) (α = 0.8),
Chebyshev, least squares and squared Chebyshev on [λ_lo, 1], λ_lo = λ_min(m⁻¹m̃) at t = 0. For
the bar and the plate of FMPM 2026 Fig. 12A it runs `smpm stability` (spectral C*, over the
lattice shifts) and, at one Courant number, `smpm run` for the change of the total energy over
the input's run (its dissipation), beside FLIP and the exact inverse. Writes PREFIX.csv (problem,
velocity, order, products, interval_low, critical_courant, energy_change_percent: "unstable"
where the run stopped), PREFIX_<problem>.csv (the stability tables), PREFIX.png (C* and the
energy change against k, one column per problem) and PREFIX_residual.png (R_k(λ) = 1 − λ q(λ)
of each member at k = 8 on the bar's interval, with the sparsempm module, else left out).
"""
import argparse
import csv
import math
import pathlib
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
import smpm_python  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
MEMBERS = ["FMPM", "blended", "chebyshev", "least_squares", "chebyshev_squared"]
LABEL = {"FMPM": "FMPM($k$), the series", "blended": "FMPM($k$) blended with FMPM(1), $\\alpha$ = 0.8",
         "chebyshev": "Chebyshev", "least_squares": "least squares",
         "chebyshev_squared": "squared Chebyshev"}
MARKER = {"FMPM": "o", "blended": "v", "chebyshev": "s", "least_squares": "D",
          "chebyshev_squared": "^"}
COLOUR = dict(zip(MEMBERS, figures.COLOURS))
# Where the energy panels mark a run that stopped (energy above 10x its start, or det F <= 0).
STOPPED = 3e3


def num(s):
    return float(s) if s not in ("", "none", None, "unstable") else math.nan


def stability(args, name, toml):
    """The stability table of one problem: its rows as {(member, k): row}."""
    out = pathlib.Path(f"{args.prefix}_{name}.csv")
    cmd = [args.smpm, "stability", str(toml), "--order", args.orders, "--polynomial",
           "chebyshev,least_squares,chebyshev_squared", "--blend-alpha", "0.8", "--blend-every",
           "1", "--periodic-cx", "none", "--shifts", str(args.shifts), "-q", "-o", str(out)]
    for s in args.sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"polynomials.py: {' '.join(cmd)}: {r.stderr.strip()}")
    rows = {}
    for row in figures.read_table(out):
        v = row["velocity"]
        if v == "FMPM" and num(row["blend_alpha"]) != 1:
            v = "blended"
        rows[(v, int(row["order"]) if row["order"] else 0)] = row
    return out, rows


def energy_change(args, name, toml, velocity, k, interval_low, work):
    """The total energy's change in % over the input's run at --courant, "unstable" when it
    stopped on a numerical failure."""
    sets = [f"time.courant={args.courant}"]
    if velocity in ("FLIP", "exact"):  # exact: the input's exact_* settings
        sets.append(f'step.velocity="{velocity}"')
    else:
        sets += [f'step.velocity="{"FMPM" if velocity == "blended" else velocity}"',
                 f"step.order={k}"]
        if velocity == "blended":
            sets += ["step.blend_alpha=0.8", "step.blend_every=1"]
        if velocity in ("chebyshev", "least_squares", "chebyshev_squared"):
            sets.append(f"step.interval_low={interval_low!r}")
    out = work / f"{name}_{velocity}_{k}.h5"
    r, _ = figures.run_smpm(args.smpm, toml, out, args.sets + sets)
    if r.returncode == 3:
        return "unstable"
    if r.returncode != 0:
        sys.exit(f"polynomials.py: smpm run {toml} {' '.join(sets)}: {r.stderr.strip()}")
    total = figures.read_run(out).series["total"]
    return f"{100 * (total[-1] - total[0]) / total[0]:.6g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--bar", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--plate", default=str(ROOT / "examples" / "vibrating_plate.toml"))
    ap.add_argument("--orders", default="2,3,4,6,8,12,16", help="orders k (k − 1 products)")
    ap.add_argument("--courant", type=float, default=0.1,
                    help="Courant number of the dissipation runs (default 0.1)")
    ap.add_argument("--shifts", type=int, default=4, help="lattice shifts of the C* sweep")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time")
    figures.add_sets(ap)
    smpm_python.add_arguments(ap)
    figures.add_output(ap, "polynomials", "PREFIX.png, PREFIX_residual.png and PREFIX.csv")
    args = ap.parse_args()
    args.prefix = figures.output_prefix(args.out)
    orders = sorted({int(k) for k in args.orders.split(",")})
    if any(k < 2 for k in orders):
        sys.exit("polynomials.py: --orders: every k must be at least 2 (k − 1 products)")
    scratch = tempfile.TemporaryDirectory(prefix="polynomials_")  # the runs' files
    work = pathlib.Path(scratch.name)
    problems = {"bar": args.bar, "plate": args.plate}
    tables, results = [], {}
    for name, toml in problems.items():
        path, rows = stability(args, name, toml)
        tables.append(path)
        lo = next(num(r["interval_low"]) for key, r in rows.items() if key[0] == "chebyshev")
        jobs = [("FLIP", 0), ("exact", 0)] + [(m, k) for m in MEMBERS for k in orders]
        with ThreadPoolExecutor(args.jobs) as pool:
            changes = list(pool.map(lambda j: energy_change(args, name, toml, j[0], j[1], lo, work),
                                    jobs))
        for (member, k), change in zip(jobs, changes):
            row = rows[(member, k)]  # FLIP and exact: order 0 (an empty cell)
            results[(name, member, k)] = {
                "problem": name, "velocity": member, "order": k if k else "",
                "products": k - 1 if k else ("0" if member == "FLIP" else ""),
                "interval_low": row["interval_low"], "critical_courant": row["critical_courant"],
                "energy_change_percent": change}
    scratch.cleanup()
    table = f"{args.prefix}.csv"
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["problem", "velocity", "order", "products",
                                          "interval_low", "critical_courant",
                                          "energy_change_percent"])
        w.writeheader()
        for r in results.values():
            w.writerow(r)
    tables.append(table)

    plt = figures.style()
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    for col, name in enumerate(problems):
        for row, (key, ylabel) in enumerate((("critical_courant", "critical Courant number $C^*$"),
                                             ("energy_change_percent",
                                              f"total energy change at $C$ = {args.courant:g} (%)"))):
            ax = axes[row][col]
            for member in MEMBERS:
                ys = [num(results[(name, member, k)][key]) for k in orders]
                ax.plot(orders, ys, "-", marker=MARKER[member], color=COLOUR[member],
                        label=LABEL[member])
                stopped = [k for k in orders if results[(name, member, k)][key] == "unstable"]
                if stopped:  # the runs that stopped, at the top of the energy panel
                    ax.plot(stopped, [STOPPED] * len(stopped), ls="none", marker="x", ms=8,
                            color=COLOUR[member])
            for member, colour, style in (("exact", "#882255", "--"), ("FLIP", "#555555", ":")):
                cell = results[(name, member, 0)][key]
                if cell == "unstable":
                    ax.plot([orders[-1]], [STOPPED], ls="none", marker="x", ms=8, color=colour)
                y = num(cell)
                if not math.isnan(y):
                    ax.axhline(y, color=colour, ls=style,
                               label=("exact $\\tilde m^{-1}$" if member == "exact" else "FLIP"))
            ax.set_xscale("log", base=2)
            ax.set_xticks(orders, [str(k) for k in orders])
            ax.set_ylabel(ylabel)
            if row == 1:  # gains of hundreds of per cent beside losses of a thousandth
                ax.set_yscale("symlog", linthresh=1e-3)
                ax.plot([], [], ls="none", marker="x", color="k",
                        label=f"run stopped (unstable), drawn at {STOPPED:g}")
            letter = "AB"[col] if row == 0 else "CD"[col]
            what = "C*" if row == 0 else "dissipation"
            ax.set_title(f"({letter}) {name}: {what}")
            if row == 1:
                ax.set_xlabel("order $k$ ($k - 1$ products with $\\tilde m$)")
    handles, names = axes[1][0].get_legend_handles_labels()
    fig.legend(handles, names, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=3, fontsize=9)
    figures.save_figure(fig, args.prefix, tables)

    sp = smpm_python.sparsempm(args)
    if sp is None:
        return
    import numpy as np
    lo = num(results[("bar", "chebyshev", orders[0])]["interval_low"])
    lam = np.linspace(0, 1, 801)
    k = 8
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    for member in ("FMPM", "chebyshev", "least_squares", "chebyshev_squared"):
        poly = "series" if member == "FMPM" else member
        R = sp.residual_polynomial(lam, k, poly, lo if poly != "series" else 0.0)
        ax.plot(lam, R, color=COLOUR[member], label=LABEL[member])
        bx.plot(lam, R, color=COLOUR[member], label=LABEL[member])
    for a in (ax, bx):
        a.axhline(0, color="k", lw=0.6)
        a.axvline(lo, color="#555555", ls=":", label=f"$\\lambda_{{lo}}$ = {lo:.4g}")
        a.set_xlabel("eigenvalue $\\lambda$ of $m^{-1}\\tilde m$ (dimensionless)")
        a.set_ylabel(f"$R_{k}(\\lambda) = 1 - \\lambda\\, q(\\lambda)$ (dimensionless)")
    bx.set_yscale("symlog", linthresh=1e-6)
    bx.set_xlim(lo / 2, 1)
    ax.set_title(f"(A) what each member leaves of a mode ($k$ = {k})")
    bx.set_title("(B) the same on a signed log scale: $V$ carries $1 - R$")
    ax.legend(fontsize=8)
    figures.save_figure(fig, f"{args.prefix}_residual")


if __name__ == "__main__":
    main()
