#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""An offset impact of two disks with Coulomb friction and heat conduction
(examples/disk_impact.toml; FMPM 2026 §3.2.2, Figs. 7-9): momentum, the energy lost by FLIP and
FMPM(k), the frictional work and the heat it becomes, and the deflection against the
coefficient of friction.

Run by ctest (Release builds only) with SMPM and SMPM_SOURCE in the environment.
"""
import concurrent.futures
import os
import pathlib
import tempfile
import tomllib
import unittest

import h5py
import numpy as np

from example_runs import fmpm, run_example

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLE = SOURCE / "examples" / "disk_impact.toml"
HALF_MM = ["grid.cell_size=[0.5, 0.5]", "grid.cells=[112, 96]"]
# The heat capacity of both disks in the example (its [[material]] tables).
C_V = tomllib.loads(EXAMPLE.read_text())["material"][0]["heat_capacity"]
# FLIP with the lumped heat transport (the example's transport, under FMPM(4)).
FLIP = ["step.velocity=FLIP", "step.transport=lumped"]


def run(work, name, sets):
    out = run_example(EXAMPLE, work, name, sets)
    with h5py.File(out, "r") as f:
        s = f["series"]
        e = s["kinetic"][:] + s["strain"][:]
        uk = s["kinetic"][:] + s["internal"][:]
        last = f["particles"][max(f["particles"])]
        capacity = C_V * last["mass"][:]
        return {"lost": 1 - (e[-1] + s["friction"][-1]) / e[0],
                "lost_uk": 1 - uk[-1] / uk[0],
                "friction": s["friction"][-1] / e[0],
                "friction_work": s["friction"][-1],
                "heat": s["heat"][-1] - s["heat"][0],
                "content": float(capacity @ last["temperature"][:]),
                "t_max": float(s["temperature_max"][:].max()),
                "t_min": float(s["temperature_min"][:].min()),
                "momentum": np.abs(s["momentum"][:]).max(),
                "material_momentum": s["material_momentum"][:]}


class Disks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cases = {"flip_mu0_half_mm": FLIP + ["contact.0.friction=0"] + HALF_MM}
        for mu in (0, 0.3, 0.6):
            cases[f"flip_mu{mu}"] = FLIP + [f"contact.0.friction={mu}"]
        for k in (1, 2, 4):
            cases[f"fmpm{k}_mu0.3"] = fmpm(k) + ["contact.0.friction=0.3"]
        cases["example"] = []  # mu = 0.6, FMPM(4), lumped transport (Fig. 7)
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            futures = {k: pool.submit(run, cls.tmp.name, k, v) for k, v in cases.items()}
            cls.r = {k: f.result() for k, f in futures.items()}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_momentum_is_conserved(self):
        # The disks start with momenta +-38.70 g mm/ms along x: the total stays 0 to round-off
        # through contact and friction (measured at most 1e-13; asserted 1e-10).
        for name, r in self.r.items():
            with self.subTest(name):
                self.assertLess(r["momentum"], 1e-10)

    def test_energy_lost(self):
        # FMPM 2026 Fig. 9: with mu = 0, FLIP loses under 2% of K + W (paper, 1/3 mm cells);
        # measured 1.79% at 0.5 mm cells (3.79% at the example's 1 mm, 1.43% at 1/3 mm).
        self.assertLess(self.r["flip_mu0_half_mm"]["lost"], 0.02)
        # Fig. 9B at mu = 0.3 (1 mm cells): FMPM(1) loses far more (paper 18.7%; measured
        # 27.8%), FMPM(2) much less than FMPM(1) (measured 8.6%), FMPM(4) within 2 points of
        # FLIP (measured 4.43% and 2.78%; the loop's corrections do frictional work too).
        f1, f2, f4 = (self.r[f"fmpm{k}_mu0.3"]["lost"] for k in (1, 2, 4))
        flip = self.r["flip_mu0.3"]["lost"]
        self.assertGreater(f1, 0.15)
        self.assertLess(f2, 0.5 * f1)
        self.assertLess(f4, f2)
        self.assertLess(abs(f4 - flip), 0.02)

    def test_friction_becomes_heat(self):
        # The disks exchange no heat with their surroundings and conduction conserves heat: the
        # heat gained, sum M C_V (T - T0), is the frictional work, to the round-off of the heat
        # content sum M C_V T over some 1000 steps (4.2e5 mJ; 1e-13 of it), and U + K with U = W + Q
        # loses what K + W + W_friction does. Without friction nothing heats (mu = 0: 300 K to
        # round-off); with it the contact surfaces heat (FLIP, 1 mm: measured 314.6 and 311.7 K
        # at mu = 0.3 and 0.6, the example (FMPM(4), lumped transport, mu = 0.6) 323.8 K; at the
        # paper's 1/3 mm 420.6 K for the example, beside its 456 K: docs/studies/heat.md).
        for name, r in self.r.items():
            with self.subTest(name):
                self.assertLess(abs(r["heat"] - r["friction_work"]), 1e-13 * r["content"])
                self.assertAlmostEqual(r["lost_uk"], r["lost"], delta=1e-10)  # the same round-off
        self.assertAlmostEqual(self.r["flip_mu0"]["t_max"], 300.0, delta=1e-9)
        self.assertGreater(self.r["flip_mu0.6"]["t_max"], 305)
        self.assertGreater(self.r["flip_mu0.3"]["t_max"], 305)
        self.assertGreater(self.r["example"]["t_max"], 305)
        # The lumped update adds Δt S c⁻¹ q, and friction heat is positive: no particle cools
        # below the 300 K it started at (measured 300 K to round-off in every lumped run; FMPM(4)
        # transport reaches 291.3 K at 1/3 mm, docs/studies/heat.md), but by round-off (1e-9 K at 0.5 mm).
        for name, r in self.r.items():  # every run here conducts by the lumped update
            with self.subTest(name):
                self.assertGreaterEqual(r["t_min"], 300 - 1e-7)
        # FMPM 2026 Fig. 9A: U + K lost by FMPM(4) at mu = 0.6 (1 mm: measured 5.96%; 2.01% at
        # the paper's 1/3 mm, docs/studies/shocks.md, beside its "< 2%")
        self.assertLess(self.r["example"]["lost_uk"], 0.07)

    def test_friction_turns_the_disks(self):
        # Friction does work only with mu > 0 (mu = 0: round-off, measured 1.4e-16 of the
        # initial energy; 23.9% and 13.4% at mu = 0.3 and 0.6 with FLIP), and the left disk's path turns more with mu: the
        # angle of its final momentum from +x grows (measured 46.3, 60.0 and 76.3 degrees for
        # mu = 0, 0.3, 0.6).
        self.assertLess(self.r["flip_mu0"]["friction"], 1e-12)
        self.assertGreater(self.r["flip_mu0.3"]["friction"], 0.05)
        angles = []
        for mu in (0, 0.3, 0.6):
            p = self.r[f"flip_mu{mu}"]["material_momentum"][-1]
            angles.append(np.degrees(abs(np.arctan2(p[1], p[0]))))
        self.assertLess(angles[0], angles[1])
        self.assertLess(angles[1], angles[2])


if __name__ == "__main__":
    unittest.main(verbosity=2)
