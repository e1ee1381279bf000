#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 12B: energy dissipation of FMPM(4) blended with FMPM(1) against α at C = 0.539.

    analysis/fig12b.py [--input examples/vibrating_bar.toml] [--build build/python]
                       [--courant 0.539] [--set section.key=value ...] [-o fig12b]

Runs the bar for α = 0, 0.1, …, 1 (five periods) with the Python module sparsempm (the run loop
of `smpm run`), or with `smpm run` (--smpm) when the module does not import or with --cli, and
writes PREFIX.csv and PREFIX.png (a trailing .png of -o is dropped). --set changes an input
entry of every run (--set time.end=80: one period).
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
import smpm_python  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def settings(args, alpha):
    """The input entries of the run at α (output.every: one stop, at the end), then --set's."""
    return {"step.velocity": "FMPM", "step.order": 4, "step.blend_alpha": alpha,
            "step.blend_every": 1, "time.courant": args.courant, "output.every": 400.0,
            **figures.set_values(args.sets)}


def loss_module(smpm, args, alpha):
    """Energy loss (%) of the run from the Python module: advance() is the loop of smpm run."""
    try:
        model = smpm.Model.from_toml(args.input, settings(args, alpha))
        r = smpm.Stepper(model.options).advance(model, model.end, model.courant, stop_every=400.0)
    except smpm.InputError as e:
        sys.exit(f"fig12b.py: {e}")
    except smpm.NumericalError:
        return float("nan")
    return 100 * (r.energy_start - r.energy_end) / r.energy_start


def loss_cli(args, alpha, out):
    """Energy loss (%) of the run by `smpm run`, from the series of its file."""
    cmd = [args.smpm, "run", args.input, "-o", str(out), "-q"]
    for key, value in settings(args, alpha).items():
        cmd += ["--set", f"{key}={value}"]
    if subprocess.run(cmd, capture_output=True, text=True).returncode != 0:
        return float("nan")
    total = figures.read_run(out).series["total"]
    return 100 * (total[0] - total[-1]) / total[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--input", default=str(ROOT / "examples" / "vibrating_bar.toml"))
    ap.add_argument("--courant", type=float, default=0.539)
    figures.add_sets(ap)
    figures.add_output(ap, "fig12b", "PREFIX.csv and PREFIX.png")
    smpm_python.add_arguments(ap)
    args = ap.parse_args()
    prefix = figures.output_prefix(args.out)
    smpm = smpm_python.sparsempm(args)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(11):
            alpha = i / 10
            if smpm:
                loss = loss_module(smpm, args, alpha)
            else:
                loss = loss_cli(args, alpha, pathlib.Path(tmp) / f"a{i}.h5")
            rows.append((alpha, loss))
            print(f"alpha = {alpha:.1f}: energy loss {loss:.3f}%", file=sys.stderr)
    table = prefix + ".csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["blend_alpha", "energy_loss_percent"])
        w.writerows(rows)
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in rows], [r[1] for r in rows], "-o")
    ax.set_xlabel("fraction of FMPM(4), $\\alpha$ (blended with FMPM(1))")
    ax.set_ylabel("energy lost at the end, $(E_0 - E)/E_0$ (%)")
    ax.set_title(f"Free-vibrating bar, $C$ = {args.courant} (FMPM 2026 Fig. 12B)")
    png = figures.save_figure(fig, prefix, report=False)
    print(f"{png} and {table} ({'sparsempm ' + smpm.__version__ if smpm else args.smpm})")


if __name__ == "__main__":
    main()
