#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The moving-wall manufactured solution of FMPM 2026 §3.1 (examples/moving_wall_mms.toml):
the paper's statements about Fig. 3 and the exact axial stress, on full runs.

Run by ctest (Release builds only: ten full runs) with SMPM and SMPM_SOURCE in the environment.
"""
import concurrent.futures
import os
import pathlib
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
MMS = SOURCE / "examples" / "moving_wall_mms.toml"
EDOT, G = 3e-3, 0.375


def run(work, name, *sets):
    """(<Velocity Error> in %, max |sigma_xx / exact - 1| over |X| < 8 m) of one full run."""
    out = pathlib.Path(work) / (name + ".h5")
    args = [SMPM, "run", MMS, "-o", out, "-q", "--set", "output.every=66.66666666666667"]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(list(map(str, args)), capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        s = f["series"]
        steps = len(s["t"]) - 1
        err = 100 * s["velocity_change_sum"][-1] / (steps * 10 * EDOT)  # FMPM 2026 §3.1
        g = f["particles"][sorted(f["particles"])[-1]]
        e = EDOT * g.attrs["time"]
        exact = 2 * G * (2 + e) * e / (2 * (1 + e))
        inner = np.abs(g["X"][:, 0]) < 8
        return err, float(np.abs(g["stress"][inner, 0] / exact - 1).max())


def depth(d):
    return [f"bc.0.wall.depth_cells={d}", f"bc.1.wall.depth_cells={d}"]


class MovingWalls(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        fmpm8 = ["step.velocity=FMPM", "step.order=8"]
        cases = {
            "flip": ["step.velocity=FLIP"],
            "new8": fmpm8,
            "combined8": fmpm8 + ["step.bc_method=combined"],
            "new8_d2": fmpm8 + depth(2),
            "b2_flip_d15": ["step.velocity=FLIP", "step.shape=b2cpdi"] + depth(1.5),
            "b2_new8_d1": fmpm8 + ["step.shape=b2cpdi"],
            "b2_new8_d15": fmpm8 + ["step.shape=b2cpdi"] + depth(1.5),
        }
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            futures = {k: pool.submit(run, cls.tmp.name, k, *v) for k, v in cases.items()}
            cls.r = {k: f.result() for k, f in futures.items()}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_new_method_far_below_flip(self):
        # Paper: FMPM(8) with the new method 400 times below FLIP (CPDI, d = 1 cell); asserted
        # at least 100 times (measured 257).
        self.assertGreater(self.r["flip"][0] / self.r["new8"][0], 100)

    def test_combined_method_above_flip(self):
        # Paper: the combined method's errors exceed FLIP's for k > 6 (measured: from k = 4).
        self.assertGreater(self.r["combined8"][0], self.r["flip"][0])

    def test_errors_nearly_independent_of_depth(self):
        # Paper: new-method errors constant for d >= 1 (within 30% here between d = 1 and 2).
        self.assertAlmostEqual(self.r["new8_d2"][0] / self.r["new8"][0], 1.0, delta=0.3)

    def test_b2cpdi(self):
        # Paper: with B2CPDI, FMPM(8) is 4400 times below FLIP at d >= 1.5 cells and poor at
        # d = 1 (the quadratic spline reaches 1.5 cells). Measured here: B2CPDI FMPM(8) at d = 1.5
        # is 9.2e-5 %, 3.5 times below CPDI's FMPM(8), 890 times below CPDI's FLIP and 152 times
        # below B2CPDI's FLIP (whose 0.014 % is 6 times below CPDI's FLIP, where the paper found
        # the two FLIP errors similar), and 40,000 times worse at d = 1. Asserted: lower than
        # CPDI's FMPM(8), more than 500 times below CPDI's FLIP and 100 times below B2CPDI's,
        # and more than ten times worse at d = 1 than at d = 1.5.
        b2 = self.r["b2_new8_d15"][0]
        self.assertLess(b2, self.r["new8"][0])
        self.assertGreater(self.r["flip"][0] / b2, 500)
        self.assertGreater(self.r["b2_flip_d15"][0] / b2, 100)
        self.assertGreater(self.r["b2_new8_d1"][0], 10 * b2)

    def test_axial_stress(self):
        # sigma_xx = 2G(2 + edot t) edot t / (2(1 + edot t)) for the interior particles at 20%
        # elongation: within 1e-4 relative for FMPM(8) with the new method (measured 3.1e-5).
        self.assertLess(self.r["new8"][1], 1e-4)


if __name__ == "__main__":
    unittest.main(verbosity=2)
