#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Input refused before any work (exit 2, one line naming the file, the line and the key, no
output written): each class of bad input, inputs that are not files, control characters,
numbers and caps in messages, sizes whose products overflow, the contact inputs' ranges, long
keys and expressions clipped, an earlier table name's type error located once; and a direction
with large entries read as the unit vector it points along. Inputs whose every value is valid
but whose run cannot be carried out are test_input_limits.py's.

Run by ctest (cli.bad_input) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import os
import unittest

import h5py
import numpy as np

from example_runs import BAR, EXAMPLES, Base, one_line, smpm


def line_of(needle):
    """'bad.toml:<n>:' for the first line of the vibrating-bar example that contains needle."""
    lines = (EXAMPLES / "vibrating_bar.toml").read_text().splitlines()
    return "bad.toml:%d:" % next(i + 1 for i, l in enumerate(lines) if needle in l)


class BadInput(Base):
    """One test per class of bad input: exit status 2, one line naming file, key (and line),
    and no output file."""

    def run_bad(self, text=None, extra=(), expect=()):
        src = (EXAMPLES / "vibrating_bar.toml").read_text()
        for old, new in text or []:
            self.assertIn(old, src)
            src = src.replace(old, new, 1)
        path = self.dir / "bad.toml"
        path.write_text(src)
        out = self.dir / "out.h5"
        r = smpm("run", path, "-o", out, "-q", *extra)
        self.assertEqual(r.returncode, 2, r.stderr)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        for e in expect:
            self.assertIn(e, lines[0])
        self.assertFalse(out.exists(), "an output file was left behind")
        self.assertFalse(out.with_suffix(".xmf").exists())
        return lines[0]

    def test_unknown_key_suggests(self):
        self.run_bad([("cell_size", "cell_sizes")], expect=[line_of("cell_size"), "grid.cell_sizes", "did you mean 'cell_size'"])

    def test_missing_key(self):
        self.run_bad([("end = 400.0", "")], expect=["bad.toml", "time.end", "missing required key"])

    def test_wrong_type(self):
        self.run_bad([("youngs = 2.0", "youngs = [2.0]")], expect=[line_of("youngs = 2.0"), "material.bar.youngs", "expected a number"])

    def test_non_positive_density(self):
        self.run_bad([("density = 0.5", "density = -0.5")], expect=[line_of("density = 0.5"), "material.bar.density = -0.5", "must be positive"])

    def test_non_positive_modulus(self):
        self.run_bad([("youngs = 2.0", "youngs = 0")], expect=["material.bar.youngs = 0", "must be positive"])

    def test_non_positive_cell_size(self):
        self.run_bad([("cell_size = [1.0]", "cell_size = [-1.0]")], expect=[line_of("cell_size = [1.0]"), "grid.cell_size"])

    def test_non_positive_courant(self):
        self.run_bad(extra=["--set", "time.courant=-0.1"], expect=["time.courant = -0.1", "must be positive"])

    def test_particles_outside_grid(self):
        self.run_bad([("max = [40.0]", "max = [50.0]")], expect=["bad.toml", "particles outside the grid"])

    def test_expression_does_not_parse(self):
        self.run_bad([("sin(pi*X/80)", "sin(pi*X/80")], expect=[line_of("sin(pi*X/80)"), "body.0.velocity", "cannot parse"])

    def test_unknown_override(self):
        self.run_bad(extra=["--set", "step.shap=gimp"], expect=["step.shap", "did you mean 'shape'"])

    def test_output_not_writable(self):
        src = self.dir / "ok.toml"
        src.write_text((EXAMPLES / "vibrating_bar.toml").read_text())
        r = smpm("run", src, "-o", self.dir / "no" / "such" / "dir.h5", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1)
        self.assertIn("does not exist", r.stderr)
        self.assertFalse((self.dir / "no").exists())

    def test_held_temperature_with_b_splines(self):
        # Quadratic B-spline nodal values are control points: a held temperature node does not
        # hold the plane (docs/studies/heat.md), so `smpm run` refuses the pair before any write; the
        # transport stability of the same input, which runs no simulation, takes it.
        bar = EXAMPLES / "conduction_bar.toml"
        for shape in ("bspline2", "b2cpdi"):
            out = self.dir / (shape + ".h5")
            line = one_line(self, smpm("run", bar, "-o", out, "--set", "step.shape=" + shape), 2)
            self.assertIn("conduction_bar.toml: bc.0.temperature: a held temperature needs", line)
            self.assertIn('step.shape = "%s"' % shape, line)
            self.assertFalse(list(self.dir.glob(shape + "*")), "a file was left behind")
        r = smpm("transport-stability", bar, "--set", "step.shape=bspline2", "--order", "4",
                 "--no-exact", "-o", self.dir / "t.csv")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_missing_input_file(self):
        r = smpm("run", self.dir / "absent.toml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("absent.toml: cannot open the input file", r.stderr)


class Inputs(Base):
    """Items 9, 11, 16: inputs that are not files, control characters, messages."""

    def test_inputs_that_are_not_files(self):
        self.assertIn("regular file", one_line(self, smpm("run", "/dev/zero", timeout=20), 2))
        self.assertIn("directory", one_line(self, smpm("run", self.dir, timeout=20), 2))
        fifo = self.dir / "fifo"
        os.mkfifo(fifo)
        for args in (("run", fifo), ("info", fifo), ("stability", fifo)):
            with self.subTest(cmd=args[0]):
                self.assertIn("regular file", one_line(self, smpm(*args, timeout=20), 2))
        big = self.dir / "big.toml"
        big.write_text(BAR.read_text() + "#" * (17 << 20))
        self.assertIn("16777216", one_line(self, smpm("run", big, timeout=20), 2))

    def test_control_characters_in_set(self):
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "x.h5", "--set", "output.file=a\nb.h5"), 2)
        self.assertIn("control character", line)
        self.assertFalse(list(self.dir.iterdir()))

    def test_messages(self):
        src = self.dir / "bar.toml"
        text = BAR.read_text()
        cases = (
            (text.replace("origin = [-2.0]", "origin = [nan]"), "must be finite"),
            (text.replace("cells = [48]", "cells = [2000000000]"), "at most"),
        )
        for body, want in cases:
            with self.subTest(want=want):
                src.write_text(body)
                self.assertIn(want, one_line(self, smpm("run", src, "-o", self.dir / "m.h5"), 2))
        src.write_bytes(b"\xef\xbb\xbf" + text.encode())  # a UTF-8 byte-order mark is accepted
        r = smpm("run", src, "-o", self.dir / "bom.h5", "-q", "--set", "time.end=10")
        self.assertEqual(r.returncode, 0, r.stderr)
        long_value = "x" * 2000
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "l.h5", "--set", "step.shape=" + long_value), 2)
        self.assertLess(len(line), 400)
        # Numbers in messages are short (before: 300 digits twice), and a cap is stated.
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "l.h5", "--set", "time.end=1e300"), 2)
        self.assertIn("frames up to time.end = 1e+300, more than the 100000 accepted", line)
        self.assertLess(len(line), 300)
        for key in ("step.order", "step.blend_every"):
            line = one_line(self, smpm("run", BAR, "-o", self.dir / "l.h5", "--set", key + "=1000000"), 2)
            self.assertIn("must be an integer from 1 to 100000", line)


class OverflowingSizes(Base):
    """Sizes whose products overflow are refused at input by key (exit 2, nothing written); they
    surfaced as failures of step 1 ("the time step must be positive", an infinite mass)."""

    def refused(self, *sets, example=BAR):
        r = smpm("run", example, "-o", self.dir / "out.h5", "-q", *[a for s in sets for a in ("--set", s)])
        line = one_line(self, r, 2)
        self.assertEqual(list(self.dir.glob("out*")), [])
        return line

    def test_sizes_that_overflow(self):
        # The bar: density 0.5, so E = 1e308 gives E / rho = inf.
        line = self.refused("material.0.youngs=1e308")
        self.assertIn("material.bar.youngs = 1e+308: gives an infinite wave speed", line)
        # 2D: a cell of (1e200)^2 has no finite volume; a cell of (1e-200)^2 has none either.
        for h in ("1e200", "1e-200"):
            line = self.refused("grid.cell_size=[%s, %s]" % (h, h),
                                example=EXAMPLES / "two_block_compression.toml")
            self.assertIn("grid.cell_size: the cell volume", line)
            self.assertIn("is not a positive finite number", line)
        line = self.refused("grid.cell_size=[1e307]")  # 48 cells
        self.assertIn("grid.cell_size: the grid's extent along axis 0 overflows", line)
        # Particles of 4 (one per cell of 4) at a density of 1e308 (E / rho = 1).
        line = self.refused("material.0.density=1e308", "material.0.youngs=1e308",
                            "body.0.ppc=[1]", "grid.cell_size=[4.0]")
        self.assertIn("material.bar.density: gives particle 0 an infinite mass", line)


class ContactLimits(Base):
    """The contact inputs' ranges: δ_c in cells, and the number of materials (the contact laws
    are a table over pairs of fields). Each was accepted: -1 and 1e300 as δ_c; 20,000 materials
    with a fallback law ended in std::bad_alloc after a quadratic duplicate check."""

    def test_critical_separation_range(self):
        two = EXAMPLES / "two_block_compression.toml"
        for value in ("-1", "1e300", "4.5"):
            r = smpm("run", two, "-o", self.dir / "out.h5", "-q",
                     "--set", "contact.0.critical_separation=" + value)
            line = one_line(self, r, 2)
            self.assertIn("contact.0.critical_separation", line)
            self.assertIn("must be in [0, 4] cells", line)
        self.assertEqual(list(self.dir.glob("out*")), [])

    def test_too_many_materials(self):
        inp = self.dir / "many.toml"
        mats = "".join('[[material]]\nname = "m%d"\ndensity = 1.0\nyoungs = 1.0\n\n' % i
                       for i in range(20000))
        inp.write_text("[grid]\ndim = 1\norigin = [0.0]\ncell_size = [1.0]\ncells = [10]\n\n" + mats +
                       '[[body]]\nmaterial = "m0"\nregion = "box"\nmin = [0.0]\nmax = [4.0]\n'
                       'ppc = [2]\n\n[[contact]]\nlaw = "stick"\n\n[time]\nend = 1.0\n')
        line = one_line(self, smpm("run", inp, "-o", self.dir / "out.h5", "-q"), 2)
        self.assertIn("[[material]]: 20000 tables, more than the 1000 materials a model takes",
                      line)
        self.assertEqual(list(self.dir.glob("out*")), [])


class Messages(Base):
    """One line that says what is wrong, however long what the input holds."""

    def test_long_keys_and_expressions_are_clipped(self):
        text = BAR.read_text()
        key = "k" * 100000
        inp = self.dir / "key.toml"
        inp.write_text(text.replace("[time]", "[time]\n%s = 1\n" % key))
        line = one_line(self, smpm("run", inp, "-o", self.dir / "out.h5", "-q"), 2)
        self.assertLess(len(line), 400)  # the whole key made a 100 kB line
        self.assertIn("time.kkkk", line)
        self.assertIn("(100005 characters)", line)
        self.assertIn("unknown key", line)
        inp = self.dir / "expr.toml"
        inp.write_text(text.replace('velocity = ["0.16*sin(pi*X/80)"]',
                                    'velocity = ["%s@"]' % ("1+" * 50000)))
        line = one_line(self, smpm("run", inp, "-o", self.dir / "out.h5", "-q"), 2)
        self.assertLess(len(line), 500)  # muparser's echo of the expression made another
        self.assertIn("body.0.velocity: cannot parse '1+1+", line)
        self.assertIn("(100001 characters)", line)
        self.assertEqual(list(self.dir.glob("out*")), [])


class EarlierNames(Base):
    def test_a_type_error_under_the_earlier_table_name_is_located_once(self):
        # [scheme] is the earlier name of [step]: its type errors printed the location twice.
        text = BAR.read_text().replace("[step]", "[scheme]").replace(
            'velocity = "FLIP" ', "velocity = 4 ", 1)
        inp = self.dir / "sch.toml"
        inp.write_text(text)
        line = one_line(self, smpm("run", inp, "-o", self.dir / "out.h5", "-q"), 2)
        self.assertRegex(line, r"^smpm: error: [^ ]*sch\.toml:\d+: step\.velocity = 4: expected a "
                               r"string$")
        self.assertEqual(line.count("sch.toml"), 1)


class Directions(Base):
    """A direction with large entries (a wall's normal, a velocity condition's or a contact's
    direction) is the unit vector it points along: scaled by its largest entry before it is
    normalised (|[1e200, 0]| overflows to inf, and the direction divided by it was zero)."""

    INPUT = ("[grid]\ndim = 2\norigin = [0.0, 0.0]\ncell_size = [1.0, 1.0]\ncells = [20, 4]\n\n"
             "[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs = 10.0\n\n"
             "[[body]]\nmaterial = \"m\"\nregion = \"box\"\nmin = [2.0, 0.0]\nmax = [8.0, 4.0]\n"
             "ppc = [2, 2]\nvelocity = [\"1\", \"0\"]\n\n"
             "[[bc]]\nplane = {{ axis = \"x\", at = 2.0 }}\n"
             "velocity = {{ direction = [{d}, 0.0], value = 0.5 }}\n\n"
             "[[bc]]\nwall = {{ normal = [{d}, 0.0], position = \"9\", velocity = 0.0, "
             "gradient = 0.0, depth_cells = 1.0 }}\n\n"
             "[time]\nend = 3.0\n\n[output]\nevery = 3.0\n")

    def final_positions(self, name, d):
        inp = self.dir / (name + ".toml")
        inp.write_text(self.INPUT.format(d=d))
        out = self.dir / (name + ".h5")
        r = smpm("run", inp, "-o", out, "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(out, "r") as f:
            return f["particles"]["000001"]["X"][:]

    def test_large_entries(self):
        unit = self.final_positions("unit", "1.0")
        # The conditions act: the wall at x = 9 holds the block (moving at 1 for t = 3, a free
        # block's right edge would reach 11).
        self.assertLess(unit[:, 0].max(), 9.5)
        # Scaling by the largest entry gives exactly [1, 0]: the same run bit for bit.
        np.testing.assert_array_equal(self.final_positions("large", "1e200"), unit)
        np.testing.assert_array_equal(self.final_positions("small", "1e-300"), unit)

    def test_contact_direction(self):
        sets = ["time.end=2", "output.every=2", "contact.0.normal=specified"]
        def run(d):
            out = self.dir / f"c{len(d)}.h5"
            args = [a for s in (*sets, f"contact.0.direction={d}") for a in ("--set", s)]
            r = smpm("run", EXAMPLES / "two_block_compression.toml", "-o", out, "-q", *args)
            self.assertEqual(r.returncode, 0, r.stderr)
            with h5py.File(out, "r") as f:
                return f["particles"]["000001"]["V"][:]
        np.testing.assert_array_equal(run("[0.0, 1e200]"), run("[0.0, 1.0]"))


if __name__ == "__main__":
    unittest.main(verbosity=2)
