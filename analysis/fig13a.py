#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 13A: the convergence metrics of dynamic FMPM against the pass ℓ.

One step in the middle of the block impact and of the shock.

    analysis/fig13a.py [--build build/python] [--order 40] [--set section.key=value ...]
                       [-o fig13a]

Each problem (examples/block_impact.toml; examples/shock_split_bar.toml in single material
mode) runs with FMPM(order) to half its end time; the next step is then taken twice from that
state, with the "means" and the "changes" metric of FMPM 2026 §3.4 and a limit of 0, so the
loop runs to the order and Stepper.fmpm_metrics holds the metric of every pass ℓ = 2 … order.
Writes PREFIX.csv and PREFIX.png (a trailing .png of -o is dropped). --set changes an input
entry of both problems (--set time.end=0.0002 for a short run: the step is then taken at half
of it). Uses the Python module (build it with scripts/test).
"""
import argparse
import csv
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from figures import save_figure  # noqa: E402
from smpm_python import add_arguments, sparsempm  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
PROBLEMS = {"block impact": ("block_impact.toml", {}),
            "shock": ("shock_split_bar.toml", {"contact.0.law": "single-field"})}


def metric_curves(smpm, problem, order, extra=None):
    """{metric: [metric at ℓ = 2 … order]} on the step after half the end time; `extra`: more
    overrides of the input, after the problem's own."""
    src, sets = PROBLEMS[problem]
    overrides = {**sets, "step.velocity": "FMPM", "step.order": order, **(extra or {})}
    model = smpm.Model.from_toml(str(ROOT / "examples" / src), overrides)
    stepper = smpm.Stepper(model.options)
    stepper.advance(model, 0.5 * model.end, model.courant)
    dt = smpm.stable_time_step(model, model.courant)
    curves = {}
    for metric in ("means", "changes"):
        options = model.options.copy()
        options.dynamic_metric = metric
        options.dynamic_limit = 0.0
        trial = model.copy()
        stepper = smpm.Stepper(options)
        stepper.step(trial, dt)
        curves[metric] = [float(x) for x in stepper.fmpm_metrics]
    return model.step, curves


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_arguments(ap)
    ap.add_argument("--order", type=int, default=40)
    figures.add_sets(ap)
    figures.add_output(ap, "fig13a", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    smpm = sparsempm(a)
    if smpm is None:
        sys.exit("fig13a.py needs the Python module sparsempm (build it with scripts/test)")
    rows = []
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for i, problem in enumerate(PROBLEMS):
        step, curves = metric_curves(smpm, problem, a.order, figures.set_values(a.sets))
        for metric, style in (("means", "-"), ("changes", "--")):
            values = curves[metric]
            ells = list(range(2, 2 + len(values)))
            rows += [[problem, step + 1, metric, ell, f"{v:.6e}"] for ell, v in zip(ells, values)]
            ax.semilogy(ells, values, style, color=f"C{i}", label=f"{problem}, {metric}")
        shown = sorted({ell for ell in (2, 5, 10, 20, a.order) if 2 <= ell <= a.order})
        print(f"{problem}, step {step + 1}: metric at ℓ = {', '.join(map(str, shown))}")
        for metric in ("means", "changes"):
            v = curves[metric]
            print(f"  {metric:8s} " + " ".join(f"{v[ell - 2]:9.3e}" for ell in shown
                                               if ell - 2 < len(v)))
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["problem", "step", "metric", "ell", "value"])
        w.writerows(rows)
    ax.set_xlabel("FMPM pass $\\ell$")
    ax.set_ylabel("convergence metric (dimensionless)")
    ax.set_title("Dynamic FMPM: metric of each pass (FMPM 2026 Fig. 13A)")
    ax.legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
