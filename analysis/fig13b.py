#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 13B: energy lost and cost of dynamic FMPM(20) against its convergence limit,
on the two-block impact, beside FLIP, FMPM(2) and FMPM(20).

    analysis/fig13b.py [--smpm build/apps/smpm] [--limits 0.1,...] [--jobs 1]
                       [--set section.key=value ...] [-o fig13b]

Runs examples/block_impact.toml with FLIP, FMPM(2), FMPM(20) and dynamic FMPM(20) (FMPM 2026
§3.4) for each limit and both metrics ("means", "changes"), one thread each. Energy lost is
-(E_end - E_0)/E_0 in % of the total energy (the example's claim: FLIP 1.84%, FMPM(20) 0.20%).
The cost is given twice: the mean FMPM order the loop reached (the products with m~ per step,
deterministic; drawn) and the run's wall time over FLIP's (the paper's "calculation time",
measured one run at a time with --jobs 1; in the table only, as a shared machine moves it). Writes PREFIX.csv
and PREFIX.png (a trailing .png of -o is dropped). --set changes an input entry of every run
(--set time.end=0.0002 for a short run).
"""
import argparse
import concurrent.futures
import csv
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402
from figures import read_run, run_smpm, save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUT = ROOT / "examples" / "block_impact.toml"
REFERENCES = {"FLIP": ["step.velocity=FLIP"],
              "FMPM(2)": ["step.velocity=FMPM", "step.order=2"],
              "FMPM(20)": ["step.velocity=FMPM", "step.order=20"]}
METRICS = ("means", "changes")


def run(smpm, work, tag, sets):
    """(energy lost in %, wall seconds, mean FMPM order) of one run of the block impact."""
    out = pathlib.Path(work) / (tag + ".h5")
    r, seconds = run_smpm(smpm, INPUT, out, sets)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(sets)}: {r.stderr.strip()}")
    s = read_run(out).series
    total = s["total"]
    return -100 * (total[-1] - total[0]) / total[0], seconds, float(s["fmpm_order"][1:].mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--limits", default="0.1,0.03,0.01,0.003,0.001,0.0003,0.0001")
    ap.add_argument("--jobs", type=int, default=1)
    figures.add_sets(ap)
    figures.add_output(ap, "fig13b", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    limits = [float(x) for x in a.limits.split(",")]
    todo = {(name, "", 0.0): sets for name, sets in REFERENCES.items()}
    for m in METRICS:
        for lim in limits:
            todo[("dynamic FMPM(20)", m, lim)] = REFERENCES["FMPM(20)"] + [
                f"step.dynamic_metric={m}", f"step.dynamic_limit={lim}"]
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(run, a.smpm, work, f"r{i}", v + a.sets)
                   for i, (k, v) in enumerate(todo.items())}
        try:
            res = {k: f.result() for k, f in futures.items()}
        except RuntimeError as e:
            sys.exit(f"fig13b.py: {e}")
    flip_seconds = res[("FLIP", "", 0.0)][1]
    rows = [[name, metric, f"{lim:g}" if metric else "", f"{lost:.4f}", f"{sec:.3f}",
             f"{sec / flip_seconds:.3f}", f"{order:.3f}"]
            for (name, metric, lim), (lost, sec, order) in res.items()]
    print("block impact: energy lost (%), wall time relative to FLIP, mean FMPM order")
    for r in rows:
        label = r[0] + (f" {r[1]} {r[2]}" if r[1] else "")
        print(f"{label:34s} {float(r[3]):8.3f} {float(r[5]):8.2f} {float(r[6]):8.2f}")
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["velocity", "metric", "limit", "energy_lost_percent", "seconds",
                    "time_relative_to_flip", "mean_order"])
        w.writerows(rows)
    plt = figures.style()
    fig, (ax, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for m, style in (("means", "-"), ("changes", "--")):
        dyn = [res[("dynamic FMPM(20)", m, lim)] for lim in limits]
        ax.semilogx(limits, [d[0] for d in dyn], style, marker="o", color="k",
                    label=f"dynamic FMPM(20), {m}")
        right.semilogx(limits, [d[2] for d in dyn], style, marker="s", color="C0",
                       label=f"dynamic FMPM(20), {m}")
    for i, name in enumerate(REFERENCES):
        lost, _, order = res[(name, "", 0.0)]
        ax.axhline(lost, color=f"C{i + 2}", lw=1, ls=":", label=name)
        if name != "FLIP":
            right.axhline(order, color=f"C{i + 2}", lw=1, ls=":", label=name)
    for axis in (ax, right):
        axis.set_xlabel("convergence limit of dynamic FMPM (dimensionless)")
        axis.legend(fontsize="small")
    ax.set_ylabel("energy lost $-\\Delta E / E_0$ (%)")
    right.set_ylabel("mean FMPM order: products with $\\tilde m$ per step (count)")
    ax.set_title("Fig. 13B: energy lost, block impact")
    right.set_title("Fig. 13B: cost of the loop")
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
