#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""MPM as matrices from Python, and one point of FMPM 2026 Fig. 12A.
Run: PYTHONPATH=build/python python3 examples/python/matrices.py (from the source tree).
Look at: spec(A) lies in [0, 1); FMPM(4)'s critical Courant number by simulation is 0.543
(the paper: 0.539), its spectral bound over lattice shifts 0.451 (docs/studies/stability.md)."""
import os, numpy as np, scipy.linalg, sparsempm as smpm

# 1. The four particles of docs/guide/cpp.md of mass 1/4 on a 1D grid of three cells (linear shapes).
model = smpm.Model(smpm.Grid(cells=[3]), X=[0.75, 1.25, 1.75, 2.25], mass=[0.25] * 4,
                   volume0=[0.5] * 4, materials=[smpm.Material(density=0.5)])
ops = smpm.assemble(model, "linear")
print("S =\n", ops.S.toarray(), "\nm = S^T M =", ops.m)
print("m~ = S^T M S =\n", ops.consistent_mass().toarray())
A = ops.expansion_matrix().toarray()
print("A = I - m^-1 m~ =\n", A.round(4))
mu = scipy.linalg.eigvals(A).real
in_range = mu.min() > -1e-12 and mu.max() < 1
print("spec(A) =", np.sort(mu).round(4), "in [0, 1):", "yes" if in_range else "no")

# 2. Fig. 12A at k = 4: the vibrating bar with FMPM(4), spectral and simulation C*.
path = os.path.join(os.environ.get("SMPM_SOURCE", "."), "examples", "vibrating_bar.toml")
bar = smpm.Model.from_toml(path, {"step.velocity": "FMPM", "step.order": 4})
spectral = smpm.sweep_shifts(bar, shifts=4).minimum.critical_courant
simulation = smpm.simulation_courant(bar).simulation_courant  # five periods per run, bisection to 0.005
print(f"FMPM(4): C* spectral = {spectral:.3f}, C* simulation = {simulation:.3f} (paper 0.539)")
