#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""End-to-end tests of the file-safety promises of `smpm` (README, "What survives"): results are
never destroyed by a rerun that fails, is killed or points at the wrong path; a full disk, a
signal or a closed stdout end the run with a one-line message and a non-zero status; inputs that
are not files, bad restart files and bad options are refused before any work.

Run by ctest with SMPM (the binary) and SMPM_SOURCE (the source tree) in the environment.
"""
import csv
import hashlib
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import h5py
import numpy as np

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE / "examples"
BAR = EXAMPLES / "vibrating_bar.toml"


def smpm(*args, timeout=600, **kw):
    return subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, timeout=timeout, **kw)


def digest(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def one_line(test, r, code):
    test.assertEqual(r.returncode, code, r.stderr)
    test.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
    return r.stderr.strip()


class Base(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def completed(self, name="run.h5", *sets):
        out = self.dir / name
        args = [a for s in ("time.end=80", *sets) for a in
                (("--set", s) if not s.startswith("--") else (s,))]
        r = smpm("run", BAR, "-o", out, "-q", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return out


class Results(Base):
    """Item 1: a rerun that fails, is killed or races another run leaves the result intact."""

    def test_failed_rerun_keeps_the_result(self):
        out = self.completed()
        before = digest(out), digest(out.with_suffix(".xmf"))
        r = smpm("run", BAR, "-o", out, "-q", "--set", "time.courant=1.5")  # unstable
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertEqual((digest(out), digest(out.with_suffix(".xmf"))), before)
        with h5py.File(self.dir / "run.partial.h5", "r") as f:
            self.assertIn("failed", f.attrs["status"])

    def test_killed_rerun_keeps_the_result(self):
        out = self.dir / "impact.h5"
        r = smpm("run", EXAMPLES / "block_impact.toml", "-o", out, "-q", "--set", "time.end=0.01")
        self.assertEqual(r.returncode, 0, r.stderr)
        before = digest(out)
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q"])
        partial = self.dir / "impact.partial.h5"
        deadline = time.time() + 120
        while time.time() < deadline and not partial.exists() and p.poll() is None:
            time.sleep(0.01)
        time.sleep(0.3)
        p.kill()
        p.wait()
        self.assertEqual(digest(out), before)

    def test_second_writer_refuses_at_once(self):
        out = self.dir / "impact.h5"
        args = ["run", EXAMPLES / "block_impact.toml", "-o", out, "-q", "--set", "time.end=0.05"]
        first = subprocess.Popen([SMPM, *map(str, args)], stderr=subprocess.PIPE, text=True)
        lock = self.dir / "impact.h5.lock"
        deadline = time.time() + 120
        while time.time() < deadline and not (self.dir / "impact.partial.h5").exists():
            time.sleep(0.01)
        second = smpm(*args)
        line = one_line(self, second, 2)
        self.assertIn("another run is writing this file", line)
        self.assertEqual(first.wait(timeout=600), 0, first.stderr.read())
        with h5py.File(out, "r") as f:  # the first run's result is whole
            self.assertEqual(f.attrs["status"], "completed")
        self.assertFalse(lock.exists())


class OutputNames(Base):
    """Item 2 (and 13): -o that would overwrite the input, a foreign file or a sidecar."""

    def test_refused_output_paths(self):
        src = self.dir / "bar.toml"
        src.write_text(BAR.read_text())
        foreign = self.dir / "data.h5"
        foreign.write_bytes(b"not a run")
        xmf_owner = self.dir / "other.h5"
        (self.dir / "other.xmf").write_text("<Xdmf>somebody else's</Xdmf>")
        for o, why in ((self.dir / "run.xmf", "sidecar"), (src, "input file"),
                       (foreign, "not a sparsempm run file"), (xmf_owner, "sidecar"),
                       (self.dir, "directory"), (src / "x.h5", "bar.toml is a file")):
            with self.subTest(o=o):
                line = one_line(self, smpm("run", src, "-o", o, "-q"), 2)
                self.assertIn(why, line)
        self.assertEqual(foreign.read_bytes(), b"not a run")
        self.assertEqual((self.dir / "other.xmf").read_text(), "<Xdmf>somebody else's</Xdmf>")
        self.assertEqual(src.read_text(), BAR.read_text())
        for cmd in ("stability", "spectrum"):
            with self.subTest(cmd=cmd):
                self.assertIn("input file", one_line(self, smpm(cmd, src, "-o", src), 2))
                self.assertIn("directory", one_line(self, smpm(cmd, src, "-o", self.dir), 2))
        self.assertEqual(src.read_text(), BAR.read_text())

    def test_partial_names(self):
        src = self.dir / "bar.toml"
        src.write_text(BAR.read_text())
        # No extension: the partial file and the sidecars could not be told apart.
        self.assertIn("no extension", one_line(self, smpm("run", src, "-o", self.dir / "run", "-q"), 2))
        # A partial name as -o: a second name for the file another run writes.
        self.assertIn("partial file", one_line(self, smpm("run", src, "-o", self.dir / "r.partial.h5", "-q"), 2))
        # A foreign file where the partial file would go, or the input there, is not overwritten.
        (self.dir / "x.partial.h5").write_bytes(b"precious")
        line = one_line(self, smpm("run", src, "-o", self.dir / "x.h5", "-q"), 2)
        self.assertIn("x.partial.h5 exists and is not a sparsempm run file", line)
        self.assertEqual((self.dir / "x.partial.h5").read_bytes(), b"precious")
        inp = self.dir / "case.partial.toml"
        inp.write_text(BAR.read_text())
        self.assertIn("input file", one_line(self, smpm("run", inp, "-o", self.dir / "case.toml", "-q"), 2))
        self.assertEqual(inp.read_text(), BAR.read_text())

    def test_table_write_failure_is_an_error(self):
        # A file size limit of 100 bytes (the table has about 250) makes the write fail
        # (EFBIG; SIGXFSZ ignored), as a full disk would.
        def limit():
            import resource
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (100, 100))
        r = smpm("spectrum", BAR, "--order", "1,2", "--blend-alpha", "1", "--blend-every", "1", "-o", self.dir / "t.csv",
                 preexec_fn=limit)
        self.assertIn("cannot write the table (File too large)", one_line(self, r, 1))
        self.assertFalse((self.dir / "t.csv").exists())
        self.assertFalse((self.dir / "t.csv.tmp").exists())


class Restart(Base):
    """Items 4, 5, 10: restart into -o, bit for bit for every update, and bad restart files."""

    def test_restart_honours_output(self):
        src = self.completed()
        before = digest(src)
        other = self.dir / "other.h5"
        r = smpm("run", "--restart", src, "-o", other, "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(digest(src), before)
        with h5py.File(other, "r") as f:
            self.assertEqual(f.attrs["status"], "completed")

    @staticmethod
    def cut(full, partial, keep):
        """The file a run killed after frame `keep` leaves: later frames and series rows gone."""
        import shutil
        shutil.copy(full, partial)
        with h5py.File(partial, "r+") as f:
            step = f["particles"]["%06d" % keep].attrs["step"]
            for group in ("particles", "grid"):
                for name in list(f[group]):
                    if int(name) > keep:
                        del f[group][name]
            rows = int(np.searchsorted(f["series"]["step"][:], step, side="right"))
            for name in f["series"]:
                d = f["series"][name]
                d.resize((rows,) + d.shape[1:])
            f.attrs["status"] = "running"

    def test_restart_is_bit_for_bit_for_every_update(self):
        variants = {
            "periodic": ["step.velocity=FMPM", "step.order=8", "step.periodic_cx=2", "time.courant=0.3"],
            "dynamic": ["step.velocity=FMPM", "step.order=20", "step.dynamic_metric=means", "step.dynamic_limit=1e-3"],
            "blend": ["step.velocity=FMPM", "step.order=8", "step.blend_alpha=0.8", "step.blend_every=2", "time.courant=0.3"],
            "xpic": ["step.velocity=XPIC", "step.order=4", "time.courant=0.3"],
            "exact": ["step.velocity=exact", "time.courant=0.1"],
        }
        # Heat transport: the temperatures and the thermal series continue too (FMPM(3) on c~,
        # the lumped FLIP update and the exact solve), with a held end and a source.
        heat = ["material.bar.heat_capacity=2.0", "material.bar.conductivity=40.0",
                "material.bar.reference_temperature=300.0", 'body.0.temperature="300 + X"',
                "body.0.heat_source=0.5", "time.fourier=0.5"]
        variants["heat FMPM"] = heat + ["step.transport=FMPM", "step.transport_order=3"]
        variants["heat lumped"] = heat + ["step.transport=lumped"]
        variants["heat exact"] = heat + ["step.transport=exact"]
        for name, sets in variants.items():
            with self.subTest(variant=name):
                full = self.completed(name + ".h5", *sets)
                partial = self.dir / (name + "_cut.partial.h5")
                self.cut(full, partial, 3)
                r = smpm("run", "--restart", partial, "-q")
                self.assertEqual(r.returncode, 0, r.stderr)
                with h5py.File(full, "r") as a, h5py.File(self.dir / (name + "_cut.h5"), "r") as b:
                    self.assertEqual(sorted(a["particles"]), sorted(b["particles"]))
                    for frame in a["particles"]:
                        fields = ("X", "V", "F", "stress") + (("temperature",) if "heat" in name else ())
                        for field in fields:
                            self.assertTrue(np.array_equal(a["particles"][frame][field][:], b["particles"][frame][field][:]),
                                            f"{frame}/{field}")
                    series = ("step", "t", "total") + (("heat", "entropy", "temperature_max") if "heat" in name else ())
                    for s in series:
                        self.assertTrue(np.array_equal(a["series"][s][:], b["series"][s][:]), s)

    def test_inconsistent_restart_file_is_refused(self):
        full = self.completed()
        bad = self.dir / "bad.partial.h5"
        self.cut(full, bad, 3)
        with h5py.File(bad, "r+") as f:
            v = f["particles"]["000003"]["V"][:]
            del f["particles"]["000003"]["V"]
            f["particles"]["000003"]["V"] = v[:-7]
        line = one_line(self, smpm("run", "--restart", bad, "-q"), 2)
        self.assertIn("frame 3", line)
        self.assertIn("V is 73 x 1, expected 80 x 1", line)


class Frames(Base):
    """Items 6 and 7: frames at multiples of output.every, bounded in number, linear cost."""

    def test_frame_interval_extremes(self):
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "a.h5", "--set", "output.every=1e-300"), 2)
        self.assertIn("output.every", line)
        self.assertIn("100000", line)
        for every in ("1e15", "1e13"):
            with self.subTest(every=every):
                out = self.dir / f"e{every}.h5"
                r = smpm("run", BAR, "-o", out, "-q", "--set", "output.every=" + every)
                self.assertEqual(r.returncode, 0, r.stderr)
                with h5py.File(out, "r") as f:
                    self.assertEqual(f["series"]["t"][-1], 400.0)  # reached time.end
                    self.assertEqual(len(f["particles"]), 2)  # t = 0 and the end

    @staticmethod
    def bytes_written(args):
        p = subprocess.Popen([SMPM, *map(str, args)], stdout=subprocess.DEVNULL)
        wchar = 0
        while p.poll() is None:
            try:
                wchar = int(open(f"/proc/{p.pid}/io").read().split("wchar:")[1].split()[0])
            except (OSError, IndexError, ValueError):
                pass
            time.sleep(0.005)
        return wchar

    def test_output_cost_grows_linearly_with_frames(self):
        # Bytes written by the run (wchar of /proc), not time: 40 times more frames may write at
        # most 80 times more (a sidecar rewritten whole at every frame writes ~800 times more).
        small = self.bytes_written(["run", BAR, "-o", self.dir / "s.h5", "-q", "--set", "output.every=10"])
        large = self.bytes_written(["run", BAR, "-o", self.dir / "l.h5", "-q", "--set", "output.every=0.25"])
        self.assertGreater(small, 0)
        self.assertLess(large, 80 * small, (small, large))


TINY = """
[grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [1.0, 1.0]
cells = [1500, 1500]
[[material]]
name = "m"
density = 1.0
youngs = 1.0
[[body]]
material = "m"
min = [700.0, 700.0]
max = [701.0, 701.0]
ppc = [2, 2]
velocity = ["0.1", "0"]
[time]
end = 1.0
[output]
every = 0.5
"""


class GridFields(Base):
    """Item 8: nodal fields are written for the nodes with mass only, with their indices, and
    memory follows the particles and the nodes they reach."""

    def test_small_body_on_a_large_grid(self):
        src = self.dir / "tiny.toml"
        src.write_text(TINY)
        out = self.dir / "tiny.h5"
        r = smpm("run", src, "-o", out, "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(out, "r") as f:
            for name, g in f["grid"].items():
                self.assertEqual(g.attrs["grid_nodes"], 1501 * 1501)
                n = len(g["nodes"])
                self.assertLessEqual(n, 16)  # 4 particles touch at most 16 nodes
                self.assertEqual(g["m"].shape, (n,))
                self.assertAlmostEqual(g["m"][:].sum(), 1.0, places=12)  # sum of particle masses
        # Three frames of ~10 nodes each: the file is the fixed cost of its datasets (measured
        # 209 kB with ten series columns), where grid-sized frames of 2.25 million nodes would
        # take over 100 MB.
        self.assertLess(out.stat().st_size, 400_000)
        # The particle cap counts the body's own lattice, not the grid's: 16 particles per cell
        # in this 1 x 1 box (1501^2 x 16 = 36 million would be over the 20 million cap).
        r = smpm("run", src, "-o", self.dir / "dense.h5", "-q", "--set", "body.0.ppc=[4, 4]")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_memory_follows_the_particles_not_the_grid(self):
        # The case: 4 particles on a grid of 19.4 million nodes (4400 x 4400 cells). The
        # steps, the frames and the input checks work on the window of nodes the particles reach
        # (NodeRange::Particles), so the peak resident memory is that of a small run: measured
        # 18 MB on this grid and on one of 2.25 million nodes, where a grid-sized step needed
        # 190 bytes per node (3.6 GB here); 40 MB leaves out even one int per grid node (78 MB).
        # Under the sanitizers their shadow memory decides the resident size, so only the run is
        # checked there.
        src = self.dir / "huge.toml"
        src.write_text(TINY.replace("cells = [1500, 1500]", "cells = [4400, 4400]"))
        out = self.dir / "huge.h5"
        probe = ("import resource, subprocess, sys\n"
                 "r = subprocess.run(sys.argv[1:], capture_output=True, text=True)\n"
                 "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
                 "sys.stderr.write(r.stderr)\n")
        r = subprocess.run([sys.executable, "-c", probe, SMPM, "run", str(src), "-o", str(out),
                            "-q"], capture_output=True, text=True, timeout=600)
        code, peak_kb = map(int, r.stdout.split())
        self.assertEqual(code, 0, r.stderr)
        if os.environ.get("SMPM_SANITIZED") != "1":
            self.assertLess(peak_kb, 40_000)  # 40 MB, against 3.6 GB for grid-sized storage
        with h5py.File(out, "r") as f:
            g = f["grid"]["000002"]
            self.assertEqual(g.attrs["grid_nodes"], 4401 * 4401)
            nodes = g["nodes"][:]
            # The 2 x 2 particles in cell (700, 700), moved 0.1 to the right: nodes of the grid's
            # numbering (i + 4401 j) around it.
            self.assertTrue(set(nodes) <= {i + 4401 * j for i in range(699, 704)
                                           for j in range(699, 703)})
            self.assertAlmostEqual(g["m"][:].sum(), 1.0, places=12)


class Signals(Base):
    """Item 14: SIGINT and SIGTERM mark the file interrupted and exit 130 / 143."""

    def test_signals(self):
        for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
            with self.subTest(sig=sig):
                out = self.dir / f"sig{code}.h5"
                p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q"],
                                     stderr=subprocess.PIPE, text=True)
                partial = self.dir / f"sig{code}.partial.xmf"
                deadline = time.time() + 120
                while time.time() < deadline and p.poll() is None:
                    if partial.exists() and partial.read_text().count("<Time ") >= 2:
                        break
                    time.sleep(0.01)
                p.send_signal(sig)
                self.assertEqual(p.wait(timeout=120), code)
                err = p.stderr.read().strip()
                self.assertEqual(len(err.splitlines()), 1, err)
                self.assertIn("interrupted", err)
                self.assertFalse(out.exists())
                with h5py.File(self.dir / f"sig{code}.partial.h5", "r") as f:
                    self.assertIn("interrupted", f.attrs["status"])
                    self.assertGreaterEqual(len(f["particles"]), 2)
                    self.assertGreater(len(f["series"]["t"]), 1)


class Streams(Base):
    """Item 15: a full or closed standard output is an error."""

    def test_full_stdout(self):
        out = self.completed()
        with open("/dev/full", "w") as full:
            r = subprocess.run([SMPM, "info", str(out)], stdout=full, stderr=subprocess.PIPE, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("standard output", r.stderr)


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


class Options(Base):
    """Item 12: options are validated, with caps, before any work starts."""

    def test_option_values(self):
        cases = (
            ("spectrum", "--blend-every", "0"), ("spectrum", "--order", "0"), ("spectrum", "--order", "-1"),
            ("spectrum", "--blend-alpha", "5"), ("spectrum", "--blend-alpha", "nan"), ("spectrum", "--courant", "-1"),
            ("stability", "--order", "1000000"), ("stability", "--shifts", "1000000000"),
            ("stability", "--frame-stride", "0"),
        )
        for cmd, opt, value in cases:
            with self.subTest(cmd=cmd, opt=opt, value=value):
                line = one_line(self, smpm(cmd, BAR, opt, value, "-o", self.dir / "t.csv", timeout=30), 2)
                self.assertIn(opt, line)
                self.assertIn(opt + " " + value, line)  # the value as given (nan was shown empty)
        self.assertFalse((self.dir / "t.csv").exists())

    def test_bad_output_found_before_the_work(self):
        r = smpm("stability", BAR, "-o", self.dir / "no" / "t.csv", timeout=30)
        line = one_line(self, r, 2)  # one line: no progress line of a computed row before it
        self.assertIn("does not exist", line)


class Sidecar(Base):
    """The XDMF sidecar is XML whatever the run file's name holds."""

    def test_name_with_markup(self):
        import xml.etree.ElementTree as ET
        out = self.dir / "a&b<c>'d\".h5"
        r = smpm("run", BAR, "-o", out, "-q", "--set", "time.end=20")
        self.assertEqual(r.returncode, 0, r.stderr)
        items = [d.text for d in ET.parse(self.dir / "a&b<c>'d\".xmf").iter("DataItem") if d.text]
        self.assertTrue(any(t.startswith("a&b<c>'d\".h5:/particles/000000/") for t in items), items[:3])


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


class DiskFull(Base):
    """Item 3: a full disk stops the run with a one-line error; completed frames stay readable."""

    def test_disk_full(self):
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs needs root")
        mnt = self.dir / "small"
        mnt.mkdir()
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=700k", "tmpfs", str(mnt)]).returncode:
            self.skipTest("cannot mount a tmpfs here")
        try:
            out = mnt / "disks.h5"
            r = smpm("run", EXAMPLES / "two_disks.toml", "-o", out, "-q", "--set", "output.every=0.05")
            self.assertEqual(r.returncode, 1, r.stderr)
            line = r.stderr.strip()
            self.assertEqual(len(line.splitlines()), 1, line)
            self.assertIn("disks.partial.h5", line)
            self.assertIn("step", line)
            info = smpm("info", mnt / "disks.partial.h5")  # lists the complete frames
            self.assertEqual(info.returncode, 0, info.stderr)
            def frames_in_index():
                # h5py through the index's links: (frames, complete ones, all X finite). The
                # frame files it opens close with the objects of this function.
                with h5py.File(mnt / "disks.partial.h5", "r") as f:
                    groups = [f["particles"].get(name) for name in f["particles"]]
                    whole = [g for g in groups if g is not None and "complete" in g.attrs]
                    return len(groups), len(whole), all(np.all(np.isfinite(g["X"][:])) for g in whole)
            # The run stops before a frame that might not fit (its size, an upper bound, and the
            # index written again after it): two of the 165 kB frame files fit in 700 kB.
            linked, whole, finite = frames_in_index()
            self.assertEqual(whole, linked)
            self.assertGreaterEqual(whole, 2)
            self.assertIn("frames:   %d" % whole, info.stdout)
            self.assertTrue(finite)
        finally:
            subprocess.run(["umount", str(mnt)])

    def test_disk_full_leaves_a_restart_point(self):
        # A frame that might not fit is not begun (its size is known): the partial file keeps the
        # frames before it and says "failed", and --restart on a disk with room continues from the
        # last complete frame to the uninterrupted run's result, bit for bit. Before, the frame
        # that filled the disk left links past the end of the file (HDF5 cannot delete them), the
        # status said "running" and --restart failed ("cannot create group 000001").
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs needs root")
        blocks = EXAMPLES / "two_block_compression.toml"
        sets = ["--set", "time.end=4.157"]
        whole = self.dir / "whole.h5"
        self.assertEqual(smpm("run", blocks, "-o", whole, "-q", *sets).returncode, 0)
        for size, frames in (("500k", 1), ("300k", 0)):
            mnt = self.dir / ("small" + size)
            mnt.mkdir()
            if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=" + size, "tmpfs", str(mnt)]).returncode:
                self.skipTest("cannot mount a tmpfs here")
            try:
                line = one_line(self, smpm("run", blocks, "-o", mnt / "x.h5", "-q", *sets), 1)
                self.assertIn("no room for the frame", line)
                if frames == 0:  # nothing to keep: no file that looks like a run
                    self.assertIn("no file is kept", line)
                    self.assertEqual(sorted(p.name for p in mnt.iterdir()), [])
                    continue
                kept = self.dir / "k.partial.h5"  # the index and its frame files
                kept.write_bytes((mnt / "x.partial.h5").read_bytes())
                shutil.copytree(mnt / "x.partial.frames", self.dir / "x.partial.frames")
            finally:
                subprocess.run(["umount", str(mnt)])
            with h5py.File(kept, "r") as f:
                self.assertTrue(f.attrs["status"].startswith("failed"), f.attrs["status"])
                self.assertEqual(sorted(f["particles"].keys()), ["000000"])
            r = smpm("run", "--restart", kept, "-o", self.dir / "r.h5", "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            with h5py.File(whole, "r") as a, h5py.File(self.dir / "r.h5", "r") as b:
                last = sorted(a["particles"].keys())[-1]
                self.assertEqual(sorted(b["particles"].keys()), sorted(a["particles"].keys()))
                for name in ("X", "V", "stress"):
                    self.assertTrue(np.array_equal(a["particles"][last][name][...], b["particles"][last][name][...]))

    def test_disk_full_before_the_first_frame(self):
        # 8 kB: room for the lock file, not for the run file's first flush. Before, the message
        # was "HDF5: flush" (no file named) and a frameless partial file was left.
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs needs root")
        mnt = self.dir / "tiny"
        mnt.mkdir()
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=8k", "tmpfs", str(mnt)]).returncode:
            self.skipTest("cannot mount a tmpfs here")
        try:
            r = smpm("run", BAR, "-o", mnt / "x.h5", "-q")
            line = one_line(self, r, 1)
            self.assertIn("x.partial.h5: cannot start the run file", line)
            self.assertIn("is the disk full?", line)
            self.assertEqual(sorted(p.name for p in mnt.iterdir()), [])
        finally:
            subprocess.run(["umount", str(mnt)])


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


class SecondLook(Base):
    """The same kind of probing on paths and files no item names: tables aimed at run files,
    lock-file names, links and damaged files where the partial file goes, a killed run's restart
    point, a restart file without a frame, and a condition that fails only at a later step."""

    def run_in_background(self, out, *sets):
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q", *sets],
                             stderr=subprocess.PIPE, text=True)
        partial = pathlib.Path(str(out).replace(".h5", ".partial.h5"))
        deadline = time.time() + 120
        while time.time() < deadline and not partial.exists() and p.poll() is None:
            time.sleep(0.01)
        return p

    def test_tables_never_replace_run_files(self):
        run = self.completed()
        xmf = run.with_suffix(".xmf")
        before = digest(run), digest(xmf)
        for cmd, extra in (("spectrum", ["--order", "1"]), ("stability", ["--order", "1", "--no-exact", "--shifts", "1", "--method", "spectral"])):
            for o, why in ((run, "run file"), (xmf, "run file or its sidecar")):
                with self.subTest(cmd=cmd, o=o.name):
                    self.assertIn(why, one_line(self, smpm(cmd, BAR, *extra, "-o", o), 2))
        # stability's --frames run file is an input of the table.
        line = one_line(self, smpm("stability", BAR, "--order", "1", "--no-exact", "--shifts", "1", "--method", "spectral",
                                   "--frames", run, "-o", run), 2)
        self.assertIn("not overwritten", line)
        self.assertEqual((digest(run), digest(xmf)), before)
        # A live run: neither its partial file nor its path takes a table, and the run completes
        # with its own result (before, the table was renamed over the partial file and the run
        # then moved the table to live.h5 and exited 0).
        live = self.dir / "live.h5"
        p = self.run_in_background(live, "--set", "time.end=0.2")  # about 1.5 s
        self.assertIn("partial file", one_line(self, smpm("spectrum", BAR, "--order", "1", "-o", self.dir / "live.partial.h5"), 2))
        self.assertIn("a run is writing this path", one_line(self, smpm("spectrum", BAR, "--order", "1", "-o", live), 2))
        _, err = p.communicate(timeout=600)
        self.assertEqual(p.returncode, 0, err)
        with h5py.File(live, "r") as f:
            self.assertEqual(f.attrs["status"], "completed")
        # A path under a file, named as such.
        self.assertIn("is a file", one_line(self, smpm("spectrum", BAR, "--order", "1", "-o", run / "t.csv"), 2))
        # A link at the table's temporary name is replaced, not written through; a FIFO as the
        # table is refused at once (it would block); a stale lock file does not block a table.
        (self.dir / "t.csv.tmp").symlink_to(run)
        r = smpm("spectrum", BAR, "--order", "1", "-o", self.dir / "t.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(digest(run), before[0])
        self.assertTrue((self.dir / "t.csv").read_text().startswith("order,"))
        os.mkfifo(self.dir / "f.csv")
        self.assertIn("not a regular file", one_line(self, smpm("spectrum", BAR, "--order", "1", "-o", self.dir / "f.csv", timeout=30), 2))
        (self.dir / "s.csv.lock").touch()
        self.assertEqual(smpm("spectrum", BAR, "--order", "1", "-o", self.dir / "s.csv").returncode, 0)

    def test_table_directory_is_checked_before_the_work(self):
        if os.geteuid() != 0:
            self.skipTest("mounting a read-only tmpfs needs root")
        mnt = self.dir / "ro"
        mnt.mkdir()
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k,ro", "tmpfs", str(mnt)]).returncode:
            self.skipTest("cannot mount a tmpfs here")
        try:
            # Before, the stability sweep ran (3 s) and then could not write its table (exit 1).
            r = smpm("stability", BAR, "--order", "1,2,4", "--method", "spectral", "-q", "-o", mnt / "t.csv")
            self.assertIn("cannot write in the directory", one_line(self, r, 2))
            self.assertIn("Read-only file system", r.stderr)
        finally:
            subprocess.run(["umount", str(mnt)])

    def test_lock_file_names(self):
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "a.h5.lock", "-q"), 2)
        self.assertIn("lock file", line)
        self.assertFalse((self.dir / "a.h5.lock").exists())
        # Somebody's file at a lock file's name is neither taken as a lock nor removed with it.
        mine = self.dir / "b.h5.lock"
        mine.write_bytes(b"precious")
        self.assertIn("not an empty lock file", one_line(self, smpm("run", BAR, "-o", self.dir / "b.h5", "-q"), 2))
        self.assertEqual(mine.read_bytes(), b"precious")
        self.assertFalse((self.dir / "b.partial.h5").exists())
        (self.dir / "c.h5.lock").symlink_to(mine)
        self.assertIn("is a link", one_line(self, smpm("run", BAR, "-o", self.dir / "c.h5", "-q"), 2))
        self.assertEqual(mine.read_bytes(), b"precious")
        # A stale lock of a killed run (empty, unlocked) is taken over and removed.
        (self.dir / "d.h5.lock").touch()
        self.completed("d.h5")
        self.assertFalse((self.dir / "d.h5.lock").exists())

    def test_links_at_the_partial_name_are_not_written_through(self):
        precious = self.completed("precious.h5")
        backup = self.dir / "backup.h5"
        os.link(precious, backup)
        before = digest(precious)
        (self.dir / "x.partial.h5").symlink_to(precious)
        os.link(precious, self.dir / "y.partial.h5")
        for out in ("x.h5", "y.h5"):
            with self.subTest(out=out):
                r = smpm("run", BAR, "-o", self.dir / out, "-q", "--set", "time.end=80", "--set", "time.courant=1.5")
                self.assertEqual(r.returncode, 3, r.stderr)  # unstable: fails after some frames
                self.assertEqual(digest(precious), before)
                self.assertEqual(digest(backup), before)
                with h5py.File(self.dir / out.replace(".h5", ".partial.h5"), "r") as f:
                    self.assertIn("failed", f.attrs["status"])
        self.assertTrue(precious.exists() and not (self.dir / "x.partial.h5").is_symlink())
        # A restart of the completed run into an output whose partial name is a link to it: the
        # link is replaced by the new run's index, the file it named (and its other names) stay
        # as they were.
        for make in (os.symlink, os.link):
            with self.subTest(link=make.__name__):
                (self.dir / "more.partial.h5").unlink(missing_ok=True)
                make(precious, self.dir / "more.partial.h5")
                r = smpm("run", "--restart", precious, "-o", self.dir / "more.h5", "-q")
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertFalse(precious.is_symlink())
                self.assertEqual(digest(precious), before)
                self.assertEqual(digest(backup), before)
                with h5py.File(self.dir / "more.h5", "r") as f:
                    self.assertEqual(f.attrs["status"], "completed")

    def test_a_rerun_keeps_a_killed_runs_restart_point(self):
        full = self.completed()
        for status in ("running", "interrupted: interrupted by SIGINT after step 99"):
            with self.subTest(status=status):
                partial = self.dir / "k.partial.h5"
                Restart.cut(full, partial, 3)
                with h5py.File(partial, "r+") as f:
                    f.attrs["status"] = status
                before = digest(partial)
                line = one_line(self, smpm("run", BAR, "-o", self.dir / "k.h5", "-q", "--set", "time.end=80"), 2)
                self.assertIn("--restart", line)
                self.assertEqual(digest(partial), before)
        # It is the restart point: continued in place, into k.h5.
        r = smpm("run", "--restart", self.dir / "k.partial.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "k.h5", "r") as f:
            self.assertEqual(f.attrs["status"], "completed")
        # A failed run's partial file (or one whose restart failed) is a restart point too: a
        # rerun replaces it only with --discard-partial.
        Restart.cut(full, self.dir / "f.partial.h5", 3)
        with h5py.File(self.dir / "f.partial.h5", "r+") as f:
            f.attrs["status"] = "failed: at step 5"
        before = digest(self.dir / "f.partial.h5")
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "f.h5", "-q"), 2)
        self.assertIn("holds 4 frames of a run that failed", line)
        self.assertIn("--discard-partial", line)
        self.assertEqual(digest(self.dir / "f.partial.h5"), before)
        self.completed("f.h5", "--discard-partial")

    def test_damaged_files_are_named_as_such(self):
        full = self.completed()
        damaged = self.dir / "damaged.h5"
        damaged.write_bytes(full.read_bytes()[:300_000])
        for args in (("info", damaged), ("run", "--restart", damaged, "-o", self.dir / "rr.h5", "-q")):
            with self.subTest(args=args[0]):
                line = one_line(self, smpm(*args), 2)
                self.assertIn("damaged", line)
                self.assertNotIn("another process", line)
        self.assertFalse((self.dir / "rr.partial.h5").exists())
        (self.dir / "z.partial.h5").write_bytes(damaged.read_bytes())
        line = one_line(self, smpm("run", BAR, "-o", self.dir / "z.h5", "-q"), 2)
        self.assertIn("z.partial.h5 exists and is a damaged HDF5 file", line)

    def test_restart_without_a_complete_frame_writes_nothing(self):
        full = self.completed()
        empty = self.dir / "e.partial.h5"
        Restart.cut(full, empty, 0)
        with h5py.File(empty, "r+") as f:
            del f["particles"]["000000"].attrs["complete"]
        before = digest(empty)
        line = one_line(self, smpm("run", "--restart", empty, "-o", self.dir / "e2.h5", "-q"), 2)
        self.assertIn(str(empty) + ": no complete frame to restart from", line)
        self.assertFalse((self.dir / "e2.partial.h5").exists())
        self.assertFalse((self.dir / "e2.h5").exists())
        one_line(self, smpm("run", "--restart", empty, "-q"), 2)  # in place: not rewritten
        self.assertEqual(digest(empty), before)

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


class StrictOptions(Base):
    """Every number of a stability option is all of its text, finite and within its cap; these
    were accepted (std::stod read "2abc" as 2, a NaN --position-alpha meant "not given")."""

    def test_malformed_and_out_of_range_values_are_refused(self):
        long_list = ",".join(["2:0.5"] * 1001)
        cases = {
            ("--blend", "20000:0.5"): "--blend 20000:0.5: m must lie in [1, 10000]",
            ("--blend", "2junk:0.8zzz"): "--blend 2junk:0.8zzz: expected m:alpha, e.g. 2:0.8",
            ("--blend", "2:0.8zzz"): "--blend 2:0.8zzz: expected m:alpha",
            ("--periodic", "2abc"): "--periodic-cx 2abc: expected a Courant budget C_X or none",
            ("--periodic-cx", "1e999"): "--periodic-cx 1e999: expected a Courant budget",
            ("--periodic-cx", "-2"): "--periodic-cx -2: must be non-negative (0: no rows)",
            ("--blend-alpha", "+-0.5"): "--blend-alpha +-0.5: expected a number",
            ("--blend-alpha", "0.5x"): "--blend-alpha 0.5x: expected a number in [0, 1] or none",
            ("--blend-alpha", "nan"): "--blend-alpha nan: expected a number",
            ("--position-alpha", "nan"): "--position-alpha nan: must lie in [0, 1]",
            ("--order", "20000"): "--order 20000: must lie in [1, 10000]",
            ("--blend-every", "20000"): "--blend-every 20000: must lie in [1, 10000]",
            ("--blend", long_list): "--blend: give 1 to 1000 values",
            ("--periodic-cx", ",".join(["2"] * 1001)): "--periodic-cx: give 1 to 1000 values",
        }
        out = self.dir / "t.csv"
        for (option, value), message in cases.items():
            r = smpm("stability", BAR, option, value, "-o", out, "-q")
            self.assertEqual(r.returncode, 2, (option, r.stderr))
            self.assertIn("smpm: error: " + message, r.stderr.splitlines()[-1], option)
            self.assertFalse(out.exists())

    def test_an_unknown_command_is_named(self):
        line = one_line(self, smpm("bogus"), 2)
        self.assertEqual(line, "smpm: error: unknown command 'bogus' (expected run, stability, "
                               "spectrum, transport-stability or info; smpm --help lists them)")


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

    def test_a_full_inode_table_is_named(self):
        # A file system with no free inode: creating the lock file fails with ENOSPC, which was
        # blamed on the directory ("is the directory writable?") and -o was "output.file".
        if os.geteuid() != 0:
            self.skipTest("mounting a tmpfs needs root")
        mnt = self.dir / "few_inodes"
        mnt.mkdir()
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=10m,nr_inodes=2", "tmpfs",
                           str(mnt)]).returncode:
            self.skipTest("cannot mount a tmpfs here")
        try:
            while True:  # use up the inodes left
                try:
                    (mnt / ("f%d" % len(list(mnt.iterdir())))).touch()
                except OSError:
                    break
            line = one_line(self, smpm("run", BAR, "-o", mnt / "x.h5", "-q"), 2)
            self.assertIn("x.h5.lock (No space left on device: the disk, its table of inodes or "
                          "the quota is full)", line)
            self.assertNotIn("output.file", line)
            self.assertNotIn("writable", line)
        finally:
            subprocess.run(["umount", str(mnt)])


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


def last_frame_name(path):
    with h5py.File(path, "r") as f:
        return sorted(f["particles"].keys())[-1]


class DamagedRestart(Base):
    """A restart file whose last frame or state is damaged is refused by its own name (exit 2,
    nothing written), before it is copied: a Mie-Gruneisen frame without `energy` restarted with
    U = 0, a NaN courant_budget turned periodic FMPM off for good, a NaN position failed some
    steps later as a numerical failure naming the output's copy."""

    def damaged(self, example, sets, damage, files=("done.h5", "done.nodes.xmf", "done.xmf")):
        done = self.dir / "done.h5"
        r = smpm("run", example, "-o", done, "-q", *[a for s in sets for a in ("--set", s)])
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(done, "r+") as f:
            last = sorted(f["particles"].keys())[-1]
            damage(f, last)
        r = smpm("run", "--restart", done, "-o", self.dir / "again.h5", "-q")
        line = one_line(self, r, 2)
        self.assertIn(str(done) + ": frame %d: " % int(last), line)
        self.assertEqual(sorted(p.name for p in self.dir.iterdir()), sorted(files))
        return line

    def test_a_mie_gruneisen_frame_without_energy(self):
        shock = EXAMPLES / "shock_split_bar.toml"
        sets = ["time.end=2e-4", "output.every=1e-4"]
        files = ("done.h5", "done.nodes.xmf", "done.xmf", "done.contact.xmf")  # bonded contact
        line = self.damaged(shock, sets, lambda f, last: f["particles"][last].__delitem__("energy"),
                            files)
        self.assertIn("energy is missing (the Mie-Gruneisen materials need it)", line)

        def nan_energy(f, last):
            f["particles"][last]["energy"][0] = np.nan
        line = self.damaged(shock, sets, nan_energy, files)
        self.assertIn("energy holds a value that is not finite", line)

    def test_a_missing_state_group(self):
        sets = ["time.end=8", "output.every=4"]
        line = self.damaged(BAR, sets, lambda f, last: f["state"].__delitem__(last))
        self.assertIn("/state/%s is missing" % last_frame_name(self.dir / "done.h5"), line)

    def test_non_finite_values_and_state(self):
        sets = ["time.end=8", "output.every=4", "step.velocity=FMPM", "step.order=2",
                "step.periodic_cx=2"]

        def nan_budget(f, last):
            f["state"][last].attrs["courant_budget"] = np.nan
        line = self.damaged(BAR, sets, nan_budget)
        self.assertIn("the state's courant_budget = nan (it must be finite and non-negative)", line)

        def nan_position(f, last):
            f["particles"][last]["X"][3, 0] = np.nan
        line = self.damaged(BAR, sets, nan_position)
        self.assertIn("X holds a value that is not finite", line)

        def negative_mass(f, last):
            f["particles"][last]["mass"][2] = -1.0
        line = self.damaged(BAR, sets, negative_mass)
        self.assertIn("mass holds -1 (it must be positive and finite)", line)


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


class ManyFrames(Base):
    """The run file is closed and opened again every 64 frames (emptying HDF5's metadata cache):
    a run of 200 frames completes with every frame, and a restart from a frame past a reopening
    continues bit for bit."""

    def test_two_hundred_frames(self):
        inp = self.dir / "four.toml"
        inp.write_text("[grid]\ndim = 1\norigin = [0.0]\ncell_size = [1.0]\ncells = [10]\n\n"
                       "[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs = 1.0\n\n[[body]]\n"
                       "material = \"m\"\nregion = \"box\"\nmin = [2.0]\nmax = [4.0]\nppc = [2]\n"
                       "velocity = [\"0.01*sin(X)\"]\n\n[time]\ncourant = 0.1\nend = 20.0\n\n"
                       "[step]\nshape = \"linear\"\n\n[output]\nevery = 0.1\n")
        out = self.dir / "four.h5"
        r = smpm("run", inp, "-o", out, "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(out, "r") as f:
            self.assertEqual(f.attrs["status"], "completed")
            self.assertEqual(len(f["particles"]), 201)
            X = f["particles"]["000200"]["X"][...]
            cut = self.dir / "cut.h5"
            with h5py.File(cut, "w") as g:  # the run as killed after frame 130
                for key, value in f.attrs.items():
                    g.attrs[key] = value
                g.attrs["status"] = "running"
                for group in ("particles", "grid", "state"):
                    g.create_group(group)
                    for name in sorted(f[group].keys())[:131]:
                        f.copy(f[group][name], g[group], name)
                n = int(f["particles"]["000130"].attrs["step"])
                g.create_group("series")
                for name, data in f["series"].items():
                    g["series"].create_dataset(name, data=data[:n + 1], maxshape=(None,) + data.shape[1:],
                                               chunks=True)
        r = smpm("run", "--restart", cut, "-o", self.dir / "again.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "again.h5", "r") as f:
            self.assertEqual(len(f["particles"]), 201)
            np.testing.assert_array_equal(f["particles"]["000200"]["X"][...], X)


class Version(Base):
    def test_the_version_names_the_commit(self):
        # `smpm --version` printed a bare number; now the release and the checkout's commit.
        git = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"],
                             cwd=SOURCE, capture_output=True, text=True)
        commit = git.stdout.strip() if git.returncode == 0 and git.stdout.strip() else "unknown"
        r = smpm("--version")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout.strip(), r"^smpm \d+\.\d+\.\d+ \(commit [0-9a-z-]+\)$")
        self.assertTrue(r.stdout.strip().endswith("(commit %s)" % commit), r.stdout)



class LiveRun(Base):
    """A run in progress can be read: `smpm info` of its partial file lists the frames completed
    so far (HDF5's file lock kept every reader out: "cannot be opened now")."""

    def test_info_of_a_live_run(self):
        out = self.dir / "live.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                              "--set", "time.end=100", "--set", "output.every=0.01"],
                             stderr=subprocess.PIPE, text=True)
        partial = self.dir / "live.partial.h5"
        try:
            seen = 0
            deadline = time.time() + 300
            while seen < 3 and time.time() < deadline and p.poll() is None:
                time.sleep(0.2)
                if not partial.exists():
                    continue
                info = smpm("info", partial)
                self.assertEqual(info.returncode, 0, info.stderr)
                found = [int(l.split()[1]) for l in info.stdout.splitlines()
                         if l.startswith("frames:")]
                seen = found[0] if found else 0
            self.assertIsNone(p.poll(), p.stderr.read() if p.poll() is not None else "")
            self.assertGreaterEqual(seen, 3)
        finally:
            p.kill()
            p.wait()
            p.stderr.close()


class Help(Base):
    def test_no_stable_courant_number_is_none(self):
        # A simulation search where no C holds (an energy-change limit no run meets) says "none"
        # in the table and the CSV (it left both empty, as for a row not searched).
        out = self.dir / "st.csv"
        r = smpm("stability", BAR, "--method", "simulation", "--order", "1", "--blend-alpha",
                 "none", "--periodic-cx", "none", "--no-exact", "--max-energy-change", "1e-15",
                 "-q", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = list(csv.DictReader(open(out)))
        self.assertEqual([row["c_simulation"] for row in rows], ["none", "none"])
        self.assertEqual([row["c_spectral"] for row in rows], ["", ""])  # not searched
        self.assertEqual(r.stdout.splitlines()[1].split()[-1], "none")

    def test_stability_help_shows_defaults(self):
        # --help printed "--no-exact{false}" and no default for --position-alpha and
        # --max-energy-change.
        r = smpm("stability", "--help")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("{false}", r.stdout)
        self.assertRegex(r.stdout, r"--no-exact +leave out the exact consistent-mass row")
        self.assertRegex(r.stdout, r"--shifts INT=4 ")
        self.assertIn("(default: the input's, else 1 for FLIP and 1/2 for the others)", r.stdout)
        self.assertIn("(default: no limit)", r.stdout)
        rows = []
        for extra in ([], ["--no-exact"]):
            out = self.dir / ("t%d.csv" % len(extra))
            r = smpm("stability", BAR, "--order", "1", "--method", "spectral", "--shifts", "1",
                     "-q", "-o", out, *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows.append([l.split(",")[0] for l in out.read_text().splitlines()[1:]])
        self.assertEqual(rows, [["FLIP", "FMPM", "exact"], ["FLIP", "FMPM"]])


if __name__ == "__main__":
    unittest.main(verbosity=2)
