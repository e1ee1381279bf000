#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Opens the XDMF sidecars of sparsempm runs in the readers researchers use and checks what they
read against the run file itself (h5py): ParaView 5.11's three XDMF readers (Xdmf3ReaderS, the
one OpenDataFile picks, Xdmf3ReaderT and the legacy XDMFReader), headless, and meshio's
TimeSeriesReader. For every sidecar of every run given: the time steps (to the last bit: the
sidecar writes max_digits10 digits), each frame's point count, the array names and shapes, and
the values of every array at the first, a middle and the last frame.

usage: check_readers.py [--live] RUN.h5 [RUN.h5 ...]   (one line per reader and sidecar;
       --live: the files of a run in progress, whose sidecars grow while they are read)
"""

import os
import sys
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")


def fail(msg):
    sys.exit("check_readers: " + msg)


def expected_frames(xmf):
    """Per time step of the sidecar, (time, points, {name: array}) read with h5py from the
    datasets the sidecar names, shaped as the sidecar declares them."""
    root = ET.parse(xmf).getroot()
    collection = root.find("Domain/Grid")
    if collection is None or collection.get("CollectionType") != "Temporal":
        fail(f"{xmf}: no temporal collection")
    frames = []
    for grid in collection.findall("Grid"):
        def read(item):
            name, path = item.text.strip().rsplit(":", 1)
            with h5py.File(os.path.join(os.path.dirname(xmf), name), "r") as f:
                a = f[path][()]
            dims = [int(d) for d in item.get("Dimensions").split()]
            if a.size != np.prod(dims):
                fail(f"{xmf}: {path} has {a.size} values, the sidecar declares {dims}")
            return a.reshape(dims)

        time = float(grid.find("Time").get("Value"))
        points = read(grid.find("Geometry/DataItem"))
        arrays = {a.get("Name"): read(a.find("DataItem")) for a in grid.findall("Attribute")}
        frames.append((time, points, arrays))
    return frames


def as_columns(a):
    return a.reshape(a.shape[0], -1)


def compare(who, k, got, want):
    for name, w in want.items():
        if name not in got:
            fail(f"{who}: frame {k}: no array '{name}' (it read {sorted(got)})")
        g = np.asarray(got[name])
        w = as_columns(w)
        g = as_columns(g)
        if g.shape[1] == 3 and w.shape[1] == 2:  # the legacy reader pads 2D vectors with z = 0
            if np.any(g[:, 2] != 0):
                fail(f"{who}: frame {k}: '{name}' has a non-zero third component")
            g = g[:, :2]
        if g.shape != w.shape:
            fail(f"{who}: frame {k}: '{name}' has shape {g.shape}, the run file {w.shape}")
        if not np.array_equal(g.astype(w.dtype), w):
            fail(f"{who}: frame {k}: '{name}' differs from the run file by "
                 f"{np.max(np.abs(g - w))}")


def sample(n):
    return sorted({0, n // 2, n - 1})


def check_paraview(xmf, frames, live):
    from paraview import servermanager as sm
    from paraview import simple
    from vtkmodules.util.numpy_support import vtk_to_numpy

    times = [t for t, _, _ in frames]
    for reader in ("Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader"):
        who = f"ParaView {reader} {os.path.basename(xmf)}"
        if reader == "XDMFReader":
            r = simple.XDMFReader(FileNames=[xmf])
        else:
            r = getattr(simple, reader)(FileName=[xmf])
        got_times = list(r.TimestepValues) if len(times) > 1 else times
        if live:  # a live run's sidecar may have grown since it was parsed
            got_times = got_times[:len(times)]
        if got_times != times:
            fail(f"{who}: time steps {got_times[:4]}... differ from the sidecar's {times[:4]}...")
        for k in sample(len(frames)):
            t, points, arrays = frames[k]
            r.UpdatePipeline(t)
            data = sm.Fetch(r)
            while data.IsA("vtkMultiBlockDataSet"):
                data = data.GetBlock(0)
            if data.GetNumberOfPoints() != len(points) or data.GetNumberOfCells() != len(points):
                fail(f"{who}: frame {k}: {data.GetNumberOfPoints()} points and "
                     f"{data.GetNumberOfCells()} cells, the run file has {len(points)} points")
            # The arrays as stored, one tuple per row (dsa's wrapper would reshape a 9-component
            # array to 3 × 3 in VTK's column-major tensor order).
            pd = data.GetPointData()
            got = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i))
                   for i in range(pd.GetNumberOfArrays())}
            pts = vtk_to_numpy(data.GetPoints().GetData())
            d = points.shape[1]
            if not np.array_equal(pts[:, :d], points) or np.any(pts[:, d:] != 0):
                fail(f"{who}: frame {k}: point coordinates differ from the run file")
            compare(who, k, got, arrays)
        simple.Delete(r)
        print(f"{who}: {len(frames)} time steps, {len(frames[-1][2])} arrays: as in the run file")


def check_meshio(xmf, frames, live):
    who = f"meshio TimeSeriesReader {os.path.basename(xmf)}"
    with meshio.xdmf.TimeSeriesReader(xmf) as reader:
        points, cells = reader.read_points_cells()
        if cells[0].type != "vertex" or len(cells[0].data) != len(frames[0][1]):
            fail(f"{who}: cells {cells[0].type} × {len(cells[0].data)}")
        if not np.array_equal(points, frames[0][1]):
            fail(f"{who}: the points differ from the first frame's")
        if reader.num_steps != len(frames) and not (live and reader.num_steps > len(frames)):
            fail(f"{who}: {reader.num_steps} time steps, the sidecar has {len(frames)}")
        for k in range(len(frames)):
            t, point_data, _ = reader.read_data(k)
            if t != frames[k][0]:
                fail(f"{who}: frame {k}: time {t!r}, the run file {frames[k][0]!r}")
            if k in sample(len(frames)):
                compare(who, k, point_data, frames[k][2])
    print(f"{who}: {len(frames)} time steps, {len(frames[-1][2])} arrays: as in the run file")


def check_times(run, xmf, frames, live):
    """The sidecar's times are the frames' time attributes, to the last bit (of a live run: the
    first frames', the file may have more by now)."""
    with h5py.File(run, "r") as f:
        want = [f["particles"][k].attrs["time"] for k in sorted(f["particles"]) if k.isdigit()]
    got = [t for t, _, _ in frames]
    if live:
        want = want[:len(got)]
    if xmf.endswith(".contact.xmf"):
        if not set(got) <= set(want):
            fail(f"{xmf}: times not among the frames' times")
    elif got != want:
        fail(f"{xmf}: times {got[:3]}... differ from the frames' {want[:3]}...")


def main(runs, live=False):
    """Checks every sidecar of each run file in `runs` (live: of a run still writing it)."""
    for run in runs:
        base = os.path.abspath(str(run))[:-3]  # Xdmf3 needs a directory in the name
        sidecars = [base + s for s in (".xmf", ".nodes.xmf", ".contact.xmf")]
        for xmf in sidecars:
            if not os.path.exists(xmf):
                if xmf.endswith(".contact.xmf"):
                    continue
                fail(f"{xmf}: missing")
            frames = expected_frames(xmf)
            if not frames:
                fail(f"{xmf}: no time step")
            check_times(run, xmf, frames, live)
            check_paraview(xmf, frames, live)
            check_meshio(xmf, frames, live)


if __name__ == "__main__":
    args = sys.argv[1:]
    live = "--live" in args
    args = [a for a in args if a != "--live"]
    if not args:
        sys.exit(__doc__)
    main(args, live)
