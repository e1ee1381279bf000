#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The sidecars of a 1D, a 2D multimaterial (with contact nodes) and a 3D run, and of a run in
progress, open in ParaView's three XDMF readers and meshio with the run file's arrays, shapes
and times (check_readers.py)."""

import os
import pathlib
import signal
import subprocess
import sys
import tempfile
import time
import unittest

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import check_readers  # noqa: E402

SMPM = os.environ["SMPM"]
EXAMPLES = pathlib.Path(os.environ["SMPM_SOURCE"]) / "examples"


def run(*args):
    r = subprocess.run([SMPM, "run", *map(str, args), "-q"], capture_output=True, text=True)
    if r.returncode:
        raise AssertionError(r.stderr)


class Readers(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def test_completed_runs(self):
        runs = [(EXAMPLES / "vibrating_bar.toml", "bar.h5", []),
                (EXAMPLES / "two_block_compression.toml", "blocks.h5",
                 ["--set", "time.end=0.002", "--set", "output.every=0.0005"]),
                (HERE / "inputs" / "block3d.toml", "block3d.h5", [])]
        for toml, name, extra in runs:
            run(toml, "-o", self.dir / name, *extra)
        self.assertTrue((self.dir / "blocks.contact.xmf").exists())
        self.assertFalse((self.dir / "bar.contact.xmf").exists())  # one velocity field
        check_readers.main([self.dir / name for _, name, _ in runs])

    def test_live_run(self):
        # A run still writing: its partial file's sidecars, read without HDF5's file lock
        # (HDF5_USE_FILE_LOCKING=FALSE, as docs/guide/run-files.md says for h5py and ParaView).
        out = self.dir / "live.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                              "--set", "time.end=100", "--set", "output.every=0.01"],
                             stderr=subprocess.PIPE, text=True)
        partial = self.dir / "live.partial.h5"
        try:
            xmf = self.dir / "live.partial.xmf"
            deadline = time.time() + 300
            while time.time() < deadline and p.poll() is None:
                if xmf.exists() and xmf.read_text().count("<Time ") >= 3:
                    break
                time.sleep(0.2)
            self.assertIsNone(p.poll(), p.stderr.read() if p.poll() is not None else "")
            # A reader that opens the file while the run flushes a frame can see a torn state
            # (HDF5 has no readers-while-writing without SWMR, which cannot create groups): a
            # fresh reader process tries again, up to five times, as a user reloads. The run is
            # paused (SIGSTOP) while each reader looks and resumed between attempts, so that it
            # is still running at the end however fast the machine (running on, the blocks leave
            # the grid within seconds on a quiet machine: exit 3 before the readers finished).
            errors = []
            for _ in range(5):
                if errors:
                    p.send_signal(signal.SIGCONT)
                    time.sleep(0.3)
                p.send_signal(signal.SIGSTOP)
                r = subprocess.run([sys.executable, HERE / "check_readers.py", "--live", partial],
                                   capture_output=True, text=True)
                if r.returncode == 0:
                    break
                errors.append(r.stderr[-2000:])
            self.assertEqual(r.returncode, 0, "\n".join(errors))
            print(r.stdout, end="")
            if errors:
                print(f"({len(errors)} reader attempts saw a frame being written)")
            self.assertIsNone(p.poll())  # still running
        finally:
            p.kill()
            p.wait()
            p.stderr.close()


if __name__ == "__main__":
    unittest.main(verbosity=2)
