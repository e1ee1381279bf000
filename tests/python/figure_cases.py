# SPDX-License-Identifier: BSD-3-Clause
"""The tiny case each figure script of analysis/ is drawn on (tests/python/test_figures.py), and
the environment of the scripts and commands the figure and tour tests run.

Each script runs as a user runs it (its own /usr/bin/python3 process, from a scratch directory),
two at a time with one thread each, on a case made small by its options (--set time.end=...,
fewer orders, cells or objects).
"""
import os
import pathlib
import subprocess

import sparsempm as smpm

from conftest import BAR, SOURCE
from conftest import SMPM as SMPM_NAME

BUILD = pathlib.Path(smpm.__file__).resolve().parents[1]  # the directory holding the package
# The scripts run in scratch directories: a path to smpm is made absolute.
SMPM = str(pathlib.Path(SMPM_NAME).resolve()) if os.sep in SMPM_NAME else SMPM_NAME
EXAMPLES = SOURCE / "examples"


def env(dump=None):
    """The environment of every process here: one thread each (two run at a time)."""
    e = dict(os.environ, SMPM_THREADS="1", OMP_NUM_THREADS="1")
    if dump:
        e["SMPM_FIGURE_DUMP"] = str(dump)
    return e


def run_smpm(*args, cwd):
    """`smpm args...` run in `cwd`; its standard output (it must succeed)."""
    r = subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                       env=env(), timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout


# Each case: the script's arguments, after what it needs is prepared in its directory `w`, the
# PNGs it must write and the tables (CSV) it must write.

def case_plot_energy(w):
    (w / "smpm.out").write_text(run_smpm("run", BAR, "-o", w / "bar.h5", cwd=w))
    return [w / "bar.h5", "-o", w / "energy.png"], ["energy"], []  # -o with .png, as before


def case_plot_particles(w):
    run_smpm("run", EXAMPLES / "two_disks.toml", "-o", w / "disks.h5", "-q", "--set",
             "time.end=0.3", cwd=w)
    return ([w / "disks.h5", "--frame", "2", "--field", "stress_xx", "-o", w / "particles"],
            ["particles"], [])


def case_rho_map(w):  # the default Courant number
    return ["--smpm", SMPM, "--build", BUILD, "--input", BAR, "-o", w / "rho_map"], \
        ["rho_map"], ["rho_map"]


def case_fig12b(w):
    return ["--smpm", SMPM, "--build", BUILD, "--input", BAR, "--set", "time.end=80", "-o",
            w / "fig12b"], ["fig12b"], ["fig12b"]


def case_fig12a(w):
    # The rows scripts/run draws (FLIP, FMPM(k), both blends, periodic, exact) over one period.
    common = [BAR, "--order", "1,4", "--set", "time.end=80", "-q"]
    run_smpm("stability", *common, "--shifts", "1", "--method", "both", "-o", w / "st.csv", cwd=w)
    run_smpm("stability", *common, "--method", "simulation", "--max-energy-change", "0.001",
             "-o", w / "low.csv", cwd=w)
    return [w / "st.csv", "--low-dissipation", w / "low.csv", "-o", w / "fig12a.png"], \
        ["fig12a"], []


def case_fig12_gradient(w):
    # The three transfers on the bar (FLIP, FMPM(1), FMPM(4) and its blend with FMPM(1)) and on
    # the plate (FLIP, FMPM(4)), over short runs.
    plate = EXAMPLES / "vibrating_plate.toml"
    args = []
    for name, toml, extra in (("bar", BAR, ["--order", "1,4", "--blend-every", "1",
                                            "--set", "time.end=80"]),
                              ("plate", plate, ["--order", "4", "--blend-alpha", "none",
                                                "--set", "time.end=20"])):
        tables = []
        for transfer in ("standard", "velocity_gradient", "apic"):
            out = w / f"{name}_{transfer}.csv"
            run_smpm("stability", toml, *extra, "--shifts", "1", "--method", "both",
                     "--periodic-cx", "none", "--no-exact", "-q", "--set",
                     f"step.transfer={transfer}", "-o", out, cwd=w)
            tables.append(out)
        args += ["--problem", name, *tables]
    return [*args, "-o", w / "fig12_gradient.png"], ["fig12_gradient"], ["fig12_gradient"]


def case_truncation(w):
    run_smpm("spectrum", BAR, "-o", w / "spectrum.csv", cwd=w)
    return [w / "spectrum.csv", "-o", w / "truncation"], ["truncation"], []


def case_fig3(w):
    return ["--smpm", SMPM, "--jobs", "1", "--orders", "4", "--depths", "1,2", "--set",
            "time.end=0.5", "--set", "output.every=0.5", "-o", w / "fig3"], \
        ["fig3a", "fig3b"], ["fig3"]


def case_fig4(w):
    return ["--smpm", SMPM, "--jobs", "1", "--set", "time.end=1.5e-4", "-o", w / "fig4"], \
        ["fig4"], ["fig4"]


def case_fig5(w):  # to 2% strain: two frames
    return ["--smpm", SMPM, "--jobs", "1", "--set", "time.end=2.1", "-o", w / "fig5"], \
        ["fig5"], ["fig5"]


def case_fig8(w):
    return ["--smpm", SMPM, "--jobs", "1", "--cell", "4", "--set", "time.end=0.02", "-o",
            w / "fig8"], ["fig8"], ["fig8"]


def case_fig9(w):
    return ["--smpm", SMPM, "--jobs", "1", "--cell", "4", "--set", "time.end=0.02", "-o",
            w / "fig9"], ["fig9"], ["fig9"]


def case_buzzi(w):
    return ["--smpm", SMPM, "-o", w / "buzzi"], ["buzzi"], ["buzzi"]


def case_fig2b(w):
    return ["--smpm", SMPM, "--end", "8.5", "-o", w / "fig2b"], ["fig2b"], ["fig2b"]


def case_fig6(w):
    return ["--build", BUILD, "-o", w / "fig6"], ["fig6"], ["fig6"]


def case_fig7(w):
    return ["--smpm", SMPM, "--cell", "4", "--times", "0.01,0.02", "--set", "time.end=0.02",
            "-o", w / "fig7"], ["fig7"], ["fig7"]


def case_fig10(w):
    return ["--smpm", SMPM, "--jobs", "1", "--cell", "4", "--set", "time.end=0.02", "-o",
            w / "fig10"], ["fig10"], ["fig10"]


def case_fig11(w):
    return ["--smpm", SMPM, "--jobs", "1", "--cells", "4", "--courants", "0.4", "--cell-b", "4",
            "--set", "time.end=0.02", "-o", w / "fig11"], ["fig11"], ["fig11"]


def case_fig13b(w):
    return ["--smpm", SMPM, "--limits", "0.01,0.0001", "--set", "time.end=0.0002", "-o",
            w / "fig13b"], ["fig13b"], ["fig13b"]


def case_fig13a(w):
    return ["--build", BUILD, "--order", "5", "--set", "time.end=0.0002", "-o", w / "fig13a"], \
        ["fig13a"], ["fig13a"]


def case_fig14(w):
    return ["--smpm", SMPM, "--jobs", "1", "--limits", "0.01,0.001", "--set", "time.end=0.0002",
            "-o", w / "fig14"], ["fig14"], ["fig14"]


def case_compaction(w):
    return ["--smpm", SMPM, "--jobs", "1", "--objects", "3", "--set", "time.end=0.1", "-o",
            w / "compaction"], ["compaction"], ["compaction"]


def case_compaction_paper(w):
    return ["--smpm", SMPM, "--jobs", "1", "--scale", "14", "--compaction", "0.05", "-o",
            w / "compaction_paper"], ["compaction_paper"], ["compaction_paper"]


def case_three_materials(w):
    return ["--smpm", SMPM, "--set", "time.end=0.2", "-o", w / "three_materials"], \
        ["three_materials"], ["three_materials"]


def case_plastic_bar(w):  # the whole example: 0.3 s
    return ["--smpm", SMPM, "-o", w / "plastic_bar"], ["plastic_bar"], ["plastic_bar"]


def case_polynomials(w):  # two orders, one shift, a fifth of the runs
    return ["--smpm", SMPM, "--build", BUILD, "--orders", "2,4", "--shifts", "1", "--jobs", "1",
            "--set", "time.end=20", "-o", w / "polynomials"], \
        ["polynomials", "polynomials_residual"], ["polynomials"]


def case_df_fit(w):
    return ["-o", w / "df_fit.png"], ["df_fit"], ["df_fit"]


# Longest first, so that two workers finish together.
CASES = {"fig4.py": case_fig4, "fig5.py": case_fig5, "fig9.py": case_fig9,
         "fig3.py": case_fig3, "compaction.py": case_compaction, "rho_map.py": case_rho_map,
         "compaction_paper.py": case_compaction_paper,
         "fig12a.py": case_fig12a, "fig12_gradient.py": case_fig12_gradient,
         "fig8.py": case_fig8, "fig13a.py": case_fig13a, "fig13b.py": case_fig13b,
         "fig11.py": case_fig11, "fig14.py": case_fig14, "three_materials.py": case_three_materials,
         "fig12b.py": case_fig12b, "plot_particles.py": case_plot_particles,
         "plot_energy.py": case_plot_energy, "truncation.py": case_truncation,
         "df_fit.py": case_df_fit, "buzzi.py": case_buzzi, "fig2b.py": case_fig2b, "fig6.py": case_fig6, "fig7.py": case_fig7, "fig10.py": case_fig10,
         "plastic_bar.py": case_plastic_bar, "polynomials.py": case_polynomials}
