#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The papers' headline numbers at a stated resolution, each beside the docs' table it
reproduces: the two-disk impact's U + K lost at the paper's 1/3 mm cells (FMPM 2026 Fig. 9) and
its free energy (Fig. 10), its peak temperature at 0.5 mm (Fig. 7), and the critical Courant
numbers of the vibrating bar with the three transfers (docs/studies/gradient-transfers.md).

Run by ctest (cli.headlines, label long: the Release build only) with SMPM (the binary) and
SMPM_SOURCE (the source tree) in the environment; about a minute on two cores.
"""
import concurrent.futures
import csv
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

from example_runs import EXAMPLES, SMPM, fmpm, one_thread_each, run_example

DISKS = EXAMPLES / "disk_impact.toml"


def grid(cell):
    """Square cells of `cell` mm over the example's 56 x 48 mm grid (analysis/disks.py)."""
    return [f"grid.cell_size=[{cell!r}, {cell!r}]",
            f"grid.cells=[{round(56 / cell)}, {round(48 / cell)}]"]


def disk_run(work, name, sets):
    """U + K lost in %, the free energy's peak and end change in % of (U + K)(0), and the
    highest temperature of the example run with `sets`."""
    with h5py.File(run_example(DISKS, work, name, sets), "r") as f:
        s = f["series"]
        uk = s["kinetic"][:] + s["internal"][:]
        dA = 100 * (s["helmholtz"][:] - s["helmholtz"][0]) / uk[0]
        return {"lost": 100 * (1 - uk[-1] / uk[0]), "dA_peak": dA.max(), "dA_end": dA[-1],
                "t_max": float(s["temperature_max"][:].max()),
                "t_min": float(s["temperature_min"][:].min())}


class Headlines(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        third = grid(0.3333333333333333)
        cases = {  # the example's transport (lumped): U + K lost does not depend on it (Q is
                   # the frictional work whatever the transport, and no thermal expansion)
            "flip_mu0.3": ["step.velocity=FLIP", "contact.0.friction=0.3"] + third,
            "fmpm1_mu0.3": fmpm(1) + ["contact.0.friction=0.3"] + third,
            "fmpm4_mu0.3": fmpm(4) + ["contact.0.friction=0.3"] + third,
            "fig7_half_mm": grid(0.5),
        }
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            futures = {k: pool.submit(disk_run, cls.tmp.name, k, v) for k, v in cases.items()}
            bar = pool.submit(cls.bar_table, cls.tmp.name)
            cls.r = {k: f.result() for k, f in futures.items()}
            cls.bar = bar.result()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    @staticmethod
    def bar_table(work):
        """C* by rho(T) of FLIP, FMPM(4), FMPM(80) and the exact update on the bar with each
        transfer: {(transfer, velocity, order): (critical_courant, small_courant)}."""
        table = {}
        for transfer in ("standard", "velocity_gradient", "apic"):
            out = f"{work}/bar_{transfer}.csv"
            r = subprocess.run([str(SMPM), "stability", str(EXAMPLES / "vibrating_bar.toml"),
                                "--method", "spectral", "--order", "4,80", "--blend-alpha",
                                "none", "--set", "step.transfer=" + transfer, "-o", out],
                               capture_output=True, text=True, timeout=600,
                               env=one_thread_each())
            assert r.returncode == 0, r.stderr
            with open(out, newline="") as fh:
                for row in csv.DictReader(fh):
                    if row["periodic_cx"] == "":  # not the periodic rows
                        key = (transfer, row["velocity"], row["order"])
                        table[key] = (float(row["critical_courant"]), row["small_courant"])
        return table

    def test_fig9_energy_lost_at_the_papers_cells(self):
        # FMPM 2026 Fig. 9B at 1/3 mm, mu = 0.3: FMPM(1) loses 18.7% (the paper's number;
        # measured 18.92%, docs/studies/shocks.md), FLIP and FMPM(4) under 2% (the paper's words; measured 1.03%
        # and 1.64%), FMPM(4) more than FLIP.
        r = self.r
        self.assertAlmostEqual(r["fmpm1_mu0.3"]["lost"], 18.7, delta=0.5)
        self.assertLess(r["flip_mu0.3"]["lost"], 2.0)
        self.assertLess(r["fmpm4_mu0.3"]["lost"], 2.0)
        self.assertGreater(r["fmpm4_mu0.3"]["lost"], r["flip_mu0.3"]["lost"])

    def test_fig10_free_energy(self):
        # FMPM 2026 Fig. 10: the free energy A = U - TS peaks during the impact and returns
        # close to zero once the disks separate. FLIP with the lumped transport at 1/3 mm,
        # mu = 0.3 (docs/studies/shocks.md's table: peak 25.94%, end -1.09%; asserted to 0.3 points).
        r = self.r["flip_mu0.3"]
        self.assertAlmostEqual(r["dA_peak"], 25.94, delta=0.3)
        self.assertAlmostEqual(r["dA_end"], -1.09, delta=0.3)

    def test_fig7_peak_temperature(self):
        # FMPM 2026 Fig. 7, the example (mu = 0.6, FMPM(4), lumped transport) at 0.5 mm on the
        # example's grid: the peak 379.0 K of docs/studies/heat.md's table of cell sizes and grid shifts
        # (asserted to 1 K; the shifts move it by up to 13 K), and no particle below 300 K but
        # by round-off (measured 1.4e-9 K below; FMPM(4) transport reaches 291 K at 1/3 mm).
        r = self.r["fig7_half_mm"]
        self.assertAlmostEqual(r["t_max"], 379.0, delta=1.0)
        self.assertGreaterEqual(r["t_min"], 300 - 1e-7)

    def test_gradient_table_of_the_bar(self):
        # docs/studies/gradient-transfers.md: C* by rho(T) on the bar (CPDI), to the printed
        # digits (0.0005). The velocity-gradient transfer's FMPM(80) and exact rows have a weak
        # mode unstable at every C (C* = 0); FLIP's table entry reaches 1 but with an unstable
        # interval below C = 0.04 at two lattice shifts, which the table must say.
        expected = {
            ("velocity_gradient", "FLIP"): 1.000, ("apic", "FLIP"): 1.000,
            ("velocity_gradient", "FMPM", "4"): 0.884, ("apic", "FMPM", "4"): 0.929,
            ("velocity_gradient", "FMPM", "80"): 0.000, ("apic", "FMPM", "80"): 0.926,
            ("velocity_gradient", "exact"): 0.000, ("apic", "exact"): 0.926,
        }
        for key, value in expected.items():
            rows = [v for k, v in self.bar.items() if k[:len(key)] == key]
            with self.subTest(key=key):
                self.assertEqual(len(rows), 1)
                self.assertAlmostEqual(rows[0][0], value, delta=0.0005)
        flip = [v for k, v in self.bar.items() if k[:2] == ("velocity_gradient", "FLIP")][0]
        self.assertIn("unstable below", flip[1])


if __name__ == "__main__":
    unittest.main()
