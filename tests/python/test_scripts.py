# SPDX-License-Identifier: BSD-3-Clause
"""The analysis scripts that call the module (analysis/rho_map.py, analysis/fig12b.py) write the
same tables through sparsempm as through the `smpm` command (--cli)."""
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
    return smpm.read_table(out.with_suffix(".csv"))


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


# The tables of the previous release: the earlier names of the results' columns.
EARLIER_STABILITY = ("velocity,order,blend_alpha,blend_every,periodic_cx,position_alpha,c_spectral,"
                     "config_spectral,spectral_status,c_simulation,energy_change\n"
                     "FLIP,,,,,1,0.7555,shift 0,converged,0.8612,3.98\n"
                     "FMPM,4,1,1,,1,0.4508,shift 0.375,converged,0.5432,0.06\n")
EARLIER_TRANSPORT = ("transport,order,f_spectral,rho_T,config_spectral,evaluations\n"
                     "lumped,,0.9992,1,shift 0.25,17\nFMPM,2,0.5836,0.9990676,shift 0.25,15\n")


def test_tables_of_the_earlier_column_names_are_read(tmp_path):
    # One release of the earlier column names (sparsempm.tables.EARLIER_COLUMNS, the one alias
    # table): the package's reader, the scripts' reader (analysis/figures.py, which loads
    # python/sparsempm/tables.py by its path when the package does not import) and fig12a.py's
    # series give the values of an earlier table under the current names.
    old, now = tmp_path / "old.csv", tmp_path / "now.csv"
    old.write_text(EARLIER_STABILITY)
    header, body = EARLIER_STABILITY.split("\n", 1)
    now.write_text(",".join(smpm.tables.current_columns(header.split(","))) + "\n" + body)
    rows = smpm.read_table(old)
    assert rows == smpm.read_table(now)
    assert [r["critical_courant"] for r in rows] == ["0.7555", "0.4508"]
    assert [r["simulation_courant"] for r in rows] == ["0.8612", "0.5432"]
    assert [r["configuration"] for r in rows] == ["shift 0", "shift 0.375"]
    assert "c_spectral" not in rows[0]
    transport = tmp_path / "transport.csv"
    transport.write_text(EARLIER_TRANSPORT)
    assert [(r["transport"], r["critical_fourier"], r["configuration"], r["evaluations"])
            for r in smpm.read_table(transport)] == [("lumped", "0.9992", "shift 0.25", "17"),
                                                     ("FMPM", "0.5836", "shift 0.25", "15")]
    # The current header is the one `smpm stability` writes, with the columns added since
    # (stable_from and small_courant, what lies below C*; interval_low, the polynomial rows' λ_lo).
    st = tmp_path / "st.csv"
    r = subprocess.run([SMPM, "stability", BAR, "--order", "1", "--blend-alpha", "none",
                        "--periodic-cx", "none", "--no-exact", "--shifts", "1", "--method",
                        "spectral", "-q", "-o", st], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert st.read_text().splitlines()[0] == now.read_text().splitlines()[0].replace(
        "spectral_status,", "spectral_status,stable_from,small_courant,") + ",interval_low"
    # The scripts, without the package (-S: no site directory, so no sparsempm): figures.read_table and
    # fig12a's series of an earlier table.
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import fig12a; "
            "rows = fig12a.read(sys.argv[2]); "
            "print(fig12a.series_of(rows, 'critical_courant'), fig12a.series_of(rows, 'simulation_courant'))")
    env = {"PATH": "/usr/bin:/bin", "MPLBACKEND": "Agg"}
    r = subprocess.run(["/usr/bin/python3", "-S", "-c", code, SOURCE / "analysis", old], capture_output=True,
                       text=True, timeout=120, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["({'FMPM(k)':", "[(4,", "0.4508)]},", "{'FLIP':", "0.7555})",
                                "({'FMPM(k)':", "[(4,", "0.5432)]},", "{'FLIP':", "0.8612})"]


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
