#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Ghost nodes per rank of the distributed grid (lib/petsc) on P MPI ranks.

    analysis/ghost_nodes.py [--cells2d NX NY] [--cells3d NX NY NZ] [--shape gimp ...]
                            [--ranks 2 4 ...] [-o ghost_nodes.csv]
    analysis/ghost_nodes.py --check-boxes smpm_dmda_boxes [--mpiexec mpiexec]

The distributed component puts the grid's Nx × Ny (× Nz) nodes (cells + 1 per axis) on a
PETSc DMDA with PETSC_DECIDE ranks per axis: rank r owns the box of nodes [xs, xs + xm) ×
[ys, ys + ym) (× [zs, zs + zm)). dmda_boxes() reproduces PETSc 3.18's split exactly
(DMSetUp_DA_2D in src/dm/impls/da/da2.c, DMSetUp_DA_3D in da3.c): the process grid m × n
(× p) from the "squarish" rule and the ownership ranges lx[i] = M / m + (M % m > i). For each
rank it counts, relative to the nodes it owns:

  window   the assembly window: a rank adds the particles of the cells it owns (the cell whose
           lowest corner node is in its box; cells 0 … nodes − 2 per axis); a particle in cell c
           touches nodes c − a … c + 1 + a per axis (reach a = 0 linear, 1 gimp and bspline2).
           Ghosts = nodes of the union of those ranges (clipped to the grid) it does not own
           (the window contains the box, except for a box of only the last node of an axis,
           which owns no cell: its window is empty and its ghosts 0).
  MatMult  the off-rank nodes its rows of m̃ reference, which MatMult scatters in every FMPM
           pass: m̃ couples nodes up to w apart per axis (box stencil; w = 1 linear, 2 gimp and
           bspline2), so ghosts = nodes within w of its box (clipped) it does not own.

For each dimension, grid, shape and P the table gives the process grid, the least and most
owned nodes, and the max and mean over the ranks of ghosts / owned for both; P = 2, 4, …, 4096
unless --ranks. A grid PETSc cannot split over P ranks (an axis with fewer nodes than ranks)
is marked "too many ranks". Writes the table as CSV to -o (default ghost_nodes.csv).

--check-boxes EXECUTABLE runs the probe tests/petsc/dmda_boxes.cpp (target smpm_dmda_boxes)
under mpiexec for awkward grids and rank counts and compares the DMDA's own boxes with
dmda_boxes(); it also compares the ghost counts of small grids with a brute-force count. Exits
non-zero on a mismatch, naming the case. OpenMPI needs OMPI_ALLOW_RUN_AS_ROOT=1 and
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 as root; oversubscription (more ranks than cores) is allowed
through OMPI_MCA_rmaps_base_oversubscribe=1 unless the environment sets it.
"""
import argparse
import csv
import itertools
import math
import os
import pathlib
import subprocess
import sys
import time
from typing import NamedTuple

import numpy as np

# Per shape: the reach a of a cell's particles (cell c touches nodes c − a … c + 1 + a) and the
# half-width w of m̃'s stencil (one particle touches 2 consecutive nodes per axis with linear
# shape functions, 3 with uGIMP and the quadratic B-spline, whose support is ±1.5 cells).
SHAPES = {"linear": (0, 1), "gimp": (1, 2), "bspline2": (1, 2)}
# The DMDA's stencil width in lib/petsc/src/distributed.cpp: PETSc requires every rank to own
# at least this many nodes along each axis split over more than one rank.
STENCIL_WIDTH = 1
DEFAULT_RANKS = [2 ** k for k in range(1, 13)]
AXES = "xyz"


class TooManyRanks(ValueError):
    """PETSc refuses to split the grid over that many ranks; the text is PETSc's message."""


class Split(NamedTuple):
    """The DMDA's split of a grid over P ranks: `grid` is the process grid (m, n[, p]); row r
    of `first` and `count` (P × dim) is rank r's first node and node count per axis."""
    grid: tuple
    first: np.ndarray
    count: np.ndarray


def process_grid(nodes, size):
    """PETSc 3.18's process grid for PETSC_DECIDE ranks on every axis of a DMDA over `nodes`
    (M, N[, P]) nodes and `size` ranks: DMSetUp_DA_2D (da2.c) and DMSetUp_DA_3D (da3.c), in
    the same floating-point operations (int() truncates as the C casts do)."""
    if len(nodes) == 2:
        M, N = nodes
        # "try for squarish distribution": m ≈ sqrt(M size / N), lowered to a divisor of size.
        m = int(0.5 + math.sqrt(float(M) * float(size) / float(N)))
        if not m:
            m = 1
        while m > 0:
            n = size // m
            if m * n == size:
                break
            m -= 1
        if M > N and m < n:
            m, n = n, m
        if m * n != size:
            raise TooManyRanks("Unable to create partition, check the size of the communicator "
                               "and input m and n ")
        return (m, n)
    M, N, P = nodes
    # n ≈ (N² size / (P M))^(1/3) lowered to a divisor of size, then m as in 2D over size / n.
    n = int(0.5 + math.pow(float(N) * N * float(size) / (float(P) * M), 1.0 / 3.0))
    if not n:
        n = 1
    while n > 0:
        if n * (size // n) == size:
            break
        n -= 1
    if not n:
        n = 1
    m = int(0.5 + math.sqrt(float(M) * float(size) / (float(P) * n)))
    if not m:
        m = 1
    while m > 0:
        p = size // (m * n)
        if m * n * p == size:
            break
        m -= 1
    if M > P and m < p:
        m, p = p, m
    if m * n * p != size:
        raise TooManyRanks("Could not find good partition")
    return (m, n, p)


def ownership_ranges(M, m):
    """PETSc's nodes per part when M nodes are split over m ranks: lx[i] = M / m + (M % m > i)
    (the first M % m parts get one node more)."""
    i = np.arange(m)
    return M // m + (M % m > i).astype(np.int64)


def dmda_boxes(nodes, size, stencil_width=STENCIL_WIDTH):
    """The box of nodes of every rank of a DMDA over `nodes` (Nx, Ny[, Nz]) nodes on `size`
    ranks with PETSC_DECIDE ranks per axis and no periodic axis, as PETSc 3.18's DMSetUp.
    Returns a Split; raises TooManyRanks, with PETSc's message, where DMSetUp fails."""
    nodes = tuple(int(N) for N in nodes)
    grid = process_grid(nodes, size)
    for a, (N, parts) in enumerate(zip(nodes, grid)):
        if N < parts:
            raise TooManyRanks(f"Partition in {AXES[a]} direction is too fine! {N} {parts}")
    ranges = [ownership_ranges(N, parts) for N, parts in zip(nodes, grid)]
    for a, (l, parts) in enumerate(zip(ranges, grid)):
        # Every part of a split axis needs `stencil_width` nodes; 3D excepts a z axis of 1 node.
        if parts > 1 and l.min() < stencil_width and not (a == 2 and nodes[2] == 1):
            raise TooManyRanks(f"Local {AXES[a]}-width of domain {AXES[a]} {l.min()} is smaller "
                               f"than stencil width s {stencil_width}")
    # Rank r is part (r mod m, (r div m) mod n, r div mn) of the process grid: x varies fastest.
    r = np.arange(size)
    part = [r % grid[0], (r // grid[0]) % grid[1]]
    if len(nodes) == 3:
        part.append(r // (grid[0] * grid[1]))
    starts = [np.concatenate(([0], np.cumsum(l)[:-1])) for l in ranges]
    first = np.stack([s[i] for s, i in zip(starts, part)], axis=1)
    count = np.stack([l[i] for l, i in zip(ranges, part)], axis=1)
    return Split(grid, first, count)


def ghost_counts(nodes, first, count, shape):
    """Ghost nodes of each rank (rows of `first`, `count`) for shape `shape`: (window, MatMult),
    two arrays over the ranks, as defined in the module's description."""
    reach, half_width = SHAPES[shape]
    N = np.asarray(nodes)
    start, end = first, first + count
    owned = count.prod(axis=1)
    # The window, per axis: cells [start, min(end, N − 1)) touch nodes [cell − a, cell + 1 + a];
    # an axis without owned cells (a box of the last node only) leaves the window empty.
    cell_end = np.minimum(end, N - 1)
    has_cells = cell_end > start
    lo = np.where(has_cells, np.maximum(start - reach, 0), 0)
    hi = np.where(has_cells, np.minimum(cell_end + 1 + reach, N), 0)
    inside = np.maximum(np.minimum(hi, end) - np.maximum(lo, start), 0)  # window ∩ box
    window = (hi - lo).prod(axis=1) - inside.prod(axis=1)
    # m̃'s halo: the box widened by w on each side, clipped to the grid, which contains the box.
    halo = (np.minimum(end + half_width, N) - np.maximum(start - half_width, 0)).prod(axis=1)
    return window, halo - owned


def brute_force_ghosts(nodes, first, count, shape):
    """The same counts as ghost_counts, one rank, cell and node at a time (for small grids):
    marks the nodes every owned cell's particles touch and the nodes every owned node's row of
    m̃ references, and counts the marked nodes the rank does not own."""
    reach, half_width = SHAPES[shape]
    window, halo = [], []
    for f, c in zip(first, count):
        box = [range(s, s + k) for s, k in zip(f, c)]
        owned = set(itertools.product(*box))
        touched, referenced = set(), set()
        for cell in owned:
            if all(cell[a] <= nodes[a] - 2 for a in range(len(nodes))):
                touched.update(itertools.product(*[
                    range(max(cell[a] - reach, 0), min(cell[a] + 2 + reach, nodes[a]))
                    for a in range(len(nodes))]))
        for node in owned:
            referenced.update(itertools.product(*[
                range(max(node[a] - half_width, 0), min(node[a] + half_width + 1, nodes[a]))
                for a in range(len(nodes))]))
        window.append(len(touched - owned))
        halo.append(len(referenced - owned))
    return np.array(window), np.array(halo)


def table_rows(grids, shapes, ranks):
    """One row (a dict of the CSV's columns) per grid, shape and number of ranks."""
    rows = []
    for cells in grids:
        nodes = tuple(c + 1 for c in cells)
        for shape, size in itertools.product(shapes, ranks):
            reach, half_width = SHAPES[shape]
            row = {"dim": len(nodes), "cells": "x".join(map(str, cells)),
                   "nodes": "x".join(map(str, nodes)), "shape": shape, "reach": reach,
                   "half_width": half_width, "ranks": size}
            try:
                split = dmda_boxes(nodes, size)
            except TooManyRanks as e:
                rows.append(row | {"status": "too many ranks", "petsc_error": str(e)})
                continue
            owned = split.count.prod(axis=1)
            window, halo = ghost_counts(nodes, split.first, split.count, shape)
            row |= {"process_grid": "x".join(map(str, split.grid)),
                    "owned_min": int(owned.min()), "owned_max": int(owned.max()),
                    "window_ghosts_max": int(window.max()),
                    "window_fraction_max": (window / owned).max(),
                    "window_fraction_mean": (window / owned).mean(),
                    "matmult_ghosts_max": int(halo.max()),
                    "matmult_fraction_max": (halo / owned).max(),
                    "matmult_fraction_mean": (halo / owned).mean(), "status": "ok"}
            rows.append(row)
    return rows


COLUMNS = ["dim", "cells", "nodes", "shape", "reach", "half_width", "ranks", "process_grid",
           "owned_min", "owned_max", "window_ghosts_max", "window_fraction_max",
           "window_fraction_mean", "matmult_ghosts_max", "matmult_fraction_max",
           "matmult_fraction_mean", "status", "petsc_error"]


def print_table(rows):
    print("Ghost nodes per rank / owned nodes per rank on PETSc's DMDA split (max and mean over "
          "the ranks)")
    print("  window: the nodes the particles of the rank's cells touch, less its own;")
    print("  MatMult: the off-rank nodes its rows of m~ reference (what each FMPM pass scatters)")
    head = (f"{'dim':>3} {'nodes':>11} {'shape':>8} {'P':>5} {'ranks/axis':>10} "
            f"{'owned min':>9} {'owned max':>9} {'window max':>10} {'mean':>7} "
            f"{'MatMult max':>11} {'mean':>7}")
    print(head)
    print("-" * len(head))
    for r in rows:
        lead = f"{r['dim']:>3} {r['nodes']:>11} {r['shape']:>8} {r['ranks']:>5}"
        if r["status"] != "ok":
            print(f"{lead} {'too many ranks':>10} ({r['petsc_error']})")
            continue
        print(f"{lead} {r['process_grid']:>10} {r['owned_min']:>9} {r['owned_max']:>9} "
              f"{r['window_fraction_max']:>10.4f} {r['window_fraction_mean']:>7.4f} "
              f"{r['matmult_fraction_max']:>11.4f} {r['matmult_fraction_mean']:>7.4f}")


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


# The grids (node counts) the probe splits over each number of ranks of CHECK_RANKS: odd and
# even sizes, long thin grids (1D-like), grids too small for P ranks (PETSc refuses; so must
# dmda_boxes) and, in 3D, a z axis of one node (PETSc's "2D problem in a 3D code").
CHECK_GRIDS = [(31, 17), (7, 50), (64, 64), (9, 13, 7), (16, 16, 16),
               (2, 40), (41, 3), (25, 1), (3, 3), (30, 2, 2), (2, 2, 30), (2, 30, 1), (2, 2, 2)]
CHECK_RANKS = list(range(1, 13)) + [16]
# Small grids whose ghost counts ghost_counts and brute_force_ghosts must agree on, with ranks.
# (4, 4) on 9 and (4, 4, 4) on 27 ranks give boxes of the last node alone, which own no cell.
BRUTE_FORCE = [((9, 7), [1, 2, 3, 4, 6]), ((12, 5), [5, 8]), ((4, 4), [9]), ((30, 2), [7]),
               ((6, 5, 4), [1, 2, 4, 8]), ((5, 7, 3), [3, 6]), ((4, 4, 4), [27])]


def parse_probe(text):
    """The probe's output: {nodes: ("ranks", grid, boxes) or ("cannot split", message)}, where
    boxes is a P × 6 array of rows rank-ordered (xs, ys, zs, xm, ym, zm)."""
    found, nodes = {}, None
    for line in text.splitlines():
        if line.startswith("# grid "):
            dim, *n = map(int, line.split()[2:])
            nodes = tuple(n[:dim])
        elif line.startswith("# ranks "):
            found[nodes] = ("ranks", tuple(map(int, line.split()[2:])), [])
        elif line.startswith("# cannot split: "):
            found[nodes] = ("cannot split", line[len("# cannot split: "):].strip())
        elif line.strip() and not line.startswith("#"):
            rank, *box = map(int, line.split())
            if rank != len(found[nodes][2]):
                raise ValueError(f"rank {rank} out of order")
            found[nodes][2].append(box)
    return found


def compare(nodes, size, probe):
    """A list of the differences between dmda_boxes(nodes, size) and the probe's result."""
    try:
        split = dmda_boxes(nodes, size)
    except TooManyRanks as e:
        if probe is None or probe[0] != "cannot split":
            return [f"predicted too many ranks ({e}), PETSc splits it"]
        return [] if probe[1] == str(e) else [f"PETSc says '{probe[1]}', predicted '{e}'"]
    if probe is None or probe[0] != "ranks":
        return [f"PETSc: {probe[1] if probe else 'no output'}; predicted {split.grid}"]
    dim = len(nodes)
    grid = probe[1][:dim]
    boxes = np.array(probe[2]).reshape(-1, 6)
    if grid != split.grid or (dim == 2 and probe[1][2] != 1):
        return [f"process grid {probe[1]}, predicted {split.grid}"]
    if len(boxes) != size:
        return [f"{len(boxes)} boxes for {size} ranks"]
    want = np.hstack([split.first, np.zeros((size, 3 - dim), int),
                      split.count, np.ones((size, 3 - dim), int)])
    return [f"rank {r}: PETSc {list(boxes[r])}, predicted {list(want[r])}"
            for r in range(size) if not np.array_equal(boxes[r], want[r])]


def check_ghost_counts():
    """Compares ghost_counts with brute_force_ghosts on the grids of BRUTE_FORCE for every
    shape. Returns the number of cases (grid, P, shape) that differ."""
    failures = cases = 0
    for nodes, sizes in BRUTE_FORCE:
        for size, shape in itertools.product(sizes, SHAPES):
            cases += 1
            split = dmda_boxes(nodes, size)
            fast = ghost_counts(nodes, split.first, split.count, shape)
            slow = brute_force_ghosts(nodes, split.first, split.count, shape)
            bad = [(name, a, b) for name, a, b in zip(("window", "MatMult"), fast, slow)
                   if not np.array_equal(a, b)]
            failures += bool(bad)
            for name, a, b in bad:
                print(f"MISMATCH {'×'.join(map(str, nodes))} nodes, P = {size}, {shape}: {name} "
                      f"ghosts per rank {list(a)}, brute force {list(b)}")
    print(f"ghost counts against a brute-force count: {cases} cases (grid, P, shape), "
          f"{'all equal' if not failures else f'{failures} differ'}")
    return failures


def check_probe(executable, mpiexec):
    """Compares dmda_boxes with the DMDA of the probe `executable` for CHECK_GRIDS on each
    number of ranks of CHECK_RANKS (one launch of mpiexec per number of ranks). Returns the
    number of cases (grid, P) that differ or could not be run."""
    env = dict(os.environ)
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    env.setdefault("OMP_NUM_THREADS", "1")
    args = [str(v) for g in CHECK_GRIDS for v in (len(g), *g)]
    failures = cases = 0
    for size in CHECK_RANKS:
        command = [mpiexec, "-n", str(size), executable, *args]
        began = time.monotonic()
        cases += len(CHECK_GRIDS)
        try:
            run = subprocess.run(command, capture_output=True, text=True, env=env, timeout=120)
            # Status 0: every grid split; 3: PETSc refused some ("# cannot split").
            found = parse_probe(run.stdout) if run.returncode in (0, 3) else {}
            why = f"exited {run.returncode}\n{run.stdout}{run.stderr[-3000:]}"
        except (OSError, subprocess.TimeoutExpired, ValueError, KeyError, IndexError) as e:
            found, why = {}, str(e)
        if not found:
            print(f"MISMATCH P = {size}: {' '.join(command)}: {why}")
            failures += len(CHECK_GRIDS)
            continue
        bad = 0
        for nodes in CHECK_GRIDS:
            problems = compare(nodes, size, found.get(nodes))
            bad += bool(problems)
            if len(problems) > 4:
                problems[4:] = [f"... and {len(problems) - 4} more"]
            for problem in problems:
                print(f"MISMATCH {'×'.join(map(str, nodes))} nodes, P = {size}: {problem}")
        failures += bad
        print(f"P = {size:2}: {len(CHECK_GRIDS)} grids, {'equal' if not bad else 'MISMATCH'} "
              f"({time.monotonic() - began:.1f} s)")
    print(f"DMDA boxes against PETSc: {cases} cases (grid, P), "
          f"{'all equal' if not failures else f'{failures} differ'}")
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cells2d", type=int, nargs=2, default=[1000, 1000], metavar=("NX", "NY"),
                    help="cells of the 2D grid (default 1000 1000)")
    ap.add_argument("--cells3d", type=int, nargs=3, default=[100, 100, 100],
                    metavar=("NX", "NY", "NZ"), help="cells of the 3D grid (default 100 100 100)")
    ap.add_argument("--shape", nargs="+", choices=sorted(SHAPES), default=["gimp"],
                    help="shape functions (default gimp)")
    ap.add_argument("--ranks", type=int, nargs="+", default=DEFAULT_RANKS, metavar="P",
                    help="numbers of ranks (default 2 4 8 ... 4096)")
    ap.add_argument("-o", "--output", default="ghost_nodes.csv",
                    help="CSV file (default ghost_nodes.csv)")
    ap.add_argument("--check-boxes", metavar="EXECUTABLE",
                    help="compare with the DMDA of the probe smpm_dmda_boxes and exit")
    ap.add_argument("--mpiexec", default="mpiexec", help="MPI launcher of --check-boxes")
    args = ap.parse_args()
    name = pathlib.Path(sys.argv[0]).name
    if args.check_boxes:
        failures = check_ghost_counts() + check_probe(args.check_boxes, args.mpiexec)
        sys.exit(1 if failures else 0)
    if min(args.cells2d + args.cells3d) < 1 or min(args.ranks) < 1:
        sys.exit(f"{name}: cells and ranks must be positive")
    rows = table_rows([tuple(args.cells2d), tuple(args.cells3d)], args.shape, args.ranks)
    print_table(rows)
    try:
        write_csv(rows, args.output)
    except OSError as e:
        sys.exit(f"{name}: {args.output}: {e}")
    print(f"{args.output}: {len(rows)} rows")


if __name__ == "__main__":
    main()
