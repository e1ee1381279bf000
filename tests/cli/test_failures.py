#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A run that cannot go on keeps the frames before its failure and says why in one line: a
numerical failure (exit 3: an unstable step, a particle that leaves the grid on a frame, a
condition or moving wall whose value stops being finite, a time step that collapses) or a
condition that fails only at a later step (exit 1); the work of gravity is not taken for an
instability.

Run by ctest (cli.failures) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import re
import unittest

import h5py
import numpy as np

from example_runs import EXAMPLES, Base, one_line, smpm


class NumericalFailure(Base):
    def test_unstable_run_stops_with_step_and_particle(self):
        # C = 1.5 is far above the FLIP limit (~0.84, FMPM 2026 §3.3): the bar blows up.
        out = self.dir / "unstable.h5"
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", out, "-q", "--set", "time.courant=1.5", "--set", "output.every=2")
        self.assertEqual(r.returncode, 3, r.stderr)
        line = r.stderr.strip()
        self.assertEqual(len(line.splitlines()), 1)
        self.assertRegex(line, r"step \d+ \(t = [0-9.e+-]+\): .*particle \d+")
        self.assertFalse(out.exists())  # a failed run leaves its partial file, not a result
        with h5py.File(self.dir / "unstable.partial.h5", "r") as f:  # frames before the failure
            self.assertIn("failed", f.attrs["status"])
            step = int(re.search(r"step (\d+)", line).group(1))
            self.assertEqual(f["series"]["step"][-1], step - 1)  # the series up to the failure
            self.assertGreaterEqual(len(f["particles"]), 1)
            for frame in f["particles"].values():
                self.assertTrue(np.all(np.isfinite(frame["X"][:])))


class BodyForce(Base):
    def test_gravity_is_not_mistaken_for_instability(self):
        # Gravity does work, so kinetic + strain energy may grow far beyond 10x its start; the
        # blow-up test applies only without body forces.
        out = self.dir / "fall.h5"
        r = smpm("run", EXAMPLES / "two_disks.toml", "-o", out, "-q", "--set", "loads.gravity=[0.0, -2.0]",
                 "--set", "time.end=0.2", "--set", "output.every=0.1")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(out, "r") as f:
            total = f["series"]["total"][:]
            self.assertGreater(total[-1], 10 * total[0])
            momentum = f["series"]["momentum"][:]
            mass = sum(g["mass"][:].sum() for g in [f["particles"]["000000"]])
            t = f["series"]["t"][:]
            # Free fall: Σ M V_y changes by −2 Σ M per unit time (no boundary touched yet).
            self.assertAlmostEqual((momentum[-1, 1] - momentum[0, 1]) / (mass * t[-1]), -2.0, delta=1e-9)


class ExitCodes(Base):
    """A particle that leaves the grid in a step that ends on a frame is that run's numerical
    failure (exit 3, the step and particle named), not a failed write of the frame (exit 1)."""

    def test_leaving_the_grid_on_a_frame(self):
        inp = self.dir / "leave.toml"
        # One particle at 9.5 moving at 10 on a grid [0, 10]; C = 1 gives Δt = 0.1, so every step
        # ends on a frame (every 0.1), and the first puts the particle at 10.5, off the grid.
        inp.write_text("[grid]\ndim = 1\norigin = [0.0]\ncell_size = [1.0]\ncells = [10]\n\n"
                       "[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs = 1e-6\n\n"
                       "[[body]]\nmaterial = \"m\"\nregion = \"box\"\nmin = [9.25]\nmax = [9.75]\n"
                       "ppc = [1]\nvelocity = [\"10\"]\n\n[time]\ncourant = 1.0\nend = 1.0\n\n"
                       "[step]\nshape = \"linear\"\n\n[output]\nevery = 0.1\n")
        line = one_line(self, smpm("run", inp, "-o", self.dir / "out.h5", "-q"), 3)
        self.assertIn("smpm: numerical failure: step 2 (t = 0.1): particle 0 at (10.5) has left the grid", line)
        self.assertNotIn("disk", line)
        with h5py.File(self.dir / "out.partial.h5", "r") as f:  # frame 0 kept, the status says why
            self.assertEqual(sorted(f["particles"].keys()), ["000000"])
            self.assertIn("left the grid", f.attrs["status"])


def bar_with_bc(bc, end=12.0):
    """A 1D elastic bar on [0, 4] of a grid [0, 10], at rest, with the given [[bc]] table."""
    return ("[grid]\ndim = 1\norigin = [0.0]\ncell_size = [1.0]\ncells = [10]\n\n"
            "[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs = 1.0\n\n"
            "[[body]]\nmaterial = \"m\"\nregion = \"box\"\nmin = [0.0]\nmax = [4.0]\nppc = [2]\n\n"
            "[[bc]]\n" + bc + "\n\n[time]\ncourant = 0.5\nend = %r\n\n"
            "[step]\nshape = \"linear\"\n\n[output]\nevery = 1.0\n" % end)


class NonFiniteConditions(Base):
    """A velocity condition or moving wall whose value stops being finite stops the run as a
    numerical failure naming it (exit 3, every frame before kept); a NaN number in the input is
    refused by key (exit 2, nothing written)."""

    def run_bar(self, bc, end=12.0, name="out"):
        inp = self.dir / "bar.toml"
        inp.write_text(bar_with_bc(bc, end))
        return smpm("run", inp, "-o", self.dir / (name + ".h5"), "-q")

    def test_a_wall_whose_position_stops_being_finite(self):
        # s_w = 5 + sqrt(1 - t/10) is NaN after t = 10: the wall selected no node and the run
        # ended with exit 0 as if it had no wall. Δt = 0.5: step 22 starts at t = 10.5.
        line = one_line(self, self.run_bar(
            'wall = { normal = [1.0], position = "5 + sqrt(1 - t/10)" }'), 3)
        self.assertEqual(line, "smpm: numerical failure: step 22 (t = 11): bc.0.wall.position is "
                               "nan at t = 10.5 (the moving wall needs finite values)")
        with h5py.File(self.dir / "out.partial.h5", "r") as f:  # the frames of t = 0 ... 10
            self.assertEqual(len(f["particles"]), 11)
            self.assertIn("bc.0.wall.position", f.attrs["status"])

    def test_a_wall_velocity_and_a_condition_value_that_stop_being_finite(self):
        # These were reported as a particle's non-finite velocity, naming no condition.
        line = one_line(self, self.run_bar(
            'wall = { normal = [1.0], position = 4.0, velocity = "sqrt(0.5 - t)" }'), 3)
        # Step 3 starts at t = 1, where the frame is written (the step is prepared there).
        self.assertIn("step 3 (t = 1): bc.0.wall.velocity is nan at t = 1", line)
        line = one_line(self, self.run_bar(
            'plane = { axis = "x", at = 0.0 }\nvelocity = { direction = [1.0], '
            'value = "sqrt(0.5 - t)" }', name="condition"), 3)
        self.assertIn("step 3 (t = 1.5): condition 'bc.0.velocity' gives nan at node 0 "
                      "at t = 1", line)

    def test_a_nan_velocity_value_is_refused(self):
        # value = nan ran to step 1 and failed there (exit 3).
        for value in ("nan", "inf", "-inf"):
            line = one_line(self, self.run_bar(
                'plane = { axis = "x", at = 0.0 }\nvelocity = { direction = [1.0], value = %s }'
                % value), 2)
            self.assertIn("bc.0.velocity.value", line)
            self.assertIn("must be finite", line)
            self.assertEqual(list(self.dir.glob("out*")), [])


class Stalls(Base):
    """A run whose time step collapses stops as a numerical failure: a wall at 20 km/s drives a
    short nickel bar to the Mie-Gruneisen limit 1 - J = 1/S1, where the wave speed diverges; Δt
    fell from 1e-5 to 2e-12 over 57,742 steps and the run never ended."""

    def test_a_shock_at_the_mie_gruneisen_limit(self):
        sets = ['bc.3.wall.position="12 - 20000*t"', "bc.3.wall.velocity=-20000.0",
                "body.0.max=[10.0, 2.5]", "body.1.min=[10.0, 0.0]", "body.1.max=[12.0, 2.5]",
                "bc.0.box.max=[13.0, 0.0]", "bc.1.box.max=[13.0, 3.5]", "output.every=5e-5"]
        r = smpm("run", EXAMPLES / "shock_split_bar.toml", "-o", self.dir / "s.h5", "-q",
                 *[a for s in sets for a in ("--set", s)], timeout=300)
        line = one_line(self, r, 3)
        self.assertRegex(line, r"^smpm: numerical failure: step \d+ \(t = [0-9.e-]+\): the time "
                               r"step [0-9.e-]+ fell below 0.001 of the first step's "
                               r"1.08606e-05 \(the signal speed grew [0-9.]+ times\); particle "
                               r"\d+ is compressed to S1 \(1 - J\) = 0.99")
        with h5py.File(self.dir / "s.partial.h5", "r") as f:  # t = 0, 5e-5, 1e-4, 1.5e-4
            self.assertEqual(len(f["particles"]), 5)
            self.assertIn("fell below", f.attrs["status"])
        # Restarted from its last frame, the run fails at the same step with the same numbers:
        # the reference is the first step of t = 0, not the first step after the restart.
        again = smpm("run", "--restart", self.dir / "s.partial.h5", "-o", self.dir / "r.h5", "-q",
                     timeout=300)
        self.assertEqual(one_line(self, again, 3), line)


CONFLICT = """
[grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [1.0, 1.0]
cells = [20, 20]
[[material]]
name = "a"
density = 1.0
youngs = 100.0
[[body]]
material = "a"
min = [4.0, 4.0]
max = [10.0, 10.0]
ppc = [2, 2]
velocity = ["2", "0"]
[[bc]]
plane = { axis = "y", at = 4.0 }
fixed = ["y"]
[[bc]]
wall = { normal = [1.0, 1.0], position = "14 - 2*t", velocity = -2.0, gradient = 0.0, depth_cells = 1.0 }
[time]
end = 3.0
[output]
every = 0.2
"""


class LaterFailure(Base):
    """A condition that fails only at a later step is a failed run (exit 1, not the bad-input
    2) that keeps its frames."""

    def test_a_condition_failing_at_a_later_step_is_a_failed_run(self):
        # A fixed-y plane and a wall with normal (1, 1) moving onto the block: they first meet
        # on a node at step 18 (t = 0.85). The input was valid; the run fails at that step
        # (exit 1, not the bad-input 2) and keeps its frames.
        src = self.dir / "conflict.toml"
        src.write_text(CONFLICT)
        r = smpm("run", src, "-o", self.dir / "c.h5", "-q")
        line = one_line(self, r, 1)
        self.assertIn("step 18 (from t = 0.85", line)
        self.assertIn("at an angle", line)
        with h5py.File(self.dir / "c.partial.h5", "r") as f:
            self.assertIn("failed: step 18", f.attrs["status"])
            self.assertEqual(len([n for n in f["particles"] if "complete" in f["particles"][n].attrs]), 5)


if __name__ == "__main__":
    unittest.main(verbosity=2)
