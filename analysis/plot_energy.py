#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Kinetic, strain and total energy of a run against time.

    analysis/plot_energy.py run.h5 [-o run_energy.png]

Reads /series/{t, kinetic, strain, total} of a file written by `smpm run` and writes a PNG
(default: the run's name with _energy.png). Prints the total-energy change in percent.
"""
import argparse
import pathlib
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="HDF5 file written by smpm run")
    ap.add_argument("-o", "--output", help="PNG to write")
    args = ap.parse_args()
    try:
        f = h5py.File(args.run, "r")
    except OSError as e:
        sys.exit(f"plot_energy.py: {args.run}: cannot open ({e})")
    with f:
        s = f["series"]
        t, kin, strain, total = (s[k][:] for k in ("t", "kinetic", "strain", "total"))
        status = f.attrs.get("status", "")
    out = pathlib.Path(args.output or pathlib.Path(args.run).with_suffix("").as_posix() + "_energy.png")
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t, kin, label="kinetic")
    ax.plot(t, strain, label="strain")
    ax.plot(t, total, label="total", color="k")
    ax.set_xlabel("time")
    ax.set_ylabel("energy")
    ax.set_title(f"{pathlib.Path(args.run).name} ({status})")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    change = 100 * (total[-1] - total[0]) / abs(total[0]) if total[0] != 0 else 0.0
    print(f"{out}: {len(t)} steps, total energy {total[0]:.6g} -> {total[-1]:.6g} ({change:+.4f}%)")


if __name__ == "__main__":
    main()
