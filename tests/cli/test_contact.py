#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Multimaterial contact from the input (examples/two_block_compression.toml, contact 2020
Figs. 2 and 5): full runs against single material mode, and the [[contact]] input errors.

Run by ctest with SMPM and SMPM_SOURCE in the environment.
"""
import concurrent.futures
import os
import pathlib
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

from example_runs import check_refused, run_example

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLE = SOURCE / "examples" / "two_block_compression.toml"
# Sanitized builds leave out the FMPM(4) runs (ten times slower there; tests/CMakeLists.txt).
SANITIZED = os.environ.get("SMPM_SANITIZED") == "1"
SN = ["contact.0.normal=specified", "contact.0.direction=[0.0, 1.0]"]
LR = ["contact.0.normal=LR", "contact.0.detection=LR"]
FMPM4 = ["step.velocity=FMPM", "step.order=4", "time.courant=0.2"]


def mean_axial_stress(work, name, *sets):
    """Mean sigma_yy of the particles at every frame (1% strain apart) of a full run."""
    out = run_example(EXAMPLE, work, name, sets)
    with h5py.File(out, "r") as f:
        frames = sorted(f["particles"].values(), key=lambda g: g.attrs["time"])
        series = {k: f["series"][k][:] for k in ("material_mass", "material_centre")}
        return np.array([g["stress"][:, 3].mean() for g in frames[1:]]), series


class TwoBlocks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cases = {
            "single": ["contact.0.law=single-field"],
            "sn_approaching": ["contact.0.detection=approaching"] + SN,
            "ag_approaching": ["contact.0.detection=approaching", "contact.0.normal=AG"],
            "ag_cp": [],
            "ag_df": ["contact.0.detection=DF", "contact.0.normal=AG"],
            "df_sn": ["contact.0.detection=DF"] + SN,
            "lr": LR,
        }
        if not SANITIZED:
            cases["lr_once"] = LR + ["step.contact_corrections=once"]
            cases["fmpm_single"] = FMPM4 + ["contact.0.law=single-field"]
            cases["fmpm_net"] = FMPM4 + LR + ["contact.0.fmpm_method=net"]
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            futures = {k: pool.submit(mean_axial_stress, cls.tmp.name, k, *v)
                       for k, v in cases.items()}
            results = {k: f.result() for k, f in futures.items()}
        cls.r = {k: v[0] for k, v in results.items()}
        cls.series = {k: v[1] for k, v in results.items()}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def error(self, name):
        return self.error_against(name, "single")

    def error_against(self, name, reference):
        return 100 * np.abs(self.r[name] / self.r[reference] - 1)

    def test_specified_normal_reverts_to_single_material_mode(self):
        # The interface is a grid line in pure compression: with its exact normal and the
        # approaching criterion, contact sticks the normal velocities and multimaterial MPM is
        # single material MPM (contact 2020 §3.2) up to 20% strain: within 1e-3 % (measured
        # 1.6e-5 %: nodes whose fields separate for a step are left uncorrected).
        self.assertLess(self.error("sn_approaching").max(), 1e-3)

    def test_logistic_regression_reverts_to_single_material_mode(self):
        # Contact 2020 Fig. 5: LR normals with the LR separation d_LR are within 1% of single
        # material mode up to 20% strain (paper: < 1%); measured at most 3.7e-5 %.
        self.assertLess(self.error("lr").max(), 1.0)

    @unittest.skipIf(SANITIZED, "a full run that checks a number; the Release build runs it")
    def test_one_contact_correction_per_step_errs_more(self):
        # Contact 2020 §3.2 and its Fig. 5 "LR Once": with contact after the momentum update
        # only, the step cannot split the change into the extrapolation's and the update's, and
        # the errors are larger. Measured at most 1.7e-3 % against LR's 3.7e-5 % (asserted:
        # ten times LR's, still under the paper's 1%).
        once, twice = self.error("lr_once").max(), self.error("lr").max()
        self.assertGreater(once, 10 * twice)
        self.assertLess(once, 1.0)

    @unittest.skipIf(SANITIZED, "FMPM(4) runs are left out under the sanitizers")
    def test_fmpm_net_reverts_to_single_material_mode(self):
        # FMPM 2026 §3.2: contact on every increment of the FMPM(k) loop by the Net method;
        # FMPM(4) with LR contact stays within 0.036% of single-material FMPM(4) (asserted 0.5%),
        # while the Evolving method fails (det F <= 0 near t = 5.5 ms), as the paper finds it
        # unstable.
        self.assertLess(self.error_against("fmpm_net", "fmpm_single").max(), 0.5)
        with tempfile.TemporaryDirectory() as tmp:
            args = [SMPM, "run", str(EXAMPLE), "-o", str(pathlib.Path(tmp) / "e.h5"), "-q"]
            for s in FMPM4 + LR + ["contact.0.fmpm_method=evolving"]:
                args += ["--set", s]
            r = subprocess.run(args, capture_output=True, text=True, timeout=600)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("det F <= 0", r.stderr)

    def test_distance_function(self):
        # Contact 2020 Fig. 5: with the specified normal, DF is "excellent" (DF + SN; measured
        # at most 1.5e-5 %, asserted 0.1%); with AG normals its errors are "close to" those of
        # approaching-only (measured largest 7.995% for both; asserted within 1.5 points) and
        # below CP = 0.8's (12.47%), the paper's reading that the normal is what limits
        # grid-based detection.
        self.assertLess(self.error("df_sn").max(), 0.1)
        df, approaching = self.error("ag_df").max(), self.error("ag_approaching").max()
        self.assertLess(abs(df - approaching), 1.5)
        self.assertLess(df, self.error("ag_cp").max())

    def test_contact_nodes_of_a_frame(self):
        # The first frame of the LR run: the blocks touch on y = 50 mm, so the contact nodes are
        # the 9 nodes of that line from x = 0 to 40 mm (grid origin (-10, -10), 5 mm cells, 13
        # nodes a row), fields (0, 1), LR normal (0, 1) and d_LR = 0 to 1e-6 of a cell
        # (contact 2020 Eq. 24 on undeformed particles); at rest, none approaches. Later
        # frames: unit normals wherever the node has two fields.
        with h5py.File(pathlib.Path(self.tmp.name) / "lr.h5", "r") as f:
            frames = sorted(f["grid"].values(), key=lambda g: g.name)
            g = frames[0]
            np.testing.assert_array_equal(g["contact_nodes"][:], 12 * 13 + 2 + np.arange(9))
            np.testing.assert_array_equal(g["contact_fields"][:], [0, 1] * 9)
            np.testing.assert_allclose(g["contact_normal"][:], [[0, 1]] * 9, atol=1e-6)
            np.testing.assert_allclose(g["contact_separation"][:], 0, atol=5e-6)
            np.testing.assert_array_equal(g["contact_approaching"][:], 0)
            for g in frames[1:]:
                self.assertGreater(len(g["contact_nodes"]), 9)
                np.testing.assert_allclose(np.linalg.norm(g["contact_normal"][:], axis=1), 1,
                                           atol=1e-12)

    def test_contact_nodes_are_numbered_in_the_grid(self):
        # A step works on the window of the grid around the particles; the files number nodes in
        # the grid. The same blocks on a grid with 8 more cells on each side (origin (-50, -50),
        # 28 x 40 cells, 29 nodes a row): the first frame's contact nodes are the 9 nodes of
        # y = 50 mm from x = 0 (row 20, from node 10), and its nodes with mass are those of the
        # run above shifted by 8 cells along both axes.
        with tempfile.TemporaryDirectory() as tmp:
            out = pathlib.Path(tmp) / "wide.h5"
            args = [SMPM, "run", str(EXAMPLE), "-o", str(out), "-q", "--set", "time.end=0.5"]
            for s in LR + ["grid.origin=[-50.0, -50.0]", "grid.cells=[28, 40]"]:
                args += ["--set", s]
            r = subprocess.run(args, capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr)
            with h5py.File(out, "r") as f, \
                    h5py.File(pathlib.Path(self.tmp.name) / "lr.h5", "r") as ref:
                g = sorted(f["grid"].values(), key=lambda g: g.name)[0]
                np.testing.assert_array_equal(g["contact_nodes"][:], 20 * 29 + 10 + np.arange(9))
                g0 = sorted(ref["grid"].values(), key=lambda g: g.name)[0]
                ng0, ng = 13 * 25, 29 * 41  # nodes of the grids; field a's node i is a n_g + i
                field0, node0 = np.divmod(g0["nodes"][:], ng0)
                shifted = field0 * ng + (node0 // 13 + 8) * 29 + node0 % 13 + 8
                np.testing.assert_array_equal(g["nodes"][:], shifted)
                np.testing.assert_allclose(g["m"][:], g0["m"][:], rtol=1e-12)

    def test_per_material_series(self):
        # Each block: 40 x 50 mm at 0.001 g/mm^3 = 2 g for every step; centres of mass start at
        # (20, 25) and (20, 75) mm and stay on x = 20 (the problem is symmetric) to 1e-4 mm.
        s = self.series["lr"]
        np.testing.assert_allclose(s["material_mass"], 2.0, rtol=1e-12)
        np.testing.assert_allclose(s["material_centre"][0], [20, 25, 20, 75], atol=1e-12)
        np.testing.assert_allclose(s["material_centre"][:, [0, 2]], 20, atol=1e-4)
        self.assertLess(s["material_centre"][-1, 3], 75 - 10)  # the upper block moved down

    def test_average_gradient_normals_err(self):
        # Contact 2020 Fig. 5: grid normals (AG) give errors of several % (measured: largest
        # 8.0% approaching-only, 12.5% CP = 0.8); the paper reports up to 12% for CP = 0.8.
        # Asserted: both above 2% somewhere and below 40% everywhere.
        for name in ("ag_approaching", "ag_cp"):
            with self.subTest(name):
                self.assertGreater(self.error(name).max(), 2)
                self.assertLess(self.error(name).max(), 40)


THREE = SOURCE / "examples" / "three_materials.toml"


def three_materials_stress(work, name, contact):
    """Mean sigma_yy per frame of examples/three_materials.toml with its [[contact]] table
    replaced by `contact`."""
    text = THREE.read_text()
    start, end = text.index("\n[[contact]]") + 1, text.index("\n[[bc]]   # rollers under") + 1
    src = pathlib.Path(work) / (name + ".toml")
    src.write_text(text[:start] + contact + "\n" + text[end:])
    out = pathlib.Path(work) / (name + ".h5")
    r = subprocess.run([SMPM, "run", str(src), "-o", str(out), "-q"], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        frames = sorted(f["particles"].values(), key=lambda g: g.attrs["time"])
        g = f["grid"][sorted(f["grid"])[-1]]
        ng, nf = int(g.attrs["grid_nodes"]), int(g.attrs["velocity_fields"])
        field_mass = np.bincount(g["nodes"][:] // ng, weights=g["m"][:], minlength=nf)
        return np.array([g["stress"][:, 3].mean() for g in frames[1:]]), field_mass


SINGLE_FIELD = """[[contact]]
materials = ["left", "right"]
law = "single-field"
"""
LR_ALL = """[[contact]]
law = "frictionless"
normal = "LR"
detection = "LR"
"""


class ThreeMaterials(unittest.TestCase):
    def test_lumping(self):
        # Contact 2020 §3.4, Fig. 4: three materials meeting at a node, compressed by 5%. With
        # the lumping method (Eq. 50) the mean axial stress is 6.8-8.5% below single material
        # mode (asserted: between 2% and 15%); with left and right in one field (two fields,
        # no node of three) it is within 2e-5 % (asserted: 1e-3 %).
        with tempfile.TemporaryDirectory() as work:
            single = three_materials_stress(
                work, "single", SINGLE_FIELD + "\n" + SINGLE_FIELD.replace('"left", "right"',
                                                                         '"right", "top"'))
            lumped, field_mass = three_materials_stress(work, "lumped", LR_ALL)
            two = three_materials_stress(work, "two", SINGLE_FIELD + "\n" + LR_ALL)[0]
            single = single[0]
        # Each field's nodal masses in the frame sum to its body: 10 x 10, 10 x 10 and
        # 20 x 10 mm at 0.001 g/mm^3 (the frame writes every field's nodes, n_g apart), to
        # 1e-10: nodes lighter than 1e-10 of the heaviest are not active and not written
        # (measured 4e-12).
        np.testing.assert_allclose(field_mass, [0.1, 0.1, 0.2], rtol=1e-10)
        err = 100 * np.abs(lumped / single - 1)
        self.assertGreater(err.max(), 2)
        self.assertLess(err.max(), 15)
        self.assertLess(100 * np.abs(two / single - 1).max(), 1e-3)


class ContactInput(unittest.TestCase):
    def check(self, sets, words):
        check_refused(self, EXAMPLE, sets, words)

    def test_bad_inputs(self):
        self.check(["contact.0.law=glue"], ["contact.0.law", "stick | frictionless"])
        self.check(["contact.0.materials=[\"lower\", \"lid\"]"], ["no [[material]] named 'lid'"])
        self.check(["contact.0.materials=[\"lower\", \"lower\"]"], ["not in contact with itself"])
        self.check(["contact.0.law=stick"], ["contact.0.friction", "only the coulomb law"])
        self.check(["contact.0.friction=-1"], ["contact.0.friction", "non-negative"])
        self.check(["contact.0.normal=XY"], ["contact.0.normal", "AG"])
        self.check(["contact.0.detection=PF"], ["contact.0.detection", "CP (critical position) | DF"])
        self.check(["contact.0.df_exponent=0.5"], ["contact.0.df_exponent", "only detection"])
        self.check(["contact.0.detection=DF", "contact.0.df_reach=0"],
                   ["contact.0.df_reach", "(0, 10]"])
        self.check(["contact.0.fmpm_method=both"], ["contact.0.fmpm_method", "net | evolving"])
        self.check(["contact.0.normal=specified"], ["contact.0.direction", "missing"])
        self.check(SN[:1] + ["contact.0.direction=[0.0, 0.0]"], ["must be a non-zero vector"])
        self.check(["contact.0.critical_separation=1", "contact.0.detection=always"],
                   ["only detection = \"CP\""])


if __name__ == "__main__":
    unittest.main(verbosity=2)
