#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Inputs that a run cannot carry out are refused with one line naming the file, the key and the
value (exit 2), or stop the run naming the step and the particle (exit 3), before any file is
written: a time step that would take the run forever, overlapping bodies, speeds whose time step
underflows, images that are not what they claim, and the messages of the image and TOML
readers. Each test is named after the case it keeps.

Run by ctest with SMPM (the binary) and SMPM_SOURCE (the source tree) in the environment.
"""
import os
import struct
import subprocess
import unittest
import zlib

import h5py
import numpy as np

from example_runs import EXAMPLES, SMPM, Base, smpm


def png(path, width, height, rows=None):
    """A grey 8-bit PNG whose header claims width x height (rows: the pixel rows, if any)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + bytes(r) for r in (rows or [[0] * 4] * 4))
    path.write_bytes(b"\x89PNG\r\n\x1a\n"
                     + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


BOXES = """
[grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [1.0, 1.0]
cells = [10, 10]
[[material]]
name = "m"
density = 1.0
youngs = 1.0
{materials}
[[body]]
material = "m"
min = [2.0, 2.0]
max = [6.0, 6.0]
ppc = [2, 2]
{body}
[time]
end = 1.0
[output]
every = 0.5
"""

IMAGE = """
[grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [1.0, 1.0]
cells = [10, 10]
[[material]]
name = "m"
density = 1.0
youngs = 1.0
[[body]]
material = "m"
region = "image"
image = "{image}"
pixel_size = {pixel}
origin = [2.0, 2.0]
ppc = [2, 2]
[time]
end = 1.0
[output]
every = 0.5
"""


class Refusals(Base):
    def refused(self, args, code=2):
        """The one line of a refused run; nothing is left in the directory but the inputs."""
        before = sorted(p.name for p in self.dir.iterdir())
        r = smpm("run", *args, "-o", self.dir / "out.h5", "-q")
        self.assertEqual(r.returncode, code, r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertEqual(sorted(p.name for p in self.dir.iterdir()), before)
        return r.stderr.strip()


class RunLength(Refusals):
    def test_a_run_that_would_not_end_is_refused(self):
        # conductivity = 1e30: the conduction limit F dx^2 / D gives dt ~ 1e-34 and the run
        # ~1e33 steps (it wrote a series row per step, 1.35 million rows in 10 s). Refused at
        # once, naming the limit, its key and the dt it implies.
        line = self.refused([EXAMPLES / "conduction_bar.toml", "--set",
                             "material.bar.conductivity=1e30"])
        self.assertIn("the conduction limit time.fourier = 0.1", line)
        self.assertIn("dt = 6.25e-35", line)  # 0.1 (0.025)^2 / 1e30
        self.assertIn("more than time.max_steps = 10000000", line)
        # The cap is an input key: the bar's 1600 steps exceed 10.
        line = self.refused([EXAMPLES / "vibrating_bar.toml", "--set", "time.max_steps=10"])
        self.assertIn("about 1600 steps of dt = 0.25, from the Courant limit time.courant = 0.5",
                      line)
        self.assertIn("time.max_steps = 10", line)
        self.assertIn("time.max_steps", self.refused([EXAMPLES / "vibrating_bar.toml", "--set",
                                                      "time.max_steps=2.5"]))

    def test_a_huge_finite_speed_is_refused_with_its_particle(self):
        # velocity = [1e200]: the Courant step C dx / |V| underflows. It stopped with exit 1 and
        # the library's precondition ("the time step must be positive and finite, got 0").
        line = self.refused([EXAMPLES / "vibrating_bar.toml", "--set", "body.0.velocity=[1e200]"])
        self.assertIn("time.courant", line)
        self.assertIn("particle 0 moves at |V| = 1e+200", line)
        # A free rigid body at 1e300: the same, naming the rigid body's particle.
        line = self.refused([EXAMPLES / "rigid_impact.toml", "--set",
                             "material.block.velocity=[1e300, 0.0]"])
        self.assertIn("moves at |V| = 1e+300", line)

    def test_a_rigid_velocity_not_finite_at_t0_names_its_key(self):
        # "1/t" is inf at t = 0: an input value, named by its key (it stopped as a numerical
        # failure naming no step).
        line = self.refused([EXAMPLES / "rigid_piston.toml", "--set",
                             'material.piston.velocity=["1/t"]'])
        self.assertIn("material.piston.velocity", line)
        self.assertIn("is inf at t = 0", line)


class Bodies(Refusals):
    def test_overlapping_bodies_give_the_point_to_the_first(self):
        # NairnMPM's rule (MPMReadHandler::MPMPts: a position filled by an earlier body is not
        # filled again): two 4 x 4 boxes overlapping on 2 x 2 hold the mass of their union,
        # 16 + 16 - 4 = 28 (density 1), not 32.
        inp = self.dir / "boxes.toml"
        inp.write_text(BOXES.format(materials="", body='[[body]]\nmaterial = "m"\n'
                                    'min = [4.0, 4.0]\nmax = [8.0, 8.0]\nppc = [2, 2]'))
        r = smpm("run", inp, "-o", self.dir / "b.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "b.h5", "r") as f:
            p = f["particles"]["000000"]
            self.assertEqual(len(p["mass"]), 112)  # (64 + 64 - 16) particles of 1/4
            self.assertAlmostEqual(p["mass"][()].sum(), 28.0, places=12)
        # An identical second box, or a rigid piston inside the first, is left with no particle:
        # refused by its region.
        for body in ('[[body]]\nmaterial = "m"\nmin = [2.0, 2.0]\nmax = [6.0, 6.0]\nppc = [2, 2]',
                     '[[body]]\nmaterial = "piston"\nmin = [3.0, 3.0]\nmax = [4.0, 4.0]\n'
                     'ppc = [2, 2]'):
            with self.subTest(body=body.splitlines()[1]):
                inp.write_text(BOXES.format(
                    materials='[[material]]\nname = "piston"\nmodel = "rigid"\ndensity = 1.0\n'
                              'velocity = ["0", "0"]', body=body))
                line = self.refused([inp])
                self.assertIn("body.1.region: holds no particle that an earlier [[body]] does "
                              "not already fill", line)


class Images(Refusals):
    def test_a_png_claiming_a_huge_size_is_refused_before_any_buffer(self):
        # A PNG of under 100 bytes whose header claims 10^6 x 10^6 pixels: it allocated 3.5 GB before
        # libpng refused it. The header's size is checked first (2^28 pixels at most).
        png(self.dir / "huge.png", 10**6, 10**6)
        self.assertLess((self.dir / "huge.png").stat().st_size, 100)
        inp = self.dir / "img.toml"
        inp.write_text(IMAGE.format(image="huge.png", pixel="1.0"))
        line = self.refused([inp])
        self.assertIn("body.0.image", line)
        self.assertIn("claims 1000000 x 1000000 pixels, more than the 268435456", line)

    def test_an_image_that_is_a_fifo_is_refused(self):
        # A FIFO blocked the reader forever.
        os.mkfifo(self.dir / "fifo.png")
        inp = self.dir / "img.toml"
        inp.write_text(IMAGE.format(image="fifo.png", pixel="1.0"))
        line = self.refused([inp])
        self.assertIn("body.0.image", line)
        self.assertIn("not a regular file", line)

    def test_image_messages_name_what_made_them(self):
        png(self.dir / "small.png", 4, 4, [[0, 0, 255, 255]] * 4)
        inp = self.dir / "img.toml"
        # Reaching out of the grid: the extent and what sets it (it named pixel_size's line
        # whatever made the image reach out).
        inp.write_text(IMAGE.format(image="small.png", pixel="3.0"))
        line = self.refused([inp])
        self.assertIn("body.0.image", line)
        self.assertIn("4 x 4 pixels of pixel_size = 3 from the origin (2, 2)) reaches (14, 14)",
                      line)
        # A pixel too small to give the image an extent (it said "block max[0] must exceed
        # min[0]" without file, line or key).
        inp.write_text(IMAGE.format(image="small.png", pixel="1e-300"))
        line = self.refused([inp])
        self.assertIn(str(inp) + ":", line)
        self.assertIn("body.0.pixel_size", line)
        self.assertIn("has no extent", line)
        inp.write_text(IMAGE.format(image="small.png", pixel="1.0"))
        r = smpm("run", inp, "-o", self.dir / "ok.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_a_restart_finds_the_image_beside_its_input(self):
        # The image is named relative to the input file; a restart reads the input stored in
        # the run file, which may be elsewhere. It looked for the image beside the run file
        # only: a run written to another directory could not be continued. Now it looks beside
        # the input the run was given first (its name as the run was given it, from the same
        # working directory), then beside the run file; the restart's body equals the run's.
        (self.dir / "in").mkdir()
        (self.dir / "out").mkdir()
        png(self.dir / "in" / "small.png", 4, 4, [[0, 0, 255, 255]] * 4)
        (self.dir / "in" / "img.toml").write_text(IMAGE.format(image="small.png", pixel="1.0"))
        def run(*args):
            return subprocess.run([SMPM, "run", *map(str, args), "-q"], capture_output=True,
                                  text=True, timeout=120, cwd=self.dir)
        r = run("in/img.toml", "-o", "out/run.h5", "--set", "time.end=0.5")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = run("--restart", "out/run.h5", "-o", "out/again.h5")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "out" / "run.h5", "r") as a, \
                h5py.File(self.dir / "out" / "again.h5", "r") as b:
            # 8 dark pixels (two of each row of four) at ppc 2 x 2: 32 particles
            self.assertEqual(b["particles"]["000000"]["X"].shape, (32, 2))
            self.assertTrue(np.array_equal(a["particles"]["000001"]["X"][()],
                                           b["particles"]["000001"]["X"][()]))
        # Without the input's directory (moved away), beside the run file.
        (self.dir / "in" / "small.png").rename(self.dir / "out" / "small.png")
        r = run("--restart", "out/run.h5", "-o", "out/third.h5")
        self.assertEqual(r.returncode, 0, r.stderr)


class Toml(Refusals):
    def test_a_float_out_of_range_names_its_key(self):
        # 1e309 is refused by the TOML parser: the message named the file and line, not the key.
        inp = self.dir / "big.toml"
        inp.write_text(BOXES.format(materials="", body="").replace("end = 1.0", "end = 1e309"))
        line = self.refused([inp])
        self.assertRegex(line, r"big\.toml:\d+: time\.end: ")


if __name__ == "__main__":
    unittest.main(verbosity=2)
