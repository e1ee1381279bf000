#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Contact 2020 Fig. 4: three materials meeting at a node, compressed by 5%, by the lumping
method (Eq. 50) against single material mode.

    analysis/three_materials.py [--smpm build/apps/smpm] [--set section.key=value ...]
                                [-o three_materials]

Runs examples/three_materials.toml as it is (frictionless contact, LR normals and d_LR between
every pair: lumping at the nodes of three materials), with AG normals, with left and right in one
velocity field (two fields: no node of three), and with all three in one field (single material
mode), by replacing its [[contact]] table. Prints the error of the mean axial stress against
single material mode at each frame (1-5% strain) and the x-momentum at the end (0 when contact
conserves momentum), and writes PREFIX.csv and PREFIX.png (the error against strain, and the
particles' sigma_yy at the end for the lumped and the single material runs; a trailing .png of
-o is dropped). --set changes an input entry of every run (--set time.end=0.02 for a short run).
"""
import argparse
import csv
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from figures import read_run, run_smpm, save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "three_materials.toml"
ONE_FIELD = '[[contact]]\nmaterials = ["{a}", "{b}"]\nlaw = "single-field"\n'
EVERY_PAIR = '[[contact]]\nlaw = "frictionless"\nnormal = "{normal}"\ndetection = "LR"\n'
VARIANTS = {
    "single material": ONE_FIELD.format(a="left", b="right") + ONE_FIELD.format(a="right", b="top"),
    "lumping, LR": EVERY_PAIR.format(normal="LR"),
    "lumping, AG": EVERY_PAIR.format(normal="AG"),
    "two fields (left = right), LR": ONE_FIELD.format(a="left", b="right")
    + EVERY_PAIR.format(normal="LR"),
}
RATE = 0.9622 / 20.0 * 100  # % strain per ms (wall speed over the 20 mm block)


def run(smpm, work, name, contact, sets=()):
    """Mean sigma_yy per frame, the strain of each frame, the final particles and x-momentum."""
    text = INPUT.read_text()
    start = text.index("\n[[contact]]") + 1
    end = text.index("\n[[bc]]", start) + 1
    stem = name.split(",")[0].replace(" ", "_").replace("(", "").replace(")", "").replace("=", "")
    src = pathlib.Path(work) / (stem + name.count("AG") * "_ag" + ".toml")
    src.write_text(text[:start] + contact + "\n" + text[end:])
    out = src.with_suffix(".h5")
    r, _ = run_smpm(smpm, src, out, sets)
    if r.returncode != 0:
        raise RuntimeError(f"{name}: {r.stderr.strip()}")
    result = read_run(out)  # its frames after frame 0 (no strain yet)
    strain = RATE * result.times[1:]
    syy = np.array([result.particles(k)["stress"][:, 3].mean()
                    for k in range(1, len(result.frames))])
    last = result.particles(-1)
    return strain, syy, last["X"], last["stress"][:, 3], result.series["momentum"][-1, 0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    figures.add_sets(ap)
    figures.add_output(ap, "three_materials", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    with tempfile.TemporaryDirectory() as work:
        res = {k: run(a.smpm, work, k, v, a.sets) for k, v in VARIANTS.items()}
    strain, ref = res["single material"][0], res["single material"][1]
    print("error (MM - SMM)/SMM in % of the mean axial stress; x-momentum at the end (g mm/ms)")
    print(f"{'variant':32s} " + " ".join(f"{s:6.1f}%" for s in strain) + "  x-momentum")
    rows = []
    for name, (s, syy, _, _, px) in res.items():
        err = 100 * (syy / ref - 1)
        print(f"{name:32s} " + " ".join(f"{e:7.3f}" for e in err) + f"  {px:10.2e}")
        rows += [[name, f"{st:.3f}", f"{v:.6g}", f"{e:.6g}"] for st, v, e in zip(s, syy, err)]
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["variant", "strain_percent", "mean_sigma_yy", "error_percent"])
        w.writerows(rows)
    plt = figures.style()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for name, (s, syy, _, _, _) in res.items():
        if name != "single material":
            axes[0].plot(s, 100 * (syy / ref - 1), "o-", label=name)
    axes[0].set_title("error against single material mode")
    axes[0].set_xlabel("axial strain (%)")
    axes[0].set_ylabel(r"mean $\sigma_{yy}$: (MM $-$ SMM)/SMM (%)")
    axes[0].legend()
    lo = min(res[k][3].min() for k in ("lumping, LR", "single material"))
    for ax, name in zip(axes[1:], ("lumping, LR", "single material")):
        X, syy = res[name][2], res[name][3]
        sc = ax.scatter(X[:, 0], X[:, 1], c=syy, s=6, vmin=lo, vmax=0, cmap="viridis")
        ax.set_aspect("equal")
        ax.set_title(f"$\\sigma_{{yy}}$ at {res[name][0][-1]:.1f}% strain: {name}")
        ax.grid(False)
        ax.set_xlabel("$x$ (mm)")
        ax.set_ylabel("$y$ (mm)")
    fig.colorbar(sc, ax=axes[2]).set_label(r"$\sigma_{yy}$ (MPa)")
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
