#!/usr/bin/python3
"""FMPM 2026 Fig. 12B: energy dissipation of FMPM(4) blended with FMPM(1) against α at C = 0.539.

    analysis/fig12b.py [--smpm build/apps/smpm] [--input examples/vibrating_bar.toml] [-o fig12b.png]

Runs `smpm run` for α = 0, 0.1, …, 1 (five periods of the bar), writes fig12b.csv and the PNG.
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--input", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--courant", type=float, default=0.539)
    ap.add_argument("-o", "--output", default="fig12b.png")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(11):
            alpha = i / 10
            out = pathlib.Path(tmp) / f"a{i}.h5"
            sets = ["scheme.velocity=FMPM", "scheme.order=4", f"scheme.blend_alpha={alpha}",
                    "scheme.blend_every=1", f"time.courant={args.courant}", "output.every=400"]
            cmd = [args.smpm, "run", args.input, "-o", str(out), "-q"]
            for s in sets:
                cmd += ["--set", s]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode == 0:
                with h5py.File(out, "r") as f:
                    total = f["series"]["total"][:]
                loss = 100 * (total[0] - total[-1]) / total[0]
            else:
                loss = float("nan")
            rows.append((alpha, loss))
            print(f"alpha = {alpha:.1f}: energy loss {loss:.3f}%", file=sys.stderr)
    table = pathlib.Path(args.output).with_suffix(".csv")
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["alpha", "energy_loss_percent"])
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in rows], [r[1] for r in rows], "-o")
    ax.set_xlabel("fraction of FMPM(4), α (blended with FMPM(1))")
    ax.set_ylabel("energy loss after five periods (%)")
    ax.set_title(f"Free-vibrating bar, C = {args.courant} (FMPM 2026 Fig. 12B)")
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"{args.output} and {table}")


if __name__ == "__main__":
    main()
