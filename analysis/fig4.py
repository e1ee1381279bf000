#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Figs. 4 and 5: a shock through a split nickel bar with stick and frictional contact.

    analysis/fig4.py [--smpm build/apps/smpm] [--jobs 2] [--set section.key=value ...] [-o fig4]

Runs examples/shock_split_bar.toml with `smpm run` for each case below, two at a time, and takes
the pressure along the bar at the end (the front near 34 mm, the wall at 46 mm): the particles'
p = -(sigma_xx + sigma_yy)/2 (the material has no shear stress) averaged in bins of one cell.
Fig. 4 is bonded stick contact on every shared node, which must reproduce single material mode,
by FLIP, FMPM(1), FMPM(2) and FMPM(k >= 4) by the Net and Evolving methods; Fig. 5 is frictional
contact (Coulomb, mu = 0.3, LR normals and d_LR: contact where the fields approach and touch) by
FMPM(4), FMPM(8), FMPM(16) Net and FMPM(4), FMPM(8) Evolving, and frictionless FMPM(8) Net (the
paper's text says its Fig. 5 used the frictionless law). Contact 2020 Fig. 7 is multimaterial XPIC(5) on
the bonded interface with and without the contact term of its Eq. (37).
For each case the table gives the plateau pressure behind the front (mean over 37-44 mm, against
the Rankine-Hugoniot 118.4 GPa), the front position (where p crosses half of it), and the
plateau's and the largest difference from single material mode by the same update, in % of the
plateau and of the Rankine-Hugoniot pressure. The legends say which curves coincide to plotting
precision (figures.coincidences), and name the reference lines: the Rankine-Hugoniot pressure
(dotted) and the interface of the two materials at 40 mm (dashed). Writes
PREFIX.csv (the profiles) and PREFIX.png (a trailing .png of -o is dropped). --set changes an
input entry of every run (--set time.end=0.5e-3 for a short run: the front is then near the
wall, and the plateau and front are blank where the profile does not reach them).
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
INPUT = ROOT / "examples" / "shock_split_bar.toml"
RH = 8.87e-3 * (np.sqrt(188000 / 8.87e-3) + 1.44 * 1840) * 1840 / 1000  # GPa
FMPM = ["step.velocity=FMPM"]
SINGLE = ["contact.0.law=single-field"]
FRICTION = ["contact.0.law=coulomb", "contact.0.friction=0.3", "contact.0.detection=LR",
            "contact.0.normal=LR"]
# The paper's discussion of Fig. 5 says it "used the frictionless contact law".
FRICTIONLESS = ["contact.0.law=frictionless", "contact.0.detection=LR", "contact.0.normal=LR"]
EVOLVING = ["contact.0.fmpm_method=evolving"]
XPIC5 = ["step.velocity=XPIC", "step.order=5"]
TERM = ['step.xpic_contact="term"']


def fmpm(k):
    return FMPM + [f"step.order={k}"]


# name: (figure, --set overrides, name of the single material reference)
CASES = {
    "single FLIP": (0, ["step.velocity=FLIP"] + SINGLE, None),
    "single FMPM(1)": (0, fmpm(1) + SINGLE, None),
    "single FMPM(2)": (0, fmpm(2) + SINGLE, None),
    "single FMPM(4)": (0, fmpm(4) + SINGLE, None),
    "single FMPM(8)": (0, fmpm(8) + SINGLE, None),
    "single FMPM(16)": (0, fmpm(16) + SINGLE, None),
    "stick FLIP": (4, ["step.velocity=FLIP"], "single FLIP"),
    "stick FMPM(1)": (4, fmpm(1), "single FMPM(1)"),
    "stick FMPM(2) Net": (4, fmpm(2), "single FMPM(2)"),
    "stick FMPM(2) Evolving": (4, fmpm(2) + EVOLVING, "single FMPM(2)"),
    "stick FMPM(4) Net": (4, fmpm(4), "single FMPM(4)"),
    "stick FMPM(4) Evolving": (4, fmpm(4) + EVOLVING, "single FMPM(4)"),
    "stick FMPM(8) Net": (4, fmpm(8), "single FMPM(8)"),
    "friction FMPM(4) Net": (5, fmpm(4) + FRICTION, "single FMPM(4)"),
    "friction FMPM(8) Net": (5, fmpm(8) + FRICTION, "single FMPM(8)"),
    "friction FMPM(16) Net": (5, fmpm(16) + FRICTION, "single FMPM(16)"),
    "frictionless FMPM(8) Net": (5, fmpm(8) + FRICTIONLESS, "single FMPM(8)"),
    "friction FMPM(4) Evolving": (5, fmpm(4) + FRICTION + EVOLVING, "single FMPM(4)"),
    "friction FMPM(8) Evolving": (5, fmpm(8) + FRICTION + EVOLVING, "single FMPM(8)"),
    "single XPIC(5)": (0, XPIC5 + SINGLE, None),
    "stick XPIC(5)": (7, XPIC5, "single XPIC(5)"),
    "single XPIC(5) Eq. 41": (0, XPIC5 + TERM + SINGLE, None),
    "stick XPIC(5) Eq. 37 term": (7, XPIC5 + TERM, "single XPIC(5) Eq. 41"),
    "stick XPIC(5) uncorrected": (7, XPIC5 + ['step.xpic_contact="none"'], "single XPIC(5) Eq. 41"),
}
BINS = np.arange(30.0, 47.0, 0.25)
INTERFACE = 40.0  # mm: where the bar is split into its two materials
# The reference lines of every panel, with their legend entries (after the curves').
RH_LABEL = f"Rankine–Hugoniot pressure ({RH:.1f} GPa)"
INTERFACE_LABEL = f"material interface ($x$ = {INTERFACE:g} mm)"
REFERENCE_LABELS = (RH_LABEL, INTERFACE_LABEL)


def run(smpm, work, name, sets):
    """Pressure (GPa) in the bins at the last frame, and the wall time; None if the run failed."""
    out = pathlib.Path(work) / (name.replace(" ", "_").replace("(", "").replace(")", "") + ".h5")
    r, seconds = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        return None, seconds, r.stderr.strip().splitlines()[-1]
    g = read_run(out).particles(-1)  # the last frame
    x = g["X"][:, 0]
    p = -(g["stress"][:, 0] + g["stress"][:, 3]) / 2 / 1000
    idx = np.digitize(x, BINS) - 1
    prof = np.array([p[idx == b].mean() if np.any(idx == b) else np.nan
                     for b in range(len(BINS) - 1)])
    return prof, seconds, ""


def summary(prof):
    centre = 0.5 * (BINS[:-1] + BINS[1:])
    plateau = np.nanmean(prof[(centre > 37) & (centre < 44)])
    above = np.nonzero(prof > 0.5 * RH)[0]
    if len(above) == 0 or above[0] == 0:  # no front inside the bins
        return plateau, np.nan
    k = above[0]
    front = np.interp(0.5 * RH, [prof[k - 1], prof[k]], [centre[k - 1], centre[k]])
    return plateau, front


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig4", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, k, v[1] + a.sets) for k, v in CASES.items()}
        results = {k: f.result() for k, f in futures.items()}
    print(f"Rankine-Hugoniot pressure {RH:.1f} GPa; the front should be near 34.2 mm")
    print(f"{'case':28s} {'plateau GPa':>11s} {'front mm':>9s} {'plateau vs single %':>20s} "
          f"{'max vs single %':>16s} {'run s':>6s}")
    rows = []
    for name, (fig, _, ref) in CASES.items():
        prof, secs, err = results[name]
        if prof is None:
            print(f"{name:28s} failed: {err}")
            continue
        plateau, front = summary(prof)
        diff = rel = ""
        if ref and results[ref][0] is not None:
            d = 100 * np.nanmax(np.abs(prof - results[ref][0])) / RH
            diff = f"{d:.3g}"
            rel = f"{100 * (plateau / summary(results[ref][0])[0] - 1):+.3f}"
        print(f"{name:28s} {plateau:11.2f} {front:9.2f} {rel:>20s} {diff:>16s} {secs:6.1f}")
        rows.append((name, fig, prof))
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "figure", "x_mm", "pressure_GPa"])
        centre = 0.5 * (BINS[:-1] + BINS[1:])
        for name, fig, prof in rows:
            for x, p in zip(centre, prof):
                w.writerow([name, fig, f"{x:.3f}", f"{p:.6g}"])
    plt = figures.style()
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5), sharey=True)
    centre = 0.5 * (BINS[:-1] + BINS[1:])
    for panel, ax in ((4, axes[0]), (5, axes[1]), (7, axes[2])):
        curves = {name: (centre, prof) for name, f, prof in rows if f == panel}
        same = figures.coincidences(curves)  # e.g. Net and Evolving under bonded stick
        for i, (name, (x, y)) in enumerate(curves.items()):
            if name in same:  # over the curve it coincides with: open markers, no line
                ax.plot(x, y, ls="none", marker="o", ms=3 + 1.5 * i, mfc="none", markevery=3,
                        color=f"C{i % 9}", label=f"{name} (coincides with {same[name]})")
            else:
                ax.plot(x, y, lw=1, color=f"C{i % 9}", label=name)
    for ax, title in zip(axes, ["Fig. 4: stick contact", "Fig. 5: frictional contact",
                                "contact 2020 Fig. 7: multimaterial XPIC(5)"]):
        ax.axhline(RH, color="k", ls=":", lw=0.8, label=RH_LABEL)
        ax.axvline(INTERFACE, color="k", ls="--", lw=0.6, label=INTERFACE_LABEL)
        ax.set_title(title)
        ax.set_xlabel("$x$ (mm)")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("pressure $p$ (GPa)")
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
