# SPDX-License-Identifier: BSD-3-Clause
"""Reading a run file of `smpm run` (its layout: `smpm info --layout`) into numpy and scipy.

    run = sparsempm.read_run("two_disks.h5")
    run.times, run.series["kinetic"]          # frame times; one row per step
    p = run.particles(-1)                     # the last frame: p["X"], p["V"], p["stress"], ...
    g = run.grid(0)                           # nodes with mass: g["nodes"], g["m"], g["X"], ...
    S = run.matrices(0)["S"]                  # with [output] matrices = true: scipy CSR

A completed run is one file. A run in progress, or one that was stopped, is its partial file
(run.partial.h5: the run's input, status and series) beside a directory of frame files
(run.partial.frames/000012.h5), each file complete once it has its name: read_run lists the
frame files there, so it reads exactly the completed frames of a live run, and a file is opened
only for the call that reads it.
"""

import os
import re
import time
import tomllib

import numpy as np

__all__ = ["Run", "read_run"]


def _open(path, attempts=20):
    """The file read-only. A run of an earlier version held HDF5's lock on its file while it
    ran: such a file is read without the lock (as is one this process holds open without it),
    and an open that meets a write in progress is tried again for half a second."""
    import h5py  # an optional dependency (python3-h5py), needed only here

    for attempt in range(attempts):
        try:
            return h5py.File(path, "r")
        except OSError as first:
            try:
                return h5py.File(path, "r", locking=False)
            except OSError:
                if attempt + 1 == attempts or not os.path.isfile(path):
                    raise first from None
        time.sleep(0.025)


_FRAME_FILE = re.compile(r"^([0-9]{6,9})\.h5$")


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Run:
    """A run file: its input, status, complete frames, series and each frame's arrays."""

    def __init__(self, path):
        self.path = str(path)
        self._dir = None  # the directory of the frame files of a run in progress
        # Only a regular file: opening a FIFO would wait for a writer forever.
        if not os.path.exists(self.path):
            raise FileNotFoundError(f"{self.path}: no such run file")
        if not os.path.isfile(self.path):
            raise ValueError(f"{self.path}: a run file must be a regular file, not a directory, "
                             "FIFO or device")
        with _open(self.path) as f:
            attrs = f.attrs
            if "input" not in attrs or "series" not in f:
                raise ValueError(f"{self.path}: not a sparsempm run file (no input or series)")
            #: The input file with the --set overrides appended, its name, the overrides.
            self.input = _text(attrs["input"])
            self.source = _text(attrs.get("source", ""))
            self.overrides = [_text(o) for o in np.atleast_1d(attrs.get("overrides", []))]
            self.version = _text(attrs.get("version", ""))
            #: The unit system of the input's numbers (output.units): none, SI or mm-ms-g
            #: ("none" for files of releases that did not store it).
            self.units = _text(attrs.get("units", "none"))
            #: running | completed | failed: ... | interrupted: ...
            self.status = _text(attrs.get("status", ""))
            index_series = {k: f["series"][k][()] for k in f["series"]}
            if "frame_files" in attrs:
                self._dir = os.path.join(os.path.dirname(self.path), _text(attrs["frame_files"]))
                last, rows = int(attrs["last_frame"]), int(attrs["frame_rows"])
            elif "particles" not in f:
                raise ValueError(f"{self.path}: not a sparsempm run file (no particles)")
            else:
                parts = f["particles"]
                #: The complete frames' numbers, ascending, and their times.
                self.frames = sorted(int(k) for k in parts if k.isdigit()
                                     and int(parts[k].attrs.get("complete", 0)) == 1)
                self.times = np.array([parts["%06d" % k].attrs["time"] for k in self.frames])
                #: Every series as an array, one row per step (row 0: t = 0).
                self.series = index_series
        if self._dir is not None:
            self._read_frame_files(index_series, last, rows)
        config = tomllib.loads(self.input)
        #: The material names, by material id.
        self.materials = [m.get("name", str(i)) for i, m in enumerate(config.get("material", []))]
        #: The grid's dimension.
        self.dim = int(config.get("grid", {}).get("dim", 1))

    def _read_frame_files(self, index_series, last, rows):
        """The frames of a run in progress: the files of its directory. The index holds the
        series rows up to frame `last` (`rows` of them; after them, a stopped run's last
        steps); the rows of later frames are in their files."""
        names = os.listdir(self._dir) if os.path.isdir(self._dir) else []
        self.frames = sorted(int(m.group(1)) for m in map(_FRAME_FILE.match, names) if m)
        times, later = [], []
        for i, k in enumerate(self.frames):
            try:
                with _open(self._frame_path(k), attempts=1) as f:
                    times.append(f["particles"]["%06d" % k].attrs["time"])
                    if k > last and "series" in f:
                        later.append({n: f["series"][n][()] for n in f["series"]})
            except (OSError, KeyError):  # a frame file that cannot be read: no frame from it on
                self.frames = self.frames[:i]
                break
        self.times = np.array(times)
        if not later:
            self.series = index_series
            return
        self.series = {n: np.concatenate([v[:rows]] + [p[n] for p in later if n in p])
                       for n, v in index_series.items()}

    def _frame_path(self, number):
        if self._dir is None:
            return self.path
        return os.path.join(self._dir, "%06d.h5" % number)

    def _frame(self, k):
        if not self.frames:
            raise IndexError(f"{self.path}: no complete frame")
        return self.frames[k]  # an index into frames (negative from the end)

    def _group(self, group, k):
        number = self._frame(k)
        name = "%06d" % number
        with _open(self._frame_path(number)) as f:
            if group not in f or name not in f[group]:
                raise KeyError(f"{self.path}: frame {number} has no /{group}")
            g = f[group][name]
            out = {key: g[key][()] for key in g}
            out.update({"@" + key: g.attrs[key] for key in g.attrs})
            return out

    def particles(self, k):
        """The particle arrays of frame index k (into `frames`; -1 the last): X, V, stress, F
        (rows of d² entries, row-major), J, mass, volume, volume0, half_length, material,
        energy (where the materials have one), and the attributes as "@time", "@step"."""
        return self._group("particles", k)

    def grid(self, k):
        """The nodes with mass of frame index k: nodes (a n_g + i: field a), m, p, v, X, and the
        contact nodes of a multimaterial run (contact_nodes, contact_normal, ...)."""
        return self._group("grid", k)

    def matrices(self, k):
        """S, G0, G1, G2 and consistent_mass of frame index k as scipy.sparse CSR matrices, and
        with heat transport consistent_capacity and conductivity (a run with [output]
        matrices = true)."""
        import scipy.sparse

        number = self._frame(k)
        name = "%06d" % number
        with _open(self._frame_path(number)) as f:
            if "matrices" not in f or name not in f["matrices"]:
                raise KeyError(f"{self.path}: frame {number} has no matrices (run with "
                               "[output] matrices = true)")
            out = {}
            for key, g in f["matrices"][name].items():
                out[key] = scipy.sparse.csr_matrix(
                    (g["data"][()], g["indices"][()], g["indptr"][()]),
                    shape=tuple(int(n) for n in g["shape"][()]))
            return out

    def __repr__(self):
        return (f"Run({self.path!r}: {self.status}, {len(self.frames)} frames, "
                f"{len(self.series.get('step', []))} steps)")


def read_run(path):
    """The run file at `path` (a completed, failed or live run) as a Run."""
    return Run(path)
