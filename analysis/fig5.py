#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Contact 2020 Fig. 5: two identical blocks in uniaxial compression, multimaterial MPM with
contact against single material mode.

    analysis/fig5.py [--smpm build/apps/smpm] [--jobs 2] [--set section.key=value ...] [-o fig5]

Runs examples/two_block_compression.toml with `smpm run` in single material mode (the two
materials in one velocity field, law = "single-field") and in multimaterial mode for each
contact normal and detection method available, two runs at a time. For each frame (every 1%
strain) it takes the mean axial stress of the particles, sigma_yy, and reports the paper's
proportional error (MM - SMM)/SMM in % at 1, 5, 10 and 20% strain. Writes PREFIX.csv (every
frame) and PREFIX.png (error against strain, as Fig. 5A; a trailing .png of -o is dropped).
Several methods give the same curve: the legend says which coincide, "(coincides with ...)",
found from the data (figures.coincidences: every frame within 0.2% of the plot's range;
printed too). --set
changes an input entry of every run (--set time.end=2.1: to 2% strain).
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
from figures import read_run, run_smpm  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "two_block_compression.toml"
RATE = 0.9622 / 100.0  # axial strain per ms (wall speed / column height)
METHODS = {
    "single material": ["contact.0.law=single-field"],
    "approaching only (AG)": ["contact.0.detection=approaching"],
    "CP = 0.8 (AG)": [],
    "CP = 0.92 (AG)": ["contact.0.critical_separation=0.92"],
    "DF (AG)": ["contact.0.detection=DF"],
    "approaching, SN": ["contact.0.detection=approaching", "contact.0.normal=specified",
                        "contact.0.direction=[0.0, 1.0]"],
    "CP = 0.8, SN": ["contact.0.normal=specified", "contact.0.direction=[0.0, 1.0]"],
    "DF + SN": ["contact.0.detection=DF", "contact.0.normal=specified",
                "contact.0.direction=[0.0, 1.0]"],
    "LR normal, d_LR": ["contact.0.normal=LR", "contact.0.detection=LR"],
    "LR normal, approaching": ["contact.0.normal=LR", "contact.0.detection=approaching"],
    "LR Once": ["contact.0.normal=LR", "contact.0.detection=LR",
                "step.contact_corrections=once"],
}
REPORT = [1, 5, 10, 20]  # strains (%) of the table


def run(smpm, work, name, sets):
    """(strain in %, mean sigma_yy) of every frame of one run, and its wall time."""
    out = pathlib.Path(work) / (name.replace(" ", "_").replace("(", "").replace(")", "")
                                .replace("=", "").replace(",", "") + ".h5")
    r, seconds = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        raise RuntimeError(f"{name}: {r.stderr.strip()}")
    result = read_run(out)
    strain = 100 * RATE * result.times
    syy = np.array([result.particles(k)["stress"][:, 3].mean()
                    for k in range(len(result.frames))])
    return strain, syy, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig5", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    prefix = figures.output_prefix(a.out)
    results = {}
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, k, v + a.sets) for k, v in METHODS.items()}
        for k, fut in futures.items():
            results[k] = fut.result()
    strain, ref, _ = results["single material"]
    with open(prefix + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["method", "strain_percent", "sigma_yy", "error_percent", "seconds"])
        for k, (s, syy, secs) in results.items():
            for e, v, r0 in zip(s, syy, ref):
                err = 100 * (v - r0) / r0 if r0 != 0 else 0.0
                w.writerow([k, f"{e:.4g}", f"{v:.6g}", f"{err:.4g}", f"{secs:.2f}"])
    print("error (MM - SMM)/SMM in % of the mean axial stress at strain:")
    print(f"{'method':26s}" + "".join(f"{p:>9d}%" for p in REPORT) + "   run (s)")
    for k, (s, syy, secs) in results.items():
        row = []
        for p in REPORT:
            i = int(np.argmin(abs(s - p)))
            row.append(100 * (syy[i] - ref[i]) / ref[i])
        print(f"{k:26s}" + "".join(f"{x:10.3f}" for x in row) + f"{secs:10.1f}")
    ok = ref != 0
    curves = {k: (s[ok], 100 * (syy[ok] - ref[ok]) / ref[ok])
              for k, (s, syy, _) in results.items() if k != "single material"}
    same = figures.coincidences(curves)
    for k, other in same.items():
        print(f"coincides to plotting precision: {k} with {other}")
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(11, 4.8))
    repeats = {}
    for i, (k, (x, y)) in enumerate(curves.items()):
        colour = f"C{i % 9}"
        if k in same:  # drawn over the curve it coincides with: open markers, growing, no line
            n = repeats[same[k]] = repeats.get(same[k], 0) + 1
            ax.plot(x, y, ls="none", marker="o", ms=3 + 2.5 * n, mfc="none", mew=1.2,
                    color=colour, label=f"{k} (coincides with {same[k]})")
        else:
            ax.plot(x, y, marker="o", ms=3, color=colour, label=k)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xlabel("axial strain (%)")
    ax.set_ylabel("mean $\\sigma_{yy}$: (MM $-$ SMM)/SMM (%)")
    ax.set_title("Two blocks in uniaxial compression (contact 2020 Fig. 5)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figures.save_figure(fig, prefix, tables=[prefix + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
