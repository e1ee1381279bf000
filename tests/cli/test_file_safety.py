#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Run-file safety (docs/guide/file-safety.md): a result is never destroyed by a rerun that fails,
is killed, races another run or points at the wrong path; the names beside the output (the
partial file, sidecars, lock files, links and damaged files there) are checked before any work
and never written through; tables never replace run files; a signal, a full or read-only disk,
a full table of inodes or a closed standard output end the run with one line and a non-zero
status. Restarts and restart points are tests/cli/test_restart.py's.

Run by ctest (cli.file_safety) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import os
import pathlib
import signal
import subprocess
import time
import unittest

import h5py
import numpy as np

from example_runs import BAR, EXAMPLES, SMPM, Base, digest, one_line, smpm


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

    def test_an_empty_output_name_is_refused(self):
        # -o '' was taken as "no -o": the run wrote the input's output.file without a word.
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", "", "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(r.stderr.strip().splitlines(),
                         ["smpm: error: -o '': an empty path; name the output file (or leave -o "
                          "out for the input's output.file)"])


class Tables(Base):
    """Tables (smpm stability and spectrum) never take a run file's, its sidecar's or a live
    run's name; their directory is checked before the work, and a write that fails is an error
    that leaves no file."""

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


class LocksAndLinks(Base):
    """Lock-file names, links and damaged files where the output's partial file goes: refused or
    replaced, never taken as a lock, written through or overwritten."""

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


class DiskFull(Base):
    """Item 3: a full disk (or table of inodes) stops the run with a one-line error; completed
    frames stay readable."""

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


if __name__ == "__main__":
    unittest.main(verbosity=2)
