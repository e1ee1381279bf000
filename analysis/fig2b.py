#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Contact 2020 Fig. 2B: when each contact-detection method finds two blocks in contact.

    analysis/fig2b.py [--smpm build/apps/smpm] [--jobs 2] [--end 10] [-o fig2b]

Runs examples/two_block_compression.toml (contact 2020 Fig. 2A: two hyperelastic blocks, 5 mm
cells, GIMP, 2 x 2 particles per cell, Coulomb mu = 0.2, the top pushed at 0.9622 mm/ms) with
the upper block lifted to leave the paper's 7.5 mm (1.5 cell) gap, so that the blocks touch at
t_c = 7.5 / 0.9622 = 7.795 ms, on a grid line (the lower block's top at y = 50 mm) and in the
middle of a cell (at y = 52.5 mm), for each detection: the approaching criterion alone
(Delta v < 0, Eq. 14), CP = 0.92 and 0.8 (Eq. 16), DF (Eq. 15) with AG normals, and logistic
regression (LR normals and d_LR). The mean axial stress of the particles of the lower block is
zero until it is touched; the table gives the first frame time (every 0.05 ms) at which it
falls below -0.01 MPa, against t_c (negative: contact found before the blocks touch). Writes
PREFIX.csv (every frame of every run) and PREFIX.png (a trailing .png of -o is dropped).
"""
import argparse
import concurrent.futures
import csv
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from figures import read_run, run_smpm, save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "two_block_compression.toml"
SPEED, GAP = 0.9622, 7.5  # mm/ms of the piston; mm between the blocks (1.5 cells)
T_CONTACT = GAP / SPEED
THRESHOLD = -0.01  # MPa: the lower block's mean sigma_yy once it is pushed
METHODS = {
    "Δv < 0 (AG)": ["contact.0.detection=approaching"],
    "CP = 0.92 (AG)": ["contact.0.critical_separation=0.92"],
    "CP = 0.8 (AG)": [],
    "DF (AG)": ["contact.0.detection=DF"],
    "LR": ["contact.0.normal=LR", "contact.0.detection=LR"],
}


def placement(top):
    """Overrides putting the lower block's top (the contact plane) at y = `top` mm and the upper
    block 7.5 mm above it, 50 mm tall, pushed from its top."""
    upper = top + GAP
    return ["body.0.max=[40.0, %r]" % top, "body.1.min=[0.0, %r]" % upper,
            "body.1.max=[40.0, %r]" % (upper + 50), "grid.cells=[12, 28]",
            f'bc.3.wall.position="{upper + 50!r} - {SPEED}*t"']


def run(smpm, work, tag, sets):
    """(times, mean sigma_yy of the lower block) of every frame."""
    out = pathlib.Path(work) / (tag + ".h5")
    r, _ = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(sets)}: {r.stderr.strip()}")
    result = read_run(out)
    syy = []
    for k in range(len(result.times)):
        p = result.particles(k)
        syy.append(float(p["stress"][p["material"] == 0, 3].mean()))
    return np.asarray(result.times), np.array(syy)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--end", type=float, default=10.0, help="end time (ms)")
    figures.add_output(ap, "fig2b", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    places = {"grid line": 50.0, "mid cell": 52.5}
    todo = {(m, p): sets + placement(top) + [f"time.end={a.end!r}", "output.every=0.05"]
            for m, sets in METHODS.items() for p, top in places.items()}
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, f"r{i}", v)
                   for i, (k, v) in enumerate(todo.items())}
        try:
            res = {k: f.result() for k, f in futures.items()}
        except RuntimeError as e:
            sys.exit(f"fig2b.py: {e}")
    print(f"contact time t_c = {T_CONTACT:.3f} ms; first frame with mean sigma_yy < "
          f"{THRESHOLD} MPa, minus t_c (ms):")
    print(f"{'method':16s} {'grid line':>10s} {'mid cell':>10s}")
    found = {}
    for m in METHODS:
        cells = []
        for p in places:
            t, s = res[(m, p)]
            below = np.flatnonzero(s < THRESHOLD)
            found[(m, p)] = t[below[0]] - T_CONTACT if below.size else float("nan")
            cells.append(found[(m, p)])
        print(f"{m:16s} {cells[0]:10.2f} {cells[1]:10.2f}")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["method", "contact_plane", "t_ms", "sigma_yy_MPa", "detected_minus_tc_ms"])
        for (m, p), (t, s) in res.items():
            for ti, si in zip(t, s):
                w.writerow([m, p, f"{ti:.4g}", f"{si:.6g}", f"{found[(m, p)]:.4g}"])
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(8, 5))
    for i, m in enumerate(METHODS):
        for p, style in (("grid line", "-"), ("mid cell", "--")):
            t, s = res[(m, p)]
            ax.plot(t, s, style, color=f"C{i}", label=f"{m}, {p}")
    ax.axvline(T_CONTACT, color="k", lw=0.8, ls=":", label=f"contact time {T_CONTACT:.2f} ms")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("mean axial stress $\\sigma_{yy}$ of the lower block (MPa)")
    ax.set_title("Contact detection (contact 2020 Fig. 2B): solid on a grid line, dashed mid cell")
    ax.legend(fontsize="x-small", ncol=2)
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
