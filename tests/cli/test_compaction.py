#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Compaction of elliptical objects (contact 2020 Fig. 6) through analysis/compaction.py: grid
contact against logistic regression on the packing of examples/compaction.toml.

Run by ctest (Release builds only: three runs of about 20, 20 and 45 s) with SMPM and SMPM_SOURCE in
the environment.
"""
import csv
import os
import pathlib
import subprocess
import tempfile
import unittest

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))


class Compaction(unittest.TestCase):
    def test_lr_removes_interpenetration(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = pathlib.Path(tmp) / "c"
            r = subprocess.run(["/usr/bin/python3", str(SOURCE / "analysis" / "compaction.py"),
                                "--smpm", SMPM, "-o", str(out)], capture_output=True, text=True,
                               timeout=900)
            self.assertEqual(r.returncode, 0, r.stderr)
            # The script writes the input it ran: the packing of examples/compaction.toml.
            self.assertEqual(pathlib.Path(str(out) + ".toml").read_text(),
                             (SOURCE / "examples" / "compaction.toml").read_text())
            rows = {row["method"]: row for row in csv.DictReader(open(str(out) + ".csv"))}
        ag = float(rows["AG, CP = 0.8"]["interpenetration"])
        lr = float(rows["LR, d_LR"]["interpenetration"])
        df = float(rows["AG, DF"]["interpenetration"])
        # Measured: 0.72% of the particles inside another object with AG + CP, 0.97% with
        # AG + DF, none with LR (contact 2020 Fig. 6: LR removes the interpenetration).
        self.assertGreater(ag, 0.0005)
        self.assertGreater(df, 0.0005)
        self.assertLess(lr, 0.0005)
        # Contact 2020 §4.2: the grid methods are softer than LR (paper: CP 80, DF 84, LR
        # 105 GPa); measured mean sigma_yy -62 (CP), -81 (DF), -146 MPa (LR).
        syy = {k: float(row["mean_sigma_yy"]) for k, row in rows.items()}
        self.assertLess(syy["LR, d_LR"], 1.2 * syy["AG, DF"])
        self.assertLess(syy["AG, DF"], syy["AG, CP = 0.8"])
        for row in rows.values():  # compressed: the mean axial stress is negative
            self.assertLess(float(row["mean_sigma_yy"]), 0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
