#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Kinetic, strain and total energy of a run against time, and the change of the total.

    analysis/plot_energy.py run.h5 [--units input|mm-ms-g|SI] [-o PREFIX]

The labels' units are the run file's (output.units) unless --units names others.

Reads /series/{t, kinetic, strain, total} of a file written by `smpm run` and writes PREFIX.png
(default: the run's name with _energy: run_energy.png; a trailing .png of -o is dropped): the
energies above, and below them the relative change of the total, (E(t) − E(0))/E(0) in %, so
that a change of 0.04% is visible (the absolute change E(t) − E(0) when E(0) = 0). Prints the
steps and the total energy at the start and the end with its change in percent ("n/a" when
E(0) = 0, with the absolute change).
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import figures  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="HDF5 file written by smpm run")
    figures.add_output(ap, None, "PREFIX.png (default: the run's name with _energy)")
    figures.add_units(ap)
    args = ap.parse_args()
    try:
        run = figures.read_run(args.run)
    except OSError as e:
        sys.exit(f"plot_energy.py: {args.run}: cannot open ({e})")
    except ValueError as e:  # an HDF5 file that is no run file
        sys.exit(f"plot_energy.py: {e}")
    t, kin, strain, total = (run.series[k] for k in ("t", "kinetic", "strain", "total"))
    status = run.status
    default = pathlib.Path(args.run).with_suffix("").as_posix() + "_energy"
    prefix = figures.output_prefix(args.out or default)
    unit = figures.UNITS[figures.units_of(args.units, run)]
    plt = figures.style()
    fig, (ax, dax) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, height_ratios=[2, 1])
    ax.plot(t, kin, label="kinetic $K$")
    ax.plot(t, strain, label="strain $W$")
    ax.plot(t, total, label="total $E = K + W$", color="k")
    ax.set_ylabel(f"energy ({unit['energy']})")
    ax.set_title(f"{pathlib.Path(args.run).name} ({status})")
    ax.legend(loc="center right")
    e0 = total[0]
    if e0 != 0:
        dax.plot(t, 100 * (total - e0) / abs(e0), color="k")
        dax.set_ylabel("$(E - E_0)/E_0$ (%)")
        change = f"{100 * (total[-1] - e0) / abs(e0):+.4f}%"
    else:  # no relative change of nothing: the absolute one
        dax.plot(t, total - e0, color="k")
        dax.set_ylabel(f"$E - E_0$ ({unit['energy']})")
        change = f"n/a; change {total[-1] - e0:+.6g}"
    dax.axhline(0, color="gray", lw=0.8)
    dax.plot(t[-1:], dax.lines[0].get_ydata()[-1:], "o", color="k", ms=4)
    dax.set_title(f"change of the total energy: {change} at t = {t[-1]:g}")
    dax.set_xlabel(f"time $t$ ({unit['time']})")
    png = figures.save_figure(fig, prefix, report=False)
    print(f"{png}: {len(t) - 1} steps, total energy {e0:.6g} -> {total[-1]:.6g} ({change})")


if __name__ == "__main__":
    main()
