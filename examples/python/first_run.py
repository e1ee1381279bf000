# SPDX-License-Identifier: BSD-3-Clause
"""A run file in numpy: python3 examples/python/first_run.py vibrating_bar.h5 (after smpm run)."""
import sys

import numpy as np
import sparsempm as smpm

run = smpm.read_run(sys.argv[1])                   # the complete frames of a run file
print(f"{run.status}: {len(run.frames)} frames, t = {run.times[0]} ... {run.times[-1]}")
E = run.series["total"]                            # one row per step: t, kinetic, strain, ...
print(f"total energy {E[0]:.6g} -> {E[-1]:.6g} ({100 * (E[-1] / E[0] - 1):+.4f}%)")
p = run.particles(-1)                              # the last frame: X, V, stress, F, J, mass, ...
print(f"{len(p['X'])} particles; largest |V| {np.abs(p['V']).max():.4g}; J in "
      f"[{p['J'].min():.6f}, {p['J'].max():.6f}]")
g = run.grid(-1)                                   # the nodes with mass: m, p, v, X
print(f"{len(g['m'])} nodes with mass, sum m = {g['m'].sum():.6g} = sum M = {p['mass'].sum():.6g}")
