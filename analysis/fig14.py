#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""FMPM 2026 Fig. 14: the mean order dynamic FMPM(20) reaches against its convergence limit, on
the two-block impact and on the shock.

    analysis/fig14.py [--smpm build/apps/smpm] [--limits 0.1,...] [--jobs 2]
                      [--set section.key=value ...] [-o fig14]

Runs examples/block_impact.toml and examples/shock_split_bar.toml (single material mode) with
dynamic FMPM(20) (FMPM 2026 §3.4) for each limit and both metrics ("means", "changes"), and
averages the order the loop reached over the steps (the series' fmpm_order). Writes PREFIX.csv
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
PROBLEMS = {"block impact": ("block_impact.toml", []),
            "shock": ("shock_split_bar.toml", ["contact.0.law=single-field"])}


def mean_order(smpm, work, tag, problem, metric, limit, extra=()):
    """The mean order dynamic FMPM(20) reached over the steps of one run."""
    src, sets = PROBLEMS[problem]
    out = pathlib.Path(work) / (tag + ".h5")
    r, _ = run_smpm(smpm, ROOT / "examples" / src, out,
                    sets + ["step.velocity=FMPM", "step.order=20", f"step.dynamic_metric={metric}",
                            f"step.dynamic_limit={limit}"] + list(extra))
    if r.returncode != 0:
        raise RuntimeError(f"{problem} {metric} {limit}: {r.stderr.strip()}")
    return float(read_run(out).series["fmpm_order"][1:].mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smpm", default=str(ROOT / "build" / "apps" / "smpm"))
    ap.add_argument("--limits", default="0.1,0.03,0.01,0.003,0.001,0.0003,0.0001")
    ap.add_argument("--jobs", type=int, default=2)
    figures.add_sets(ap)
    figures.add_output(ap, "fig14", "PREFIX.csv and PREFIX.png")
    a = ap.parse_args()
    a.out = figures.output_prefix(a.out)
    limits = [float(x) for x in a.limits.split(",")]
    keys = [(p, m, lim) for p in PROBLEMS for m in ("means", "changes") for lim in limits]
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        futures = {k: pool.submit(mean_order, a.smpm, work, f"r{i}", *k, a.sets)
                   for i, k in enumerate(keys)}
        res = {k: f.result() for k, f in futures.items()}
    print("mean FMPM order reached by dynamic FMPM(20)")
    print(f"{'limit':>8s} " + " ".join(f"{p + ' ' + m:>20s}" for p in PROBLEMS
                                         for m in ("means", "changes")))
    for lim in limits:
        print(f"{lim:8.4g} " + " ".join(f"{res[(p, m, lim)]:20.2f}" for p in PROBLEMS
                                          for m in ("means", "changes")))
    with open(a.out + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["problem", "metric", "limit", "mean_order"])
        w.writerows([[p, m, lim, f"{v:.4f}"] for (p, m, lim), v in res.items()])
    plt = figures.style()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for i, p in enumerate(PROBLEMS):
        for m, style in (("means", "-"), ("changes", "--")):
            ax.semilogx(limits, [res[(p, m, lim)] for lim in limits], style, marker="o",
                        color=f"C{i}", label=f"{p}, {m}")
    ax.set_xlabel("convergence limit of dynamic FMPM (dimensionless)")
    ax.set_ylabel("mean FMPM order reached")
    ax.set_title("Dynamic FMPM(20) (FMPM 2026 Fig. 14)")
    ax.legend()
    save_figure(fig, a.out, tables=[a.out + ".csv"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
