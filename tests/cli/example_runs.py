# SPDX-License-Identifier: BSD-3-Clause
"""What the example-driven CLI tests share: a full `smpm run` of an example with overrides."""
import os
import pathlib
import subprocess

SMPM = os.environ.get("SMPM", "smpm")


def fmpm(k):
    """The overrides of FMPM(k)."""
    return ["step.velocity=FMPM", f"step.order={k}"]


def one_thread_each():
    """The environment of runs started two at a time: one thread each unless SMPM_THREADS is
    set (the results are the same bit for bit; tests/cli/test_cli.py compares 1 and 2)."""
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
