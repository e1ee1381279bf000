#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Restart (`smpm run --restart`): a killed run's partial file continues to the uninterrupted
run's file bit for bit, for every velocity and transport update and into another file (-o); a
restart point (a killed, interrupted or failed run, or one a full disk stopped) is never lost to
a rerun or a failed restart; a restart never writes the file it continues; restart files whose
frames or state are damaged or inconsistent are refused by name before anything is written.

Restarts checked as one part of another concept stay with it: a stalled run restarts to the same
failure (test_failures.py), a restart past the run file's reopening (test_frames.py), an image
body's restart (test_input_limits.py), the shock's internal energy (test_shock.py) and the kill
campaign (test_kills.py).

Run by ctest (cli.restart) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment, and SMPM_SANITIZED=1 under the sanitizers (tests/CMakeLists.txt).
"""
import os
import shutil
import signal
import subprocess
import time
import unittest

import h5py
import numpy as np

from example_runs import BAR, EXAMPLES, SANITIZED, SMPM, Base, digest, one_line, smpm


HEAT = [EXAMPLES / "conduction_bar.toml", "--set", "grid.cells=[12]", "--set",
        "grid.cell_size=[0.1]", "--set", "grid.origin=[-0.1]", "--set", "time.end=0.2", "--set",
        "output.every=0.004"]


def digests(directory):
    """Every file under `directory` with its bytes (but lock files, which a killed run leaves
    empty and the next run takes over)."""
    return {str(p.relative_to(directory)): p.read_bytes()
            for p in sorted(directory.rglob("*")) if p.is_file() and p.suffix != ".lock"}


def last_frame_name(path):
    with h5py.File(path, "r") as f:
        return sorted(f["particles"].keys())[-1]


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


class KilledRun(Base):
    """A run killed with SIGKILL keeps its completed frames, and --restart completes it to the
    uninterrupted run's file bit for bit."""

    def test_killed_run_keeps_frames_and_restart_is_bit_for_bit(self):
        # To t = 0.1 under the sanitizers (ten frames, the kill after four; 126 s under ASan to
        # t = 0.3): what they check is the memory of the kill and restart, not the run's length.
        end = "0.1" if SANITIZED else "0.3"
        args = ["--set", "time.end=" + end, "--set", "output.every=0.01"]
        full = self.dir / "full.h5"
        r = smpm("run", EXAMPLES / "block_impact.toml", "-o", full, "-q", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        # Same run, killed (SIGKILL) once a few frames are on disk: its partial file remains.
        cut = self.dir / "cut.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", cut, "-q", *args])
        xmf = self.dir / "cut.partial.xmf"
        deadline = time.time() + 300
        while time.time() < deadline and p.poll() is None:
            if xmf.exists() and xmf.read_text().count("<Time ") >= 4:
                break
            time.sleep(0.02)
        if p.poll() is not None:
            self.skipTest("the run finished before it could be killed")
        p.send_signal(signal.SIGKILL)
        p.wait()
        self.assertFalse(cut.exists())
        with h5py.File(self.dir / "cut.partial.h5", "r") as f:  # opens, with every completed frame
            frames = [k for k, g in f["particles"].items() if "complete" in g.attrs]
            self.assertGreaterEqual(len(frames), 4)
            self.assertEqual(f.attrs["status"], "running")
        r = smpm("run", "--restart", self.dir / "cut.partial.h5", "-q")  # completes into cut.h5
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse((self.dir / "cut.partial.h5").exists())
        with h5py.File(full, "r") as a, h5py.File(cut, "r") as b:
            self.assertEqual(sorted(a["particles"]), sorted(b["particles"]))
            for name in a["particles"]:
                for field in ("X", "V", "F", "stress"):
                    self.assertTrue(np.array_equal(a["particles"][name][field][:], b["particles"][name][field][:]), f"{name}/{field}")
            for s in ("step", "t", "kinetic", "strain", "total", "momentum"):
                self.assertTrue(np.array_equal(a["series"][s][:], b["series"][s][:]), s)
            self.assertEqual(b.attrs["status"], "completed")


class RestartPoints(Base):
    """A killed, interrupted or failed run's partial file is a restart point: a rerun replaces it
    only with --discard-partial, a failed restart leaves it as it was, a full disk leaves one."""

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


if __name__ == "__main__":
    unittest.main(verbosity=2)
