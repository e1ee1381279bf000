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


def velocity(name, transport=None):
    """Overrides for "FLIP" or "FMPM(k)" mechanics and a heat transport: `transport` "lumped" or
    "FMPM" (FMPM(k) on the capacity matrix, the mechanics' order; FMPM(4) with FLIP), or by
    default the one that goes with the mechanics, the lumped (FLIP) update for FLIP and FMPM(k)
    for FMPM(k) (fig8-fig11's pairs). NairnMPM's transport does not follow its velocity update:
    it conducts by the lumped update unless its periodic-FMPM task is given conduction settings,
    and adds friction heat to the nodal rate after its nodal temperature update, which for the
    lumped update is the same as adding it to the flow q; so "lumped" is NairnMPM's choice
    (fig7.py's default, as the example's)."""
    if transport is None:
        transport = "lumped" if name == "FLIP" else "FMPM"
    if transport not in ("lumped", "FMPM"):
        raise ValueError(f"transport {transport!r}: lumped or FMPM")
    order = 4 if name == "FLIP" else int(name[5:-1])
    heat = ["step.transport=" + transport] + \
        ([f"step.transport_order={order}"] if transport == "FMPM" else [])
    if name == "FLIP":
        return ["step.velocity=FLIP"] + heat
    return ["step.velocity=FMPM", f"step.order={order}"] + heat


def run(smpm, out, sets):
    """Runs the example with `sets`; returns the energy lost 1 - (U + K)(end) / (U + K)(0) in %
    with U = W + Q the internal energy (FMPM 2026 Fig. 9: the strain energy and the heat, here
    from the run's heat transport), the same with the frictional work in place of Q ("lost_work",
    1 - (K + W + W_friction)(end) / (K + W)(0): equal, the disks exchange no heat with their
    surroundings), the frictional work and the heat in % of the initial energy, the largest
    temperature reached, the series of time, free energy A and largest temperature, the centre
    of mass of each disk at every step (rows: x, y of the left disk, then the right), the
    largest |total momentum| and the run time. Raises RuntimeError with the command's message
    when it fails."""
    r, seconds = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip().splitlines()[-1] if r.stderr.strip() else
                           f"exit {r.returncode}")
    s = read_run(out).series
    e = s["kinetic"] + s["strain"]
    friction = s["friction"]
    uk = s["kinetic"] + s["internal"]
    return {"lost": 100 * (1 - uk[-1] / uk[0]),
            "lost_work": 100 * (1 - (e[-1] + friction[-1]) / e[0]),
            "friction": 100 * friction[-1] / e[0], "heat": 100 * (s["heat"][-1] - s["heat"][0]) / e[0],
            "t_max": float(s["temperature_max"].max()), "helmholtz": s["helmholtz"],
            "temperature_max": s["temperature_max"], "energy0": float(uk[0]),
            "centre": s["material_centre"],
            "time": s["t"], "momentum": np.abs(s["momentum"]).max(), "seconds": seconds}
