# SPDX-License-Identifier: BSD-3-Clause
"""Reading a run file of `smpm run` (its layout: `smpm info --layout`) into numpy and scipy.

    run = sparsempm.read_run("two_disks.h5")
    run.times, run.series["kinetic"]          # frame times; one row per step
    p = run.particles(-1)                     # the last frame: p["X"], p["V"], p["stress"], ...
    g = run.grid(0)                           # nodes with mass: g["nodes"], g["m"], g["X"], ...
    S = run.matrices(0)["S"]                  # with [output] matrices = true: scipy CSR

Only complete frames are listed, so the file of a live run (run.partial.h5) reads as the frames
written so far (the file is opened without HDF5's lock, which the writer holds); the file is
closed after each call.
"""

import tomllib

import numpy as np

__all__ = ["Run", "read_run"]


def _open(path):
    """The file read-only; without HDF5's lock when a writer holds it (a live run) or when this
    process holds it open without the lock already (HDF5 refuses a second open that differs)."""
    import h5py  # an optional dependency (python3-h5py), needed only here

    try:
        return h5py.File(path, "r")
    except OSError as first:
        try:
            return h5py.File(path, "r", locking=False)
        except OSError:
            raise first from None


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Run:
    """A run file: its input, status, complete frames, series and each frame's arrays."""

    def __init__(self, path):
        self.path = str(path)
        with _open(self.path) as f:
            attrs = f.attrs
            if "input" not in attrs or "particles" not in f or "series" not in f:
                raise ValueError(f"{self.path}: not a sparsempm run file (no input, particles "
                                 "or series)")
            #: The input file with the --set overrides appended, its name, the overrides.
            self.input = _text(attrs["input"])
            self.source = _text(attrs.get("source", ""))
            self.overrides = [_text(o) for o in np.atleast_1d(attrs.get("overrides", []))]
            self.version = _text(attrs.get("version", ""))
            #: running | completed | failed: ... | interrupted: ...
            self.status = _text(attrs.get("status", ""))
            parts = f["particles"]
            #: The complete frames' numbers, ascending, and their times.
            self.frames = sorted(int(k) for k in parts if k.isdigit()
                                 and int(parts[k].attrs.get("complete", 0)) == 1)
            self.times = np.array([parts["%06d" % k].attrs["time"] for k in self.frames])
            #: Every series as an array, one row per step (row 0: t = 0).
            self.series = {k: f["series"][k][()] for k in f["series"]}
        config = tomllib.loads(self.input)
        #: The material names, by material id.
        self.materials = [m.get("name", str(i)) for i, m in enumerate(config.get("material", []))]
        #: The grid's dimension.
        self.dim = int(config.get("grid", {}).get("dim", 1))

    def _frame(self, k):
        if not self.frames:
            raise IndexError(f"{self.path}: no complete frame")
        number = self.frames[k]  # an index into frames (negative from the end)
        return "%06d" % number

    def _group(self, group, k):
        name = self._frame(k)
        with _open(self.path) as f:
            if group not in f or name not in f[group]:
                raise KeyError(f"{self.path}: frame {int(name)} has no /{group}")
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

        name = self._frame(k)
        with _open(self.path) as f:
            if "matrices" not in f or name not in f["matrices"]:
                raise KeyError(f"{self.path}: frame {int(name)} has no matrices (run with "
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
