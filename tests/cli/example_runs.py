# SPDX-License-Identifier: BSD-3-Clause
"""What the CLI tests share: the binary and the examples, a run of `smpm` and its one-line error,
the reader of its tables, a test in a directory of its own, and a full `smpm run` of an example
with overrides.

ctest runs each test file with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment, and with SMPM_SANITIZED=1 under the sanitizers, where the runs that only check a
number are left out (tests/CMakeLists.txt).
"""
import hashlib
import importlib.util
import os
import pathlib
import subprocess
import tempfile
import unittest

SMPM = os.environ.get("SMPM", "smpm")
SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE / "examples"
BAR = EXAMPLES / "vibrating_bar.toml"
SANITIZED = os.environ.get("SMPM_SANITIZED") == "1"


def _tables():
    """python/sparsempm/tables.py of the source tree, loaded by its path (it needs only the
    standard library; these tests do not import the extension)."""
    spec = importlib.util.spec_from_file_location(
        "_sparsempm_tables", SOURCE / "python" / "sparsempm" / "tables.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# The rows of a table of `smpm stability`, `transport-stability` or `spectrum` keyed by the
# current column names (also from a table of the earlier ones): sparsempm.read_table.
read_table = _tables().read_table


def smpm(*args, timeout=600, **kw):
    """`smpm` with these arguments, its output captured as text."""
    return subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, timeout=timeout, **kw)


def digest(path):
    """The SHA-256 of a file's bytes."""
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def one_line(test, r, code):
    """Asserts that the run `r` exited with `code` and wrote one line to standard error; returns
    that line."""
    test.assertEqual(r.returncode, code, r.stderr)
    test.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
    return r.stderr.strip()


class Base(unittest.TestCase):
    """A test in a temporary directory of its own (self.dir), removed after it."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def completed(self, name="run.h5", *sets):
        """A completed run of the vibrating bar to t = 80 in self.dir / name."""
        out = self.dir / name
        args = [a for s in ("time.end=80", *sets) for a in
                (("--set", s) if not s.startswith("--") else (s,))]
        r = smpm("run", BAR, "-o", out, "-q", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        return out


def fmpm(k):
    """The overrides of FMPM(k)."""
    return ["step.velocity=FMPM", f"step.order={k}"]


def one_thread_each():
    """The environment of runs started two at a time: one thread each unless SMPM_THREADS is
    set (the results are the same bit for bit; tests/cli/test_commands.py compares 1 and 2)."""
    env = dict(os.environ)
    env.setdefault("SMPM_THREADS", "1")
    return env


def run_example(example, work, name, sets):
    """Runs `example` with `--set` overrides into <work>/<name>.h5 (asserting exit 0) and
    returns that path."""
    out = pathlib.Path(work) / (name + ".h5")
    args = [SMPM, "run", str(example), "-o", str(out), "-q"]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True, timeout=600, env=one_thread_each())
    assert r.returncode == 0, r.stderr
    return out


def check_refused(test, example, sets, words):
    """Asserts that `smpm run example` with these overrides exits 2 with one line of error
    holding every one of `words`, and writes no output file."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "x.h5"
        args = [SMPM, "run", str(example), "-o", str(out), "-q"]
        for s in sets:
            args += ["--set", s]
        r = subprocess.run(args, capture_output=True, text=True, timeout=60)
        test.assertEqual(r.returncode, 2, r.stderr)
        lines = r.stderr.strip().splitlines()
        test.assertEqual(len(lines), 1, r.stderr)
        for w in words:
            test.assertIn(w, lines[0])
        test.assertFalse(out.exists())
