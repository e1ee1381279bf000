#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Frames and the run file's layout: frames at multiples of output.every, bounded in number and
at a cost linear in their number; nodal fields for the nodes with mass only, and memory that
follows the particles, not the grid; two hundred frames across the run file's reopening every 64
frames (and a restart from past one); the contact layout's separations are never infinite.

Run by ctest (cli.frames) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment, and SMPM_SANITIZED=1 under the sanitizers (tests/CMakeLists.txt).
"""
import os
import subprocess
import sys
import time
import unittest

import h5py
import numpy as np

from example_runs import BAR, EXAMPLES, SMPM, Base, one_line, smpm


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


class Layout(Base):
    def test_contact_separation_is_never_infinite(self):
        # examples/rigid_impact.toml: where the rigid partner holds under 30% of a node's
        # volume the detection has no separation; the file held +inf (frame 7) where the layout
        # says -1 (none), and the sidecars passed inf to ParaView.
        r = smpm("run", EXAMPLES / "rigid_impact.toml", "-o", self.dir / "r.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "r.h5", "r") as f:
            seen = 0
            for name, g in f["grid"].items():
                if "contact_separation" in g:
                    s = g["contact_separation"][()]
                    self.assertTrue(np.all(np.isfinite(s)), name)
                    seen += int(np.sum(s == -1.0))
            self.assertGreater(seen, 0)  # the nodes without a separation are there, as -1


if __name__ == "__main__":
    unittest.main(verbosity=2)
