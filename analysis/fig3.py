#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 3: velocity error of the moving-wall manufactured solution (§3.1).

    analysis/fig3.py [--smpm build/apps/smpm] [--jobs 2] [--quick] [--orders 1,2,3,4,6,8,12]
                     [--depths 0.5,1,1.5,2] [--set section.key=value ...] [-o fig3]

Runs examples/moving_wall_mms.toml with `smpm run` for FLIP, FMPM(k) with the new
(incremental) and the prior combined BC method, and the exact consistent-mass inverse
(regularised with eps = 1e-4: plain m~ becomes singular to round-off at t = 51 s), for
k in {1, 2, 3, 4, 6, 8, 12}, wall depths d in {0.5, 1, 1.5, 2} cells and the CPDI and B2CPDI
shape functions, two runs at a time. Each run's error is the paper's

    <Velocity Error>(%) = 100 / (N_s V_end) * sum over steps of sqrt((1/N) sum_p |V_p(t) - V_p(0)|^2),

V_end = 10 edot, read from the run's series (velocity_change_sum); sigma_xx of the interior
particles (|X| < 8 m) is compared with 2G(2 + edot t) edot t / (2(1 + edot t)). Writes
PREFIX.csv, PREFIXa.png (error against k, CPDI, d = 1 cell: Fig. 3A) and PREFIXb.png (error against
d for FLIP and k = 1, 2, 4, 8, CPDI solid and B2CPDI dashed, the combined method for k = 4, 8:
Fig. 3B; colours the methods, line styles the shapes); a trailing .png of -o is dropped. --quick
runs only what Fig. 3A needs (CPDI, d = 1); --orders and --depths choose k and d (Fig. 3A is
drawn at d = 1 when it is among them, else at the first depth); --set changes an input entry of
every run (--set time.end=10 for a short run).
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
EDOT, G = 3e-3, 0.375
ORDERS = [1, 2, 3, 4, 6, 8, 12]
DEPTHS = [0.5, 1.0, 1.5, 2.0]


def cases(quick, orders=ORDERS, depths=DEPTHS):
    """(shape, depth, method, k) of every run; method FLIP | new | combined | exact."""
    shapes = ["cpdi"] if quick else ["cpdi", "b2cpdi"]
    depths = [1.0] if quick else depths
    for shape in shapes:
        for d in depths:
            yield shape, d, "FLIP", 1
            yield shape, d, "exact", 0
            for k in orders:
                yield shape, d, "new", k
                if k > 2:  # k <= 2: the combined method is the new one (FMPM 2026 §3.1)
                    yield shape, d, "combined", k


def run(smpm, workdir, case, extra=()):
    """One run of `case` with the overrides `extra` after the case's own; its table row."""
    shape, d, method, k = case
    out = pathlib.Path(workdir) / f"{shape}_{d}_{method}_{k}.h5"
    sets = [f"step.shape={shape}", "output.every=66.66666666666667",
            f"bc.0.wall.depth_cells={d}", f"bc.1.wall.depth_cells={d}"]
    if method == "FLIP":
        sets += ["step.velocity=FLIP"]
    elif method == "exact":  # m~ + light nodes is singular to round-off late in the run (docs/studies/moving-walls.md)
        sets += ["step.velocity=exact", "step.exact_regularization=1e-4"]
    else:
        sets += ["step.velocity=FMPM", f"step.order={k}",
                 "step.bc_method=" + ("incremental" if method == "new" else "combined")]
    r, seconds = figures.run_smpm(smpm, ROOT / "examples" / "moving_wall_mms.toml", out,
                                  sets + list(extra))
    row = {"shape": shape, "depth_cells": d, "method": method, "order": k, "seconds": round(seconds, 2)}
    if r.returncode != 0:
        row.update(error_percent="", sigma_rel_error="", steps="", note=r.stderr.strip().replace(",", ";")[:160])
        return row
    result = figures.read_run(out)
    s = result.series
    steps = len(s["t"]) - 1
    err = 100 * s["velocity_change_sum"][-1] / (steps * 10 * EDOT)
    p = result.particles(-1)  # the last frame
    e = EDOT * p["@time"]
    exact = 2 * G * (2 + e) * e / (2 * (1 + e))
    inner = np.abs(p["X"][:, 0]) < 8
    sig = float(np.abs(p["stress"][inner, 0] / exact - 1).max())
    out.unlink()
    out.with_suffix(".xmf").unlink(missing_ok=True)
    row.update(error_percent=f"{err:.6g}", sigma_rel_error=f"{sig:.3g}", steps=steps, note="")
    return row


def num(s):
    return float(s) if s not in ("", None) else math.nan


def plot(rows, prefix):
    def err(shape, d, method, k):
        for r in rows:
            if (r["shape"], float(r["depth_cells"]), r["method"], int(r["order"])) == (shape, d, method, k):
                return num(r["error_percent"])
        return math.nan

    orders = sorted({int(r["order"]) for r in rows if r["method"] == "new"})
    depths = sorted({float(r["depth_cells"]) for r in rows})
    d1 = 1.0 if 1.0 in depths else depths[0]
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method, style in (("new", "-o"), ("combined", "-s")):
        ks = [k for k in orders if method == "new" or k > 2]
        if ks:
            ax.plot(ks, [err("cpdi", d1, method, k) for k in ks], style,
                    label=f"FMPM($k$), {method} BC method")
    ax.axhline(err("cpdi", d1, "FLIP", 1), color="k", ls="--", label="FLIP")
    ex = err("cpdi", d1, "exact", 0)
    if not math.isnan(ex):
        ax.axhline(ex, color="purple", ls=":",
                   label="exact $(1 - \\varepsilon)\\tilde m + \\varepsilon m$, "
                         "$\\varepsilon = 10^{-4}$ ($k \\to \\infty$)")
    ax.set_yscale("log")
    ax.set_xlabel("FMPM order $k$")
    ax.set_ylabel("$\\langle$Velocity Error$\\rangle$ (%)")
    ax.set_title(f"Moving-wall MMS, CPDI, $d$ = {d1:g} cell (FMPM 2026 Fig. 3A)")
    ax.legend()
    figures.save_figure(fig, f"{prefix}a", report=False)

    if len(depths) < 2:
        return False
    from matplotlib.lines import Line2D
    fig, ax = plt.subplots(figsize=(7, 4.8))
    # Colours: the methods (FLIP, FMPM(k) new, FMPM(k) combined); line styles: the shapes.
    methods = [("FLIP", 1, "k", "o", "FLIP")]
    methods += [("new", k, f"C{i}", "o", f"FMPM({k}), new") for i, k in
                enumerate(k for k in (1, 2, 4, 8) if k in orders)]
    methods += [("combined", k, f"C{4 + i}", "s", f"FMPM({k}), combined") for i, k in
                enumerate(k for k in (4, 8) if k in orders)]
    shapes = (("cpdi", "-", "CPDI"), ("b2cpdi", "--", "B2CPDI"))
    for method, k, colour, marker, _ in methods:
        for shape, ls, _ in shapes:
            if method != "combined" or shape == "cpdi":
                ax.plot(depths, [err(shape, d, method, k) for d in depths], ls, color=colour,
                        marker=marker)
    ax.set_yscale("log")
    ax.set_xlabel("wall depth $d$ (cells)")
    ax.set_ylabel("$\\langle$Velocity Error$\\rangle$ (%)")
    ax.set_title("Moving-wall MMS against wall depth (FMPM 2026 Fig. 3B)")
    first = ax.legend(handles=[Line2D([], [], color=c, marker=m, label=n) for _, _, c, m, n in methods],
                      title="velocity update, BC method", loc="upper left",
                      bbox_to_anchor=(1.01, 1.0))
    ax.add_artist(first)
    ax.legend(handles=[Line2D([], [], color="k", ls=ls, label=n) for _, ls, n in shapes],
              title="shape functions", loc="lower left", bbox_to_anchor=(1.01, 0.0))
    figures.save_figure(fig, f"{prefix}b", report=False)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="only the runs of Fig. 3A")
    ap.add_argument("--orders", default=",".join(map(str, ORDERS)), help="FMPM orders k")
    ap.add_argument("--depths", default=",".join(f"{d:g}" for d in DEPTHS),
                    help="wall depths d in cells")
    figures.add_sets(ap)
    figures.add_output(ap, "fig3", "PREFIX.csv, PREFIXa.png and PREFIXb.png")
    args = ap.parse_args()
    prefix = figures.output_prefix(args.out)
    if not pathlib.Path(args.smpm).exists():
        sys.exit(f"fig3.py: {args.smpm}: no smpm binary (build it, or give --smpm)")
    start = time.time()
    todo = list(cases(args.quick, [int(k) for k in args.orders.split(",")],
                      [float(d) for d in args.depths.split(",")]))
    with tempfile.TemporaryDirectory() as work, concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(lambda c: run(args.smpm, work, c, args.sets), todo))
    fields = ["shape", "depth_cells", "method", "order", "error_percent", "sigma_rel_error", "steps", "seconds", "note"]
    with open(f"{prefix}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    both = plot(rows, prefix)
    print(f"{len(rows)} runs in {time.time() - start:.0f} s; {prefix}.csv, {prefix}a.png"
          + (f", {prefix}b.png" if both else ""))


if __name__ == "__main__":
    main()
