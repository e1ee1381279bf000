# SPDX-License-Identifier: BSD-3-Clause
"""The two-disk impact of FMPM 2026 §3.2.2 (examples/disk_impact.toml), as the figure scripts
fig8.py, fig9.py and fig11.py run it: one `smpm run` with overrides, and what they read from its
series."""
import pathlib

import numpy as np

from figures import read_run, run_smpm

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "disk_impact.toml"
EXTENT = (56.0, 48.0)  # the example's grid, mm


def grid(cell):
    """Overrides for square cells of `cell` mm over the example's extent."""
    return [f"grid.cell_size=[{cell}, {cell}]",
            f"grid.cells=[{round(EXTENT[0] / cell)}, {round(EXTENT[1] / cell)}]"]


def velocity(name):
    """Overrides for "FLIP" or "FMPM(k)"."""
    if name == "FLIP":
        return ["step.velocity=FLIP"]
    return ["step.velocity=FMPM", f"step.order={int(name[5:-1])}"]


def run(smpm, out, sets):
    """Runs the example with `sets`; returns the energy lost 1 - (K + W + Q_friction)(end) /
    (K + W)(0) in % (FMPM 2026 Fig. 9, without heat conduction the frictional work stays as
    heat), the frictional work in % of the initial energy, the centre of mass of each disk at
    every step (rows: x, y of the left disk, then the right), the time, the largest |total
    momentum| and the run time. Raises RuntimeError with the command's message when it fails."""
    r, seconds = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip().splitlines()[-1] if r.stderr.strip() else
                           f"exit {r.returncode}")
    s = read_run(out).series
    e = s["kinetic"] + s["strain"]
    friction = s["friction"]
    return {"lost": 100 * (1 - (e[-1] + friction[-1]) / e[0]),
            "friction": 100 * friction[-1] / e[0], "centre": s["material_centre"],
            "time": s["t"], "momentum": np.abs(s["momentum"]).max(), "seconds": seconds}
