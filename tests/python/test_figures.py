# SPDX-License-Identifier: BSD-3-Clause
"""Every figure script of analysis/ draws its figure on a tiny case (tests/python/figure_cases.py),
and figures.py, the scripts' shared code, keeps them to one style and one reader of run files.

figures.save_figure refuses a figure drawn without the shared style or with an axis or colour
bar that has no label, so a zero exit status and the PNG are the first check. save_figure also
pickles each figure here (SMPM_FIGURE_DUMP), and the tests open it through matplotlib: every axis
is labelled (with a unit, or named as a dimensionless quantity), the legends say what the data
say, and each script's table has its rows and columns. The README's first run is test_tour.py's.
"""
import concurrent.futures
import dataclasses
import os
import pathlib
import pickle
import re
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import sparsempm as smpm

from conftest import BAR, SOURCE
from figure_cases import CASES, env, run_smpm

import matplotlib
matplotlib.use("Agg")
from matplotlib.legend import Legend  # noqa: E402

ANALYSIS = SOURCE / "analysis"
sys.path.insert(0, str(ANALYSIS))
import figures  # noqa: E402

PNG = b"\x89PNG\r\n\x1a\n"
# Scripts of analysis/ that draw no matplotlib figure: helpers, paraview_view.py, which
# ParaView draws under pvbatch (with a display), and ghost_nodes.py, a table of the DMDA's
# partition checked against PETSc itself by the ctest petsc.ghost_nodes_partition.
HELPERS = {"figures.py", "disks.py", "smpm_python.py", "paraview_view.py", "ghost_nodes.py"}


def rows(path):
    """The rows of a CSV table (lines starting with # left out), by the one reader of the tables
    (sparsempm.read_table: the columns' current names, also from a table of the earlier ones)."""
    with open(path) as f:
        return smpm.read_table([line for line in f if not line.startswith("#")])


@dataclasses.dataclass
class Render:
    """What one script did: exit status, output, its directory, PNGs, tables and figures."""
    returncode: int
    stdout: str
    stderr: str
    seconds: float
    dir: pathlib.Path
    pngs: list
    tables: list
    figures: list

    def figure(self, i=0):
        return self.figures[i]


def render(name, root):
    """Prepares the case of script `name` and runs the script; what it did (a failure to
    prepare the case is reported as the script's failure, for that case alone)."""
    w = root / name.removesuffix(".py")
    w.mkdir()
    start = time.time()
    try:
        args, pngs, tables = CASES[name](w)
    except (AssertionError, OSError, subprocess.SubprocessError) as e:
        return Render(-1, "", f"preparing the case: {e!r}", time.time() - start, w, [], [], [])
    r = subprocess.run(["/usr/bin/python3", ANALYSIS / name, *map(str, args)], capture_output=True,
                       text=True, cwd=w, env=env(dump=w), timeout=300)
    figs = []
    for p in pngs:
        dump = w / (p + ".pickle")
        if dump.exists():
            with open(dump, "rb") as f:
                figs.append(pickle.load(f))
    return Render(r.returncode, r.stdout, r.stderr, time.time() - start, w,
                  [w / (p + ".png") for p in pngs], [w / (t + ".csv") for t in tables], figs)


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    """Every case, rendered two at a time."""
    root = tmp_path_factory.mktemp("figures")
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        futures = {name: pool.submit(render, name, root) for name in CASES}
        done = {name: f.result() for name, f in futures.items()}
    print("\n" + "\n".join(f"{n}: {r.seconds:.1f} s" for n, r in done.items()))
    return done


def legend_texts(ax):
    """The entries of every legend of `ax` (a panel may have several)."""
    return [t.get_text() for a in ax.get_children() if isinstance(a, Legend)
            for t in a.get_texts()]


def all_legend_texts(fig):
    return [t for ax in fig.axes for t in legend_texts(ax)]


def colour_bar_label(fig):
    """The label of the figure's colour bar (its axes' y label)."""
    bars = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert len(bars) == 1
    return bars[0].get_ylabel()


# A label ends with its unit in parentheses, or names one of these dimensionless quantities.
DIMENSIONLESS = ("FMPM order", "FMPM pass", "velocity update", "Courant number", "fraction",
                 "convergence limit", "relative error", "spectral radius", "mean FMPM order",
                 "material id", "volume ratio")


def labels(fig):
    """Every axis and colour-bar label the figure shows."""
    fig.canvas.draw()  # the tick labels are set when drawn
    out = []
    for ax in fig.axes:
        if not ax.axison:
            continue
        for axis, text in ((ax.xaxis, ax.get_xlabel()), (ax.yaxis, ax.get_ylabel())):
            if any(t.get_visible() and t.get_text() for t in axis.get_ticklabels()):
                out.append(text)
    return out


# The checks of each script beyond its labels.

def check_plot_energy(r):
    fig = r.figure()
    energies, change = fig.axes
    assert "%" in change.get_ylabel() and "E_0" in change.get_ylabel()
    # The numbers the run printed, printed again by the script.
    ran = re.search(r"completed (\d+) steps .*total energy (\S+) -> (\S+) \((\S+%)\)",
                    (r.dir / "smpm.out").read_text())
    printed = re.search(r"energy\.png: (\d+) steps, total energy (\S+) -> (\S+) \((\S+%)\)",
                        r.stdout)
    assert printed and ran and printed.groups() == ran.groups()
    # The lower panel is the relative change of the total, in %, to its last point.
    with h5py.File(r.dir / "bar.h5") as f:
        total = f["series"]["total"][:]
    y = change.get_lines()[0].get_ydata()
    np.testing.assert_allclose(y, 100 * (total - total[0]) / total[0], rtol=1e-12)
    assert f"{y[-1]:+.4f}%" == printed.group(4)


def check_plot_particles(r):
    label = colour_bar_label(r.figure())
    assert "sigma_{xx}" in label and "(input units)" in label
    with h5py.File(r.dir / "disks.h5") as f:
        n = len(f["particles"]["000002"]["X"])
    assert f": {n} particles, stress_xx in [" in r.stdout


def check_rho_map(r):
    table = rows(r.tables[0])
    assert len(table) == 80 and {row["courant"] for row in table} == {"0.6"}
    rho = np.array([float(row["rho_T"]) for row in table])
    # The default Courant number draws the frontier: stable and unstable cells (1e-6 is the
    # tolerance of critical_courant's ρ ≤ 1 + tol), as the title counts them.
    stable = int((rho <= 1 + 1e-6).sum())
    assert 10 < stable < 70
    assert f"{stable} of 80 stable" in r.figure().axes[0].get_title()
    page = " ".join((SOURCE / "docs" / "studies" / "stability.md").read_text().split())
    assert f"{stable} of its 80 (k, α) cells are stable" in page
    assert "rho(T)" in colour_bar_label(r.figure())
    assert r.stdout.rstrip().endswith(f"(sparsempm {smpm.__version__})")


def check_fig12b(r):
    loss = {float(row["blend_alpha"]): float(row["energy_loss_percent"])
            for row in rows(r.tables[0])}
    assert sorted(loss) == [i / 10 for i in range(11)]
    assert loss[0.0] > loss[0.5] > loss[1.0]  # FMPM(1) dissipates, FMPM(4) hardly
    x, y = r.figure().axes[0].get_lines()[0].get_data()
    np.testing.assert_allclose(y, [loss[a] for a in x])


def check_fig12a(r):
    fig = r.figure()
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title()[:3] for ax in panels] == ["(A)", "(B)"]
    a, b = panels
    for ax in panels:  # a legend of the series and one of the methods, each short
        legends = [c for c in ax.get_children() if isinstance(c, Legend)]
        assert len(legends) == 2 and all(len(lg.get_texts()) <= 5 for lg in legends)
    assert any("FLIP" in t for t in legend_texts(a)) and any("exact" in t for t in legend_texts(a))
    assert {"spectral", "simulation", "simulation, low dissipation", "paper (simulation)"} <= \
        set(legend_texts(a))
    text_b = " ".join(legend_texts(b))
    assert "FMPM(1)" in text_b and "FMPM(2)" in text_b and "periodic" in text_b

    def points(ax):
        return {(round(float(x), 9), round(float(y), 9)) for line in ax.get_lines()
                for x, y in zip(*line.get_data())}

    def level(ax):  # the heights of the horizontal lines
        return {round(float(line.get_ydata()[0]), 9) for line in ax.get_lines()
                if len(line.get_ydata()) == 2 and line.get_ydata()[0] == line.get_ydata()[1]}

    # Every number of both tables is drawn, on its panel; "none" (no C holds) is not.
    drawn = 0
    for table, columns in ((r.dir / "st.csv", ("critical_courant", "simulation_courant")),
                           (r.dir / "low.csv", ("simulation_courant",))):
        for row in rows(table):
            for col in columns:
                if row[col] in ("", "none"):
                    continue
                v = round(float(row[col]), 9)
                if row["velocity"] in ("FLIP", "exact"):
                    assert v in level(a), (row, col)
                else:
                    unblended = row["blend_alpha"] == "1" and row["periodic_cx"] == ""
                    assert (int(row["order"]), v) in points(a if unblended else b), (row, col)
                drawn += 1
    # 7 rows × 2 columns, and 5 of the 7 rows of the low-dissipation table (no C keeps
    # FMPM(1) or its blend within 0.1%: "none", as FMPM 2026 §3.3 finds).
    assert drawn == 19
    assert any(row["simulation_courant"] == "none" for row in rows(r.dir / "low.csv"))


def check_fig12_gradient(r):
    fig = r.figure()
    panels = {ax.get_title(): ax for ax in fig.axes if ax.get_title()}
    assert [t[:9] for t in panels] == ["(A) bar: ", "(B) bar: ", "(C) bar: ", "(A) plate",
                                       "(B) plate", "(C) plate"]
    texts = all_legend_texts(fig)
    assert {"spectral", "simulation", "velocity-gradient transfer (A, B); APIC (C)",
            "standard transfer (A, B); velocity gradient (C)"} <= set(texts)

    def drawn(ax, full):  # the (x, y) of the lines in full or faded
        return {(round(float(x), 9), round(float(y), 9)) for line in ax.get_lines()
                if (line.get_alpha() in (None, 1)) == full for x, y in zip(*line.get_data())}

    # Every C* of the six input tables is on its panels, in full or faded by its transfer: the
    # standard transfer faded on A and B, the velocity-gradient transfer in full there and faded
    # on C, APIC in full on C (its blended and periodic rows are in the table, not drawn); FLIP
    # as a horizontal line.
    count = 0
    for problem in ("bar", "plate"):
        a, b, c = (ax for t, ax in panels.items() if t.startswith(("(A) " + problem,
                                                                   "(B) " + problem,
                                                                   "(C) " + problem)))
        for transfer, places in (("standard", [(a, b, False)]),
                                 ("velocity_gradient", [(a, b, True), (c, None, False)]),
                                 ("apic", [(c, None, True)])):
            for row in rows(r.dir / f"{problem}_{transfer}.csv"):
                for col in ("critical_courant", "simulation_courant"):
                    if row[col] in ("", "none"):
                        continue
                    v = round(float(row[col]), 9)
                    for main, other, full in places:
                        if row["velocity"] == "FLIP":
                            assert any(round(float(y), 9) == v for x, y in drawn(main, full)), row
                        elif row["blend_alpha"] == "1":
                            assert (int(row["order"]), v) in drawn(main, full), (row, col)
                        elif other is not None:
                            assert (int(row["order"]), v) in drawn(other, full), (row, col)
                        else:
                            continue  # panel C has no blended rows
                        count += 1
    # Two methods: the standard transfer's 6 rows (bar 4, plate 2) on A or B, the gradient
    # transfer's on A or B and its 5 unblended rows on C, APIC's 5 unblended rows on C.
    assert count == 2 * (6 + 6 + 5 + 5)
    # The script's own table holds the same rows, and the summary prints FLIP for both.
    table = rows(r.tables[0])
    assert len(table) == 3 * (4 + 2)
    assert {row["transfer"] for row in table} == {"standard", "velocity gradient", "APIC"}
    assert r.stdout.count("| FLIP |") == 2
    assert "APIC: spectral / simulation" in r.stdout


def check_truncation(r):
    table = rows(r.dir / "spectrum.csv")
    groups = {(row["blend_alpha"], row["blend_every"]) for row in table}
    texts = legend_texts(r.figure().axes[0])
    assert len(texts) == len(groups) + 1 and "rho(A)^k" in texts[-1]
    assert f"{len(table)} rows" in r.stdout


def check_fig3(r):
    table = rows(r.tables[0])
    assert len(table) == 2 * 2 * 4  # shapes × depths × (FLIP, exact, new, combined)
    assert all(row["error_percent"] for row in table), table
    assert "$d$ = 1 cell" in r.figure(0).axes[0].get_title()
    shapes = [t for t in all_legend_texts(r.figure(1)) if t in ("CPDI", "B2CPDI")]
    assert shapes == ["CPDI", "B2CPDI"]


def assert_legend_says_which_coincide(texts, curves):
    """The legend entries `texts` of the curves {name: y} (in drawing order) say "(coincides
    with Y)" exactly where a curve lies on an earlier one, Y, to figures.COINCIDE of the range
    of all the y (the tables hold 4 digits: 1e-3 more); the number of such entries."""
    ys = np.concatenate(list(curves.values()))
    tol = figures.COINCIDE * (np.nanmax(ys) - np.nanmin(ys))

    def apart(a, b):  # the largest difference, NaN (a gap) only where both have one
        if not np.array_equal(np.isnan(a), np.isnan(b)):
            return np.inf
        return np.nanmax(np.abs(a - b), initial=0)

    assert [t.split(" (coincides with ")[0] for t in texts] == list(curves)
    plain = []
    for t in texts:
        m = re.fullmatch(r"(.+) \(coincides with (.+)\)", t)
        if m:  # it lies on the curve it names, to the plot's precision
            assert m[2] in plain and apart(curves[m[1]], curves[m[2]]) <= tol + 1e-3, t
        else:  # and a curve the legend does not say coincides lies on no earlier one
            for other in plain:
                assert apart(curves[t], curves[other]) > tol, (t, other)
            plain.append(t)
    return len(texts) - len(plain)


def check_fig4(r):
    import fig4
    table = rows(r.tables[0])
    assert {row["case"] for row in table} == set(fig4.CASES)
    assert len(table) == len(fig4.CASES) * (len(fig4.BINS) - 1)
    panels = [ax for ax in r.figure().axes if ax.get_title()]
    assert len(panels) == 3
    for ax, figure in zip(panels, ("4", "5", "7")):
        curves = {}
        for row in table:
            if row["figure"] == figure:
                curves.setdefault(row["case"], []).append(float(row["pressure_GPa"]))
        # The curves' entries, then the reference lines' (the Rankine-Hugoniot pressure and
        # the material interface), each named.
        texts = legend_texts(ax)
        refs = len(fig4.REFERENCE_LABELS)
        assert texts[-refs:] == list(fig4.REFERENCE_LABELS)
        assert_legend_says_which_coincide(texts[:-refs], {k: np.array(v) for k, v in
                                                          curves.items()})


def check_fig5(r):
    import fig5
    table = rows(r.tables[0])
    assert {row["method"] for row in table} == set(fig5.METHODS)
    curves = {}
    for row in table:
        curves.setdefault(row["method"], []).append(float(row["error_percent"]))
    ref = np.array([float(row["sigma_yy"]) for row in table if row["method"] == "single material"])
    curves = {k: np.array(v)[ref != 0] for k, v in curves.items()}  # frame 0: no stress yet
    del curves["single material"]
    # The tiny case has coinciding curves too.
    assert assert_legend_says_which_coincide(legend_texts(r.figure().axes[0]), curves) > 0
    assert "coincides to plotting precision" in r.stdout


def check_fig8(r):
    table = rows(r.tables[0])
    assert len(table) == 3 * 4  # μ × updates
    assert len(legend_texts(r.figure().axes[0])) == 3


def check_fig9(r):
    assert len(rows(r.tables[0])) == 3 * 4 + 5  # μ × updates, and FMPM(3, 5, 6, 7, 8) at μ = 0.3


def check_buzzi(r):
    # Buzzi et al.: the single point at dt = 0.001 within 2.4% of v0 cos wt with USF (his
    # Figs. 9-10; measured 2.33%, docs/studies/examples.md's claim 2.3%), USL dissipating (-7.6% of
    # the energy); the difference from a run at dt = 1e-5 falls at first order in dt (measured
    # orders 1.18, 1.02, 1.04); one cell (2 nodes) misses the bar's first mode whatever the
    # points (189-192%), 8 nodes follow it within 9%; the improper BC ordering changes v_cm by
    # 0.0033% of its amplitude under FLIP.
    table = {(row["panel"], row["case"], row["dt"]): row for row in rows(r.tables[0])}
    assert len(table) == 2 + 5 + 4 + 2
    assert float(table[("A", "single point, USF", "0.001")]["error_percent"]) < 2.4
    assert float(table[("A", "single point, USL", "0.001")]["energy_change_percent"]) < -5
    b = [float(table[("B", "single point, USF", dt)]["difference_percent"])
         for dt in ("0.01", "0.001", "0.0001")]
    assert all(0.9 < np.log10(b[k] / b[k + 1]) < 1.2 for k in range(2))
    assert float(table[("C", "3 points, 2 nodes", "0.001")]["error_percent"]) > 100
    assert float(table[("C", "7 points, 8 nodes", "0.001")]["error_percent"]) < 10
    assert float(table[("D", "7 points, 8 nodes, improper BCs", "0.001")]["difference_percent"]) > 0
    assert "order in dt of the difference" in r.stdout and len(r.figure().axes) == 4


def check_plastic_bar(r):
    # The elastic-plastic bar (Simo & Hughes 1998, Box 9.1; uniaxial strain): the precursor at
    # 128.88 against c_e t = 129.10 and the plastic front at 100.93 against c_p t = 100 (as
    # tests/cli/test_examples.py: within 2 cells); just ahead of the plastic front the strain is
    # eps_HEL = 0.002 (measured 5.2% under between 105 and 115: the precursor's top is not flat,
    # it falls towards its front; asserted 7%), and behind the plastic front, away from the
    # driven end, the plastic strain is (2/3)(eps - eps_HEL) = 0.00495 (measured 2.2% under;
    # asserted 5%); nothing flows ahead of it.
    m = re.search(r"precursor at ([\d.]+) against c_e t = ([\d.]+); plastic front at ([\d.]+) "
                  r"against c_p t = ([\d.]+)", r.stdout)
    assert m, r.stdout
    assert abs(float(m[1]) - float(m[2])) < 2 and abs(float(m[3]) - float(m[4])) < 2
    table = rows(r.tables[0])
    X = np.array([float(row["X"]) for row in table])
    strain = np.array([float(row["strain"]) for row in table])
    eps_p = np.array([float(row["plastic_strain"]) for row in table])
    between = (X > 105) & (X < 115)
    assert abs(strain[between].mean() / 0.002 - 1) < 0.07
    behind = (X > 40) & (X < 90)
    assert abs(eps_p[behind].mean() / (2 * (0.00942 - 0.002) / 3) - 1) < 0.05
    assert (eps_p[X > 110] == 0).all()


def check_polynomials(r):
    # FMPM's polynomial family (docs/studies/polynomials.md) on the bar and the plate.
    table = {(row["problem"], row["velocity"], row["order"]): row for row in rows(r.tables[0])}
    members = ("FMPM", "blended", "chebyshev", "least_squares", "chebyshev_squared")
    assert set(table) == {(p, v, k) for p in ("bar", "plate") for v in members for k in ("2", "4")} | \
        {(p, v, "") for p in ("bar", "plate") for v in ("FLIP", "exact")}
    for p, lo in (("bar", 0.25), ("plate", 0.0625)):  # lambda_min(m^-1 m~) as smpm spectrum prints it
        assert abs(float(table[(p, "chebyshev", "2")]["interval_low"]) - lo) < 1e-9
        # Squared Chebyshev with k - 1 = 1 product is the series' one pass: FMPM(2), bit for bit.
        for col in ("critical_courant", "energy_change_percent"):
            assert table[(p, "chebyshev_squared", "2")][col] == table[(p, "FMPM", "2")][col]
        # Chebyshev(2): R = (1 - l)(1 - l/theta) < 0 on (theta, 1): the particle update grows
        # those modes (1 - R > 1) at every C.
        assert table[(p, "chebyshev", "2")]["critical_courant"] == "0"
    titles = [ax.get_title() for ax in r.figure(0).axes]
    assert [t[:4] for t in titles] == ["(A) ", "(B) ", "(C) ", "(D) "]
    # R_8 of each member: R(0) = 1 (q is a polynomial: v = q m^-1 p), the series (1 - l)^8.
    lines = {line.get_label(): line for line in r.figure(1).axes[0].get_lines()}
    series = lines["FMPM($k$), the series"]
    lam, R = series.get_data()
    assert np.allclose(R, (1 - lam) ** 8, atol=1e-14)
    for name in ("Chebyshev", "least squares", "squared Chebyshev"):
        assert abs(lines[name].get_data()[1][0] - 1) < 1e-14
    assert lines["squared Chebyshev"].get_data()[1].min() >= -1e-15
    # Chebyshev's negative lobes on the bar's [0.25, 1]: |R_8| <= (1 - 0.25) / T_7(5/3), T_7(5/3) =
    # (3^7 + 3^-7) / 2 = 1093.5, so -6.86e-4 <= min R_8 (measured -6.52e-4).
    assert -0.75 / 1093.5 - 1e-12 <= lines["Chebyshev"].get_data()[1].min() < -1e-4


def check_fig2b(r):
    # Contact 2020 Fig. 2B: logistic regression finds the contact at the contact time on a grid
    # line and mid cell (measured +0.06 and +0.01 ms: the first frame after t_c; asserted within
    # 0.15 ms, three frames), the approaching criterion alone milliseconds early (measured
    # -5.09 and -7.69 ms).
    table = rows(r.tables[0])
    found = {(row["method"], row["contact_plane"]): float(row["detected_minus_tc_ms"])
             for row in table}
    assert len(found) == 10
    for plane in ("grid line", "mid cell"):
        assert abs(found[("LR", plane)]) < 0.15
        assert found[("Δv < 0 (AG)", plane)] < -1.0
    assert "contact time t_c = 7.795 ms" in r.stdout


def check_fig6(r):
    # The library's contact law against the paper's ‖f_c‖/A_c = √(N_c² + min(T_c, μ N_c)²)
    # (N_c > 0; 0 otherwise) at every point: the same operations, so to round-off (measured 0).
    table = rows(r.tables[0])
    assert len(table) == 3 * 601
    for row in table:
        assert float(row["force_per_area"]) == pytest.approx(float(row["paper_force_per_area"]),
                                                             abs=1e-12)
    states = {row["state"] for row in table if row["T_c"] == "2"}
    assert states == {"none", "slip", "stick"}
    assert "largest |library - formula|" in r.stdout and len(legend_texts(r.figure().axes[0])) == 3


def check_fig7(r):
    # One row per frame; the heat is the frictional work (to the printed digits), and with the
    # default lumped transport no temperature falls below the initial 300 K (positive friction
    # heat added by Δt S c⁻¹ q; FMPM(4) transport would reach a few kelvin below).
    table = rows(r.tables[0])
    assert len(table) == 2
    for row in table:
        assert float(row["heat_mJ"]) == pytest.approx(float(row["friction_mJ"]), abs=1e-3)
        assert float(row["temperature_min_K"]) >= 300 - 1e-7  # round-off
        assert float(row["temperature_max_K"]) >= float(row["temperature_min_K"])
    assert "lumped transport" in r.stdout
    assert len(r.figure().axes) == 3  # two frames and the colour bar


def check_fig10(r):
    table = rows(r.tables[0])
    assert len(table) == 3 * 2  # μ × (FLIP, FMPM(4))
    assert len(legend_texts(r.figure().axes[0])) == 6


def check_fig11(r):
    table = rows(r.tables[0])  # A: 2 updates x 2 schemes; B: FLIP, FMPM(4), periodic FMPM(4)
    assert len(table) == 4 + 3 and not any(row["error"] for row in table)
    assert [row["velocity"] for row in table if row["panel"] == "B"][-1] == "periodic FMPM(4)"


def check_fig13a(r):
    table = rows(r.tables[0])
    assert len(table) == 2 * 2 * 4  # problems × metrics × passes ℓ = 2 … 5
    assert r.figure().axes[0].get_yscale() == "log"


def check_fig13b(r):
    # FLIP, FMPM(2), FMPM(20) and dynamic FMPM(20) for 2 limits x 2 metrics; FLIP's time is
    # its own unit, and the dynamic loop never exceeds its order 20 nor falls below 2 (the
    # first pass of the loop is FMPM(2)'s).
    table = rows(r.tables[0])
    assert len(table) == 3 + 2 * 2
    flip = [row for row in table if row["velocity"] == "FLIP"][0]
    assert float(flip["time_relative_to_flip"]) == 1.0
    for row in table:
        if row["velocity"] == "dynamic FMPM(20)":
            assert 2 - 1e-12 <= float(row["mean_order"]) <= 20
    assert len(r.figure().axes) == 2


def check_fig14(r):
    table = rows(r.tables[0])
    assert len(table) == 2 * 2 * 2  # problems × metrics × limits
    assert all(1 <= float(row["mean_order"]) <= 20 for row in table)


def check_compaction(r):
    table = rows(r.tables[0])
    assert [row["method"] for row in table] == ["AG, CP = 0.8", "AG, DF", "LR, d_LR"]
    axes = r.figure().axes
    assert [ax.get_xlabel() for ax in axes] == ["$x$ (mm)"] * 3
    assert axes[0].get_ylabel() == "$y$ (mm)"
    assert (r.dir / "compaction.toml").exists()


def check_compaction_paper(r):
    table = rows(r.tables[0])
    assert sorted({row["method"] for row in table}) == ["CP", "DF", "LR"]
    axes = r.figure().axes
    assert axes[0].get_xlabel() == "compaction (%)"
    assert [ax.get_xlabel() for ax in axes[1:]] == ["$x$ (mm)"] * 3
    assert (r.dir / "compaction_paper.toml").exists()
    assert (r.dir / "compaction_paper.in.png").exists()


def check_three_materials(r):
    assert {row["variant"] for row in rows(r.tables[0])} == \
        {"single material", "lumping, LR", "lumping, AG", "two fields (left = right), LR"}
    assert colour_bar_label(r.figure()) == r"$\sigma_{yy}$ (MPa)"


def check_df_fit(r):
    assert len(rows(r.tables[0])) == 2000
    assert "r = 0.5757 (exact at d = 0)" in r.stdout  # the library's default exponent


CHECKS = {name: globals()["check_" + name.removesuffix(".py")] for name in CASES}


@pytest.mark.parametrize("name", CASES)
def test_figure_is_drawn_labelled_and_says_what_its_data_say(name, renders):
    r = renders[name]
    assert r.returncode == 0, r.stderr
    for png in r.pngs:
        data = png.read_bytes()
        assert data[:8] == PNG and len(data) > 20000, png
    for table in r.tables:
        assert rows(table), table
    assert len(r.figures) == len(r.pngs)
    for fig in r.figures:
        assert figures.unlabelled_axes(fig) == []
        for label in labels(fig):
            assert label.endswith(")") or any(d in label for d in DIMENSIONLESS), label
    CHECKS[name](r)


def test_every_figure_script_has_a_case():
    # A new script is drawn here too; each draws with the shared style and saves through
    # save_figure (no savefig of its own), and takes -o as a prefix (add_output).
    scripts = {p.name for p in ANALYSIS.glob("*.py")} - HELPERS
    assert scripts == set(CASES)
    for name in scripts:
        text = (ANALYSIS / name).read_text()
        assert "figures.style()" in text and "save_figure(" in text, name
        assert ".savefig(" not in text and "figures.add_output(" in text, name


def test_output_prefix():
    assert figures.output_prefix("fig12a.png") == "fig12a"
    assert figures.output_prefix("out/fig3") == "out/fig3"
    assert figures.output_prefix("a.b.PNG") == "a.b"


def test_save_figure_refuses_a_figure_drawn_without_the_style(tmp_path):
    code = ("import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot as plt; "
            "import figures; fig, ax = plt.subplots(); ax.set_xlabel('x (m)'); "
            "ax.set_ylabel('y (m)'); figures.save_figure(fig, 'f')")
    r = subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env=dict(env(), PYTHONPATH=str(ANALYSIS)), timeout=60)
    assert r.returncode != 0 and "drawn without figures.style()" in r.stderr
    assert not (tmp_path / "f.png").exists()


def test_plot_energy_of_a_run_from_rest(tmp_path):
    # E(0) = 0: no relative change ("n/a", not "+0.0000%"); the lower panel is E − E(0).
    with h5py.File(tmp_path / "rest.h5", "w") as f:  # a run file (figures.read_run) of series
        f.attrs["input"] = ""
        f.create_group("particles")
        s = f.create_group("series")
        s["t"] = [0.0, 1.0, 2.0]
        s["kinetic"] = [0.0, 0.5, 1.0]
        s["strain"] = [0.0, 0.0, 0.25]
        s["total"] = [0.0, 0.5, 1.25]
    r = subprocess.run(["/usr/bin/python3", ANALYSIS / "plot_energy.py", tmp_path / "rest.h5"],
                       capture_output=True, text=True, cwd=tmp_path, env=env(dump=tmp_path),
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().endswith("2 steps, total energy 0 -> 1.25 (n/a; change +1.25)")
    assert (tmp_path / "rest_energy.png").stat().st_size > 20000
    with open(tmp_path / "rest_energy.pickle", "rb") as f:
        lower = pickle.load(f).axes[1]
    assert lower.get_ylabel() == "$E - E_0$ (input units)"
    np.testing.assert_array_equal(lower.get_lines()[0].get_ydata(), [0.0, 0.5, 1.25])


def test_scripts_read_run_files_through_figures_read_run(tmp_path):
    # One reader: no script opens a run file with h5py itself.
    for path in ANALYSIS.glob("*.py"):
        assert not re.search(r"^\s*(import|from) h5py", path.read_text(), re.M), path.name
    run_smpm("run", BAR, "-o", tmp_path / "bar.h5", "-q", "--set", "time.end=20", cwd=tmp_path)
    run = smpm.read_run(tmp_path / "bar.h5")
    # With the package importable, the reader is sparsempm.read_run.
    assert isinstance(figures.read_run(tmp_path / "bar.h5"), smpm.Run)
    # Where sparsempm does not import (a package whose import fails, as python/sparsempm of a
    # checkout without the built extension), figures.read_run loads python/sparsempm/runfile.py
    # by its path and reads the same arrays.
    broken = tmp_path / "path" / "sparsempm"
    broken.mkdir(parents=True)
    (broken / "__init__.py").write_text("raise ImportError('no extension')\n")
    code = ("import sys, numpy as np, figures; r = figures.read_run(sys.argv[1]); "
            "p = r.particles(-1); print(sys.modules[type(r).__module__].__file__); "
            "print('sparsempm' in sys.modules); np.savez(sys.argv[2], times=r.times, "
            "total=r.series['total'], X=p['X'], stress=p['stress'], frames=r.frames)")
    path = os.pathsep.join([str(tmp_path / "path"), str(ANALYSIS)])
    r = subprocess.run(["/usr/bin/python3", "-c", code, tmp_path / "bar.h5", tmp_path / "r.npz"],
                       capture_output=True, text=True, cwd=tmp_path,
                       env=dict(env(), PYTHONPATH=path), timeout=60)
    assert r.returncode == 0, r.stderr
    file, imported = r.stdout.split()
    assert pathlib.Path(file) == (SOURCE / "python" / "sparsempm" / "runfile.py").resolve()
    assert imported == "False"
    p = run.particles(-1)
    with np.load(tmp_path / "r.npz") as read:
        for key, value in (("times", run.times), ("total", run.series["total"]), ("X", p["X"]),
                           ("stress", p["stress"]), ("frames", run.frames)):
            np.testing.assert_array_equal(read[key], value, err_msg=key)
