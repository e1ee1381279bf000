# SPDX-License-Identifier: BSD-3-Clause
"""The analysis scripts that call the module (analysis/rho_map.py, analysis/fig12b.py) write the
same tables through sparsempm as through the `smpm` command (--cli)."""
import csv
import pathlib
import subprocess

import pytest

import sparsempm as smpm

from conftest import BAR, SMPM, SOURCE

BUILD = pathlib.Path(smpm.__file__).resolve().parents[1]  # the directory holding the package


def script(name, tmp_path, *args):
    """Runs analysis/<name> with the module of this build (or with smpm: --cli); its rows."""
    out = tmp_path / ("cli.png" if "--cli" in args else "module.png")
    r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / name, "--smpm", SMPM, "--build",
                        BUILD, "--input", BAR, "-o", out, *args],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    # The last line names what computed the table: the module of this build, or the command.
    via = SMPM if "--cli" in args else f"sparsempm {smpm.__version__}"
    assert r.stdout.rstrip().endswith(f"({via})")
    assert out.stat().st_size > 10000  # a PNG was drawn
    return list(csv.DictReader(open(out.with_suffix(".csv"))))


@pytest.mark.parametrize("name", ["rho_map.py", "fig12b.py"])
def test_module_and_cli_write_the_same_table(name, tmp_path):
    # rho_map: C = 0.6 lies above FMPM(4)'s C* = 0.54 (FMPM 2026 §3.3), so the map holds stable
    # and unstable (k, α). Both paths call the same library functions (spectral_radius of
    # LinearizedStep, as `smpm spectrum` does; advance(), the loop of `smpm run`): equal text.
    args = ["--courant", "0.6"] if name == "rho_map.py" else []
    module, cli = script(name, tmp_path, *args), script(name, tmp_path, *args, "--cli")
    assert module == cli
    if name == "rho_map.py":
        assert len(module) == 80  # 10 orders × 8 fractions
        rho = {(int(r["order"]), float(r["blend_alpha"])): float(r["rho_T"]) for r in module}
        # FMPM(1) (PIC) is stable at C = 0.6 (C* = 0.86, FMPM 2026 §3.3) and FMPM(40) is not
        # (C* = 0.25); 1e-6 is the tolerance of critical_courant's ρ ≤ 1 + tol.
        assert rho[1, 1.0] <= 1 + 1e-6 and rho[40, 1.0] > 1 + 1e-6
    else:
        loss = {float(r["blend_alpha"]): float(r["energy_loss_percent"]) for r in module}
        assert len(loss) == 11
        # FMPM 2026 Fig. 12B: pure FMPM(1) (α = 0) dissipates ~40% in five periods at C = 0.539
        # (vibrating_bar.toml: PIC ~40%), pure FMPM(4) (α = 1) under 0.01%; ±1% and the bound.
        assert loss[0.0] == pytest.approx(40.4, abs=1.0) and abs(loss[1.0]) < 0.01


def test_the_licence_citation_and_changelog_name_this_release():
    # CITATION.cff (Citation File Format 1.2.0) gives the module's version and the licence of
    # LICENSE; the changelog has a section for the version.
    import yaml
    cff = yaml.safe_load((SOURCE / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software"
    assert cff["version"] == smpm.__version__
    assert cff["license"] == "BSD-3-Clause"
    assert (SOURCE / "LICENSE").read_text().startswith("BSD 3-Clause License")
    assert all(r["title"] and r["authors"] for r in cff["references"])
    assert f"## [{smpm.__version__}]" in (SOURCE / "CHANGELOG.md").read_text()


def test_figures_refuse_unlabelled_axes(tmp_path):
    # analysis/figures.py's save_figure refuses a figure with an axis that shows tick labels
    # but no label (a colour bar included); a shared, hidden y axis needs none.
    import sys
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sys.path.insert(0, str(SOURCE / "analysis"))
    from figures import save_figure, style, unlabelled_axes

    style()
    fig, axes = plt.subplots(1, 2, sharey=True)
    for ax in axes:
        ax.plot([0, 1], [0, 1])
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    assert unlabelled_axes(fig) == []
    fig, ax = plt.subplots()
    sc = ax.scatter([0, 1], [0, 1], c=[0, 1])
    ax.set_xlabel("x (mm)")
    bar = fig.colorbar(sc, ax=ax)
    assert unlabelled_axes(fig) == ["axes: y", "<colorbar>: y"]
    with pytest.raises(ValueError, match="axes without a label"):
        save_figure(fig, str(tmp_path / "f"))
    ax.set_ylabel("y (mm)")
    bar.set_label("stress (MPa)")
    save_figure(fig, str(tmp_path / "f"))
    assert (tmp_path / "f.png").stat().st_size > 1000


def test_fig12a_reads_none_rows(tmp_path):
    # A row where no C holds is "none" in smpm stability's table (as in scripts/run's
    # low-dissipation table); fig12a.py failed on it ("could not convert string to float").
    header = ("velocity,order,blend_alpha,blend_every,periodic_cx,position_alpha,c_spectral,"
              "config_spectral,spectral_status,c_simulation,energy_change\n")
    table = tmp_path / "st.csv"
    table.write_text(header + "FLIP,,,,,1,0.7555,shift 0,converged,0.8612,3.98\n"
                     "FMPM,4,1,1,,1,0.4508,shift 0.375,converged,0.5432,0.06\n")
    low = tmp_path / "low.csv"
    low.write_text(header + "FLIP,,,,,1,,,,none,\nFMPM,4,1,1,,1,,,,0.5403,0.0002\n"
                   "FMPM,4,0.8,1,,1,,,,none,\n")
    out = tmp_path / "f.png"
    r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / "fig12a.py", table,
                        "--low-dissipation", low, "-o", out], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10000
