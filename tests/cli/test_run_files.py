#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Run files in their two forms (README, "What survives"): the partial run, an index beside one
file per frame, and the assembled file of a completed run. A restart point is never lost to a
rerun or a failed restart, a restart never writes the file it continues, a damaged restart frame
is named as such, the sidecars are never read half written, and the contact layout holds no
infinity. Each test is named after the case it keeps.

Run by ctest with SMPM (the binary) and SMPM_SOURCE (the source tree) in the environment.
"""
import os
import pathlib
import shutil
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

import h5py
import numpy as np

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE / "examples"
HEAT = [EXAMPLES / "conduction_bar.toml", "--set", "grid.cells=[12]", "--set",
        "grid.cell_size=[0.1]", "--set", "grid.origin=[-0.1]", "--set", "time.end=0.2", "--set",
        "output.every=0.004"]


def smpm(*args, timeout=300):
    return subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, timeout=timeout)


def digests(directory):
    """Every file under `directory` with its bytes (but lock files, which a killed run leaves
    empty and the next run takes over)."""
    return {str(p.relative_to(directory)): p.read_bytes()
            for p in sorted(directory.rglob("*")) if p.is_file() and p.suffix != ".lock"}


class Base(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def killed(self, name="k", after_frames=20):
        """A heat run killed with SIGKILL once `after_frames` frame files exist: its partial."""
        p = subprocess.Popen([SMPM, "run", *HEAT, "-o", self.dir / (name + ".h5"), "-q"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        frames = self.dir / (name + ".partial.frames")
        while p.poll() is None:
            if frames.is_dir() and len([f for f in os.listdir(frames) if len(f) == 9
                                        and f.endswith(".h5")]) >= after_frames:
                break
            time.sleep(0.001)
        p.kill()
        p.wait()
        self.assertEqual(p.returncode, -9, "the run ended before it was killed")
        return self.dir / (name + ".partial.h5")


class RestartPoints(Base):
    def test_a_failed_restart_keeps_the_restart_point(self):
        # The sequence that lost 92 frames: a killed run's partial file, a restart of it that
        # fails (here the frame it continues is past the end time of its stored input, made so
        # by damaging the index's overrides), then a plain rerun. The restart point must survive
        # both: the rerun is refused, and --discard-partial is the one way to replace it.
        partial = self.killed()
        info = smpm("info", partial)
        self.assertEqual(info.returncode, 0, info.stderr)
        frames = int([l for l in info.stdout.splitlines() if l.startswith("frames:")][0].split()[1])
        self.assertGreaterEqual(frames, 20)
        r = smpm("run", "--restart", partial, "-o", self.dir / "k.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)  # it continues, into k.h5
        partial = self.killed("j")
        with h5py.File(partial, "r+") as f:  # the restart will fail: its frames are past the end
            f.attrs["overrides"] = [o.replace("time.end=0.2", "time.end=0.01")
                                    for o in f.attrs["overrides"]]
        before = digests(self.dir)
        r = smpm("run", "--restart", partial, "-o", self.dir / "j.h5", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("is past the run's end", r.stderr)
        self.assertEqual(digests(self.dir), before)  # refused before anything was written
        r = smpm("run", *HEAT, "-o", self.dir / "j.h5", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("continue it with --restart", r.stderr)
        self.assertEqual(digests(self.dir), before)
        r = smpm("run", *HEAT, "-o", self.dir / "j.h5", "-q", "--discard-partial")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse((self.dir / "j.partial.frames").exists())

    def test_a_damaged_newest_frame_restarts_from_the_frame_before(self):
        # A frame file cut short (the disk's fault, not a kill: a kill leaves no named frame
        # half written) is passed over: the restart continues from the frame before, keeps
        # every series row up to it, and ends with the uninterrupted run's file. (A restart
        # that read the damaged frame's rows failed and its writer's destructor then wrote an
        # index with no series.)
        r = smpm("run", *HEAT, "-o", self.dir / "ref.h5", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        partial = self.killed()
        frames = sorted((self.dir / "k.partial.frames").glob("[0-9]*.h5"))
        frames[-1].write_bytes(frames[-1].read_bytes()[:1000])
        # smpm info lists the objects of the frame before (it stopped on the damaged one).
        info = smpm("info", partial)
        self.assertEqual(info.returncode, 0, info.stderr)
        self.assertIn("/particles/" + frames[-2].stem + "/X ", info.stdout)
        r = smpm("run", "--restart", partial, "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "ref.h5", "r") as a, h5py.File(self.dir / "k.h5", "r") as b:
            self.assertEqual(sorted(a["particles"]), sorted(b["particles"]))
            for name in ("step", "t", "heat", "temperature_max"):
                self.assertTrue(np.array_equal(a["series"][name][()], b["series"][name][()]), name)
            last = sorted(a["particles"])[-1]
            self.assertTrue(np.array_equal(a["particles"][last]["temperature"][()],
                                           b["particles"][last]["temperature"][()]))

    def test_a_restart_frame_past_the_end_is_a_damaged_file(self):
        # A restart file whose last frame claims t = 1e9, beyond time.end: exit 2 naming the
        # file and frame as damaged (it was exit 1).
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", self.dir / "done.h5", "-q",
                 "--set", "time.end=8", "--set", "output.every=4")
        self.assertEqual(r.returncode, 0, r.stderr)
        with h5py.File(self.dir / "done.h5", "r+") as f:
            f["particles"]["000002"].attrs["time"] = 1e9
        r = smpm("run", "--restart", self.dir / "done.h5", "-o", self.dir / "again.h5", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("done.h5: frame 2: its time t = 1e+09 is past the run's end time.end = 8 "
                      "(a damaged file)", r.stderr)
        self.assertFalse((self.dir / "again.partial.h5").exists())

    def test_a_restart_never_writes_the_file_it_continues(self):
        # `--restart run.h5 -o run.h5` of a completed run exited 0 and rewrote run.h5.
        run = self.dir / "run.h5"
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", run, "-q", "--set", "time.end=8")
        self.assertEqual(r.returncode, 0, r.stderr)
        before = digests(self.dir)
        for args in (["-o", run], []):  # without -o the output is the restart file's name
            with self.subTest(args=args):
                r = smpm("run", "--restart", run, *args, "-q")
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn("is the run file the restart continues, which a restart never "
                              "writes", r.stderr)
                self.assertEqual(digests(self.dir), before)


class Options(Base):
    def test_an_empty_output_name_is_refused(self):
        # -o '' was taken as "no -o": the run wrote the input's output.file without a word.
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", "", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(r.stderr.strip().splitlines(),
                         ["smpm: error: -o '': an empty path; name the output file (or leave -o "
                          "out for the input's output.file)"])


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


class LiveReaders(Base):
    def test_sidecars_are_never_read_half_written(self):
        # A reader parsing run.partial.xmf during the run got torn XML in 2-13 of ~100 reads:
        # the sidecars are now written under a temporary name and renamed.
        out = self.dir / "live.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                              "--set", "time.end=100", "--set", "output.every=0.01"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        xmf = self.dir / "live.partial.xmf"
        reads, grids = 0, []
        try:
            deadline = time.time() + 120
            while reads < 150 and time.time() < deadline and p.poll() is None:
                if xmf.exists():
                    text = xmf.read_text()
                    root = ET.fromstring(text)  # raises on torn XML
                    grids.append(len(root.findall(".//Grid[@GridType='Uniform']")))
                    reads += 1
                time.sleep(0.005)
            self.assertIsNone(p.poll(), "the run ended before the reads")
        finally:
            p.kill()
            p.wait()
        self.assertEqual(reads, 150)
        self.assertGreater(grids[-1], grids[0])  # it was read while frames were added


if __name__ == "__main__":
    unittest.main(verbosity=2)
