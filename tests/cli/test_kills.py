#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Nothing lost, whatever the moment of the kill (docs/guide/file-safety.md): runs with heat,
plasticity, contact and many small frames are killed with SIGKILL at random instants, uniform
over the run and concentrated on the writing of frame files, of the index, of the assembled
file and on restarts; every file left must list its completed frames and restart from the
last of them into a file equal to the uninterrupted run's, dataset by dataset, bit for bit
(and so must what a killed restart into another file left).
The count of unrecoverable files is asserted to be 0.

The random seed is printed; SMPM_KILL_SEED=<seed> replays a campaign, SMPM_KILLS=<n> sets its
size (default 520). Run by ctest (label "long", Release builds only) with SMPM and SMPM_SOURCE
in the environment.
"""
import concurrent.futures
import os
import pathlib
import random
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
KILLS = int(os.environ.get("SMPM_KILLS", "520"))
SEED = int(os.environ.get("SMPM_KILL_SEED", str(int(time.time() * 1000) % 1_000_000)))

# The problems: heat by FMPM(4) transport on the conduction bar at 12 cells with a frame every
# 0.004; the split nickel bar with J2 plasticity (Mie-Gruneisen, artificial viscosity); two
# blocks in contact (FMPM(2) with contact inside the loop). Each writes 20-25 small frames.
PROBLEMS = {
    "heat": (EXAMPLES / "conduction_bar.toml",
             ["grid.cells=[12]", "grid.cell_size=[0.1]", "grid.origin=[-0.1]", "time.end=0.1",
              "output.every=0.004"]),
    "plastic": (EXAMPLES / "shock_split_bar.toml",
                ["material.left.shear=85500.0", "material.right.shear=85500.0",
                 "material.left.yield_stress=140.0", "material.right.yield_stress=140.0",
                 "time.end=0.0001", "output.every=0.000005"]),
    "contact": (EXAMPLES / "two_block_compression.toml",
                ["time.end=0.0012", "output.every=0.00005", "step.velocity=FMPM", "step.order=2"]),
}


def smpm(*args, timeout=300):
    return subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, timeout=timeout)


def run_args(problem, out):
    example, sets = PROBLEMS[problem]
    return ["run", example, "-o", out, "-q", *[a for s in sets for a in ("--set", s)]]


def datasets(path):
    """Every dataset and attribute of a run file, by path."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
            for key, value in obj.attrs.items():
                out[name + "@" + key] = value
        f.visititems(visit)
        for key, value in f.attrs.items():
            out["@" + key] = value
    return out


def equal(a, b):
    """Bit for bit: the same keys, shapes and bytes (NaN equal to NaN)."""
    if a.keys() != b.keys():
        return "objects differ: %s" % sorted(set(a) ^ set(b))[:5]
    for k in a:
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if x.dtype == object:  # strings: their values (the bytes would be their addresses)
            same = x.shape == y.shape and y.dtype == object and x.tolist() == y.tolist()
        else:
            same = x.shape == y.shape and x.dtype == y.dtype and x.tobytes() == y.tobytes()
        if not same:
            return "%s differs" % k
    return None


def start(args):
    return subprocess.Popen([SMPM, *map(str, args)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)


def kill_at(p, seconds):
    """SIGKILL `p` after `seconds` (unless it ended); whether the kill ended it."""
    try:
        p.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        p.send_signal(signal.SIGKILL)
        p.wait()
    return p.returncode == -signal.SIGKILL


def kill_on(p, frames, suffix, rng, delay=0.002):
    """SIGKILL `p` once a file ending in `suffix` appears in `frames` (a temporary: a frame file,
    the index; the last frame file, before the assembly), after a random delay up to `delay`."""
    while p.poll() is None:
        try:
            names = os.listdir(frames)
        except OSError:
            names = []
        if any(n.endswith(suffix) for n in names):
            time.sleep(rng.uniform(0, delay))
            break
        time.sleep(0.0002)
    if p.poll() is None:
        p.send_signal(signal.SIGKILL)
    p.wait()
    return p.returncode == -signal.SIGKILL


def recover(out, reference):
    """What a kill left at `out`, and None when it restarts (or had completed) into a file equal
    to the uninterrupted run's, else why not."""
    partial = out.with_name(out.stem + ".partial.h5")
    if out.exists() and not partial.exists():
        return "completed", equal(datasets(out), reference)
    if not partial.exists():
        return "not begun", None  # killed before the run file was begun: nothing completed
    info = smpm("info", partial)
    if info.returncode != 0:
        return "partial", "info: " + info.stderr.strip()
    frames = [int(l.split()[1]) for l in info.stdout.splitlines() if l.startswith("frames:")][0]
    if frames == 0:
        return "no frame", None  # killed before the first frame was complete
    r = smpm("run", "--restart", partial, "-q")
    if r.returncode != 0:
        return "partial", "restart: " + r.stderr.strip()
    return "partial", equal(datasets(out), reference)


class Campaign(unittest.TestCase):
    def test_no_kill_loses_a_run(self):
        print("kill campaign: seed %d (SMPM_KILL_SEED=%d replays it), %d kills"
              % (SEED, SEED, KILLS), flush=True)
        tmp = tempfile.TemporaryDirectory()
        base = pathlib.Path(tmp.name)
        references, durations, last_frame = {}, {}, {}
        for name in PROBLEMS:
            out = base / ("ref_" + name + ".h5")
            t0 = time.time()
            r = smpm(*run_args(name, out))
            durations[name] = time.time() - t0
            self.assertEqual(r.returncode, 0, r.stderr)
            references[name] = datasets(out)
            with h5py.File(out, "r") as f:
                last_frame[name] = max(int(k) for k in f["particles"])
        modes = ["uniform", "uniform", "frame", "index", "assembly", "restart"]
        cases = [(k, random.Random(SEED * 7919 + k)) for k in range(KILLS)]

        def one(case):
            k, rng = case
            name = sorted(PROBLEMS)[k % len(PROBLEMS)]
            mode = modes[(k // len(PROBLEMS)) % len(modes)]
            work = base / ("k%04d" % k)
            work.mkdir()
            out = work / "k.h5"
            frames = work / "k.partial.frames"
            t0 = time.time()
            p = start(run_args(name, out))
            if mode in ("uniform", "restart"):
                # Uniform over the run, from the moment its files begin (the program's start-up
                # writes nothing) to a little past its end.
                while not frames.exists() and p.poll() is None and time.time() - t0 < 60:
                    time.sleep(0.0005)
                killed = kill_at(p, rng.uniform(0, 1.1 * durations[name] - (time.time() - t0)))
            elif mode == "assembly":  # from the last frame on: the assembly, the removal
                killed = kill_on(p, frames, "%06d.h5" % last_frame[name], rng, 0.02)
            else:
                # Frame files and the index are written many times: the kill falls on a
                # random one of them.
                time.sleep(rng.uniform(0, 0.8 * durations[name]))
                killed = kill_on(p, frames, {"frame": "0.h5.tmp", "index": "index.h5.tmp"}[mode],
                                 rng)
            elsewhere = None
            if mode == "restart" and (work / "k.partial.h5").exists():
                # The restart killed too, early (while it copies or indexes) or later; in place
                # or into another file (its copy of the frames made under another name).
                more = []
                if rng.random() < 0.5:
                    elsewhere = work / "r.h5"
                    more = ["-o", elsewhere]
                q = start(["run", "--restart", work / "k.partial.h5", "-q", *more])
                kill_at(q, rng.choice([rng.uniform(0, 0.05), rng.uniform(0, durations[name])]))
            left, why = recover(out, references[name])
            other = None
            if elsewhere and not why:  # what the killed restart left restarts too
                other, why = recover(elsewhere, references[name])
            shutil.rmtree(work, ignore_errors=True)
            return k, name, mode, ("killed, " if killed else "ended, ") + left, other, why

        failures, counts, outcomes, elsewhere = [], {}, {}, {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
            for k, name, mode, outcome, other, why in pool.map(one, cases):
                counts[(name, mode)] = counts.get((name, mode), 0) + 1
                outcomes[outcome] = outcomes.get(outcome, 0) + 1
                if other:
                    elsewhere[other] = elsewhere.get(other, 0) + 1
                if why:
                    failures.append((k, name, mode, why))
                    print("case %d (%s, %s): %s" % (k, name, mode, why), flush=True)
        print("kills by problem and mode:", dict(sorted(counts.items())))
        print("what the kills left:", dict(sorted(outcomes.items())))
        print("what killed restarts into another file left:", dict(sorted(elsewhere.items())))
        print("unrecoverable: %d of %d" % (len(failures), len(cases)))
        tmp.cleanup()
        self.assertEqual(failures, [], "seed %d" % SEED)
        # The campaign kills live runs: most kills end a run that had completed frames (a kill
        # that came after the run's end, or before its first frame, proves less).
        restarted = outcomes.get("killed, partial", 0)
        self.assertGreater(restarted, 0.6 * len(cases), outcomes)


if __name__ == "__main__":
    unittest.main(verbosity=2)
