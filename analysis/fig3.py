#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 3: velocity error of the moving-wall manufactured solution (§3.1).

    analysis/fig3.py [--smpm build/apps/smpm] [--jobs 2] [--quick] [-o fig3]

Runs examples/moving_wall_mms.toml with `smpm run` for FLIP, FMPM(k) with the new
(incremental) and the prior combined BC method, and the exact consistent-mass inverse
(regularised with eps = 1e-4: plain m~ becomes singular to round-off at t = 51 s), for
k in {1, 2, 3, 4, 6, 8, 12}, wall depths d in {0.5, 1, 1.5, 2} cells and the CPDI and B2CPDI
shape functions, two runs at a time. Each run's error is the paper's

    <Velocity Error>(%) = 100 / (N_s V_end) * sum over steps of sqrt((1/N) sum_p |V_p(t) - V_p(0)|^2),

V_end = 10 edot, read from the run's series (velocity_change_sum); sigma_xx of the interior
particles (|X| < 8 m) is compared with 2G(2 + edot t) edot t / (2(1 + edot t)). Writes
<out>.csv, <out>a.png (error against k, CPDI, d = 1 cell: Fig. 3A) and <out>b.png (error against
d for FLIP and k = 1, 2, 4, 8, CPDI solid and B2CPDI dashed, the combined method for k = 4, 8:
Fig. 3B). --quick runs only what Fig. 3A needs.
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
EDOT, G = 3e-3, 0.375
ORDERS = [1, 2, 3, 4, 6, 8, 12]
DEPTHS = [0.5, 1.0, 1.5, 2.0]


def cases(quick):
    """(shape, depth, method, k) of every run; method FLIP | new | combined | exact."""
    shapes = ["cpdi"] if quick else ["cpdi", "b2cpdi"]
    depths = [1.0] if quick else DEPTHS
    for shape in shapes:
        for d in depths:
            yield shape, d, "FLIP", 1
            yield shape, d, "exact", 0
            for k in ORDERS:
                yield shape, d, "new", k
                if k > 2:  # k <= 2: the combined method is the new one (FMPM 2026 §3.1)
                    yield shape, d, "combined", k


def run(smpm, workdir, case):
    shape, d, method, k = case
    out = pathlib.Path(workdir) / f"{shape}_{d}_{method}_{k}.h5"
    sets = [f"step.shape={shape}", "output.every=66.66666666666667",
            f"bc.0.wall.depth_cells={d}", f"bc.1.wall.depth_cells={d}"]
    if method == "FLIP":
        sets += ["step.velocity=FLIP"]
    elif method == "exact":  # m~ + light nodes is singular to round-off late in the run (README)
        sets += ["step.velocity=exact", "step.exact_regularization=1e-4"]
    else:
        sets += ["step.velocity=FMPM", f"step.order={k}",
                 "step.bc_method=" + ("incremental" if method == "new" else "combined")]
    args = [smpm, "run", ROOT / "examples" / "moving_wall_mms.toml", "-o", out, "-q"]
    for s in sets:
        args += ["--set", s]
    start = time.time()
    r = subprocess.run(list(map(str, args)), capture_output=True, text=True)
    row = {"shape": shape, "depth_cells": d, "method": method, "order": k, "seconds": round(time.time() - start, 2)}
    if r.returncode != 0:
        row.update(error_percent="", sigma_rel_error="", steps="", note=r.stderr.strip().replace(",", ";")[:160])
        return row
    with h5py.File(out, "r") as f:
        s = f["series"]
        steps = len(s["t"]) - 1
        err = 100 * s["velocity_change_sum"][-1] / (steps * 10 * EDOT)
        g = f["particles"][sorted(f["particles"])[-1]]
        e = EDOT * g.attrs["time"]
        exact = 2 * G * (2 + e) * e / (2 * (1 + e))
        inner = np.abs(g["X"][:, 0]) < 8
        sig = float(np.abs(g["stress"][inner, 0] / exact - 1).max())
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

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method, style in (("new", "-o"), ("combined", "-s")):
        ks = [k for k in ORDERS if method == "new" or k > 2]
        ax.plot(ks, [err("cpdi", 1.0, method, k) for k in ks], style, label=f"FMPM(k), {method} BC method")
    ax.axhline(err("cpdi", 1.0, "FLIP", 1), color="k", ls="--", label="FLIP")
    ex = err("cpdi", 1.0, "exact", 0)
    if not math.isnan(ex):
        ax.axhline(ex, color="purple", ls=":", label="exact (1 − ε)m̃ + εm, ε = 1e-4 (k → ∞)")
    ax.set_yscale("log")
    ax.set_xlabel("FMPM order k")
    ax.set_ylabel("<Velocity Error> (%)")
    ax.set_title("Moving-wall MMS, CPDI, d = 1 cell (FMPM 2026 Fig. 3A)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{prefix}a.png", dpi=120)

    depths = sorted({float(r["depth_cells"]) for r in rows})
    if len(depths) < 2:
        return
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for shape, ls in (("cpdi", "-"), ("b2cpdi", "--")):
        ax.plot(depths, [err(shape, d, "FLIP", 1) for d in depths], ls, color="k", marker="o",
                label=f"FLIP, {shape}")
        for i, k in enumerate((1, 2, 4, 8)):
            ax.plot(depths, [err(shape, d, "new", k) for d in depths], ls, color=f"C{i}", marker="o",
                    label=f"FMPM({k}) new, {shape}")
    for k, c in ((4, "r"), (8, "m")):
        ax.plot(depths, [err("cpdi", d, "combined", k) for d in depths], "-", color=c, marker="s",
                label=f"FMPM({k}) combined, cpdi")
    ax.set_yscale("log")
    ax.set_xlabel("wall depth d (cells)")
    ax.set_ylabel("<Velocity Error> (%)")
    ax.set_title("Moving-wall MMS against wall depth (FMPM 2026 Fig. 3B)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(f"{prefix}b.png", dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="only the runs of Fig. 3A")
    ap.add_argument("-o", "--output", default="fig3")
    args = ap.parse_args()
    if not pathlib.Path(args.smpm).exists():
        sys.exit(f"fig3.py: {args.smpm}: no smpm binary (build it, or give --smpm)")
    start = time.time()
    todo = list(cases(args.quick))
    with tempfile.TemporaryDirectory() as work, concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(lambda c: run(args.smpm, work, c), todo))
    fields = ["shape", "depth_cells", "method", "order", "error_percent", "sigma_rel_error", "steps", "seconds", "note"]
    with open(f"{args.output}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    plot(rows, args.output)
    print(f"{len(rows)} runs in {time.time() - start:.0f} s; {args.output}.csv, {args.output}a.png"
          + ("" if args.quick else f", {args.output}b.png"))


if __name__ == "__main__":
    main()
