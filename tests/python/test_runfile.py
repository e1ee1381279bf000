# SPDX-License-Identifier: BSD-3-Clause
"""sparsempm.read_run: a run file's frames, series and matrices as numpy and scipy, against the
file itself (h5py) and the identities its arrays obey."""
import os

import h5py
import numpy as np
import pytest

import sparsempm as smpm

from conftest import BAR, SOURCE, TWO_BLOCKS, run_smpm


@pytest.fixture(scope="module")
def bar_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bar") / "bar.h5"
    r = run_smpm("run", BAR, "-o", out, "-q", "--set", "time.end=20", "--set",
                 "output.matrices=true")
    assert r.returncode == 0, r.stderr
    return out


@pytest.fixture(scope="module")
def blocks_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("blocks") / "blocks.h5"
    r = run_smpm("run", TWO_BLOCKS, "-o", out, "-q", "--set", "time.end=0.002", "--set",
                 "output.every=0.0005")
    assert r.returncode == 0, r.stderr
    return out


def test_frames_times_and_series_are_the_files(bar_run):
    run = smpm.read_run(bar_run)
    assert run.status == "completed" and run.version == smpm.__version__
    assert run.materials == ["bar"] and run.dim == 1
    with h5py.File(bar_run, "r") as f:
        names = sorted(f["particles"])
        assert run.frames == [int(n) for n in names]
        assert list(run.times) == [f["particles"][n].attrs["time"] for n in names]  # bit for bit
        for k in f["series"]:
            assert np.array_equal(run.series[k], f["series"][k][()])
        p = run.particles(-1)
        for k in f["particles"][names[-1]]:
            assert np.array_equal(p[k], f["particles"][names[-1]][k][()])
        assert p["@time"] == run.times[-1]
    s = run.series
    # total = kinetic + strain, row by row (as the run sums them: to round-off).
    assert np.allclose(s["total"], s["kinetic"] + s["strain"], rtol=1e-14, atol=0)
    assert "overrides" in repr(run) or "frames" in repr(run)
    assert run.overrides == ["time.end=20", "output.matrices=true"]


def test_matrices_obey_their_identities(bar_run):
    run = smpm.read_run(bar_run)
    mats = run.matrices(0)
    S, mt = mats["S"], mats["consistent_mass"]
    # Partition of unity: each row of S sums to 1 (round-off 1e-13).
    assert np.abs(S @ np.ones(S.shape[1]) - 1).max() < 1e-13
    g = run.grid(0)
    m = np.zeros(mt.shape[0])
    m[g["nodes"]] = g["m"]
    # The consistent mass m~ = S^T M S has row sums m = S^T M 1 (relative 1e-13).
    assert np.abs(mt @ np.ones(mt.shape[1]) - m).max() < 1e-13 * m.max()


def test_multimaterial_frames_have_J_and_contact_nodes(blocks_run):
    run = smpm.read_run(blocks_run)
    assert run.materials == ["lower", "upper"] and run.dim == 2
    p = run.particles(-1)
    F = p["F"].reshape(-1, 2, 2)
    # J = det F, the volume ratio: volume = J volume0 (round-off).
    assert np.allclose(p["J"], np.linalg.det(F), rtol=1e-14, atol=0)
    assert np.allclose(p["volume"], p["J"] * p["volume0"], rtol=1e-13, atol=0)
    g = run.grid(-1)
    assert g["@velocity_fields"] == 2 and len(g["contact_nodes"]) > 0
    # The contact nodes' normals are unit vectors (lumped nodes of three or more fields: 0).
    n = np.linalg.norm(g["contact_normal"], axis=1)
    assert np.allclose(n[g["contact_fields"][0::2] >= 0], 1, atol=1e-12)
    with pytest.raises(KeyError, match="no matrices"):
        run.matrices(0)


def test_a_file_that_is_no_run_is_refused(tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = [1.0]
    with pytest.raises(ValueError, match="not a sparsempm run file"):
        smpm.read_run(other)


def test_a_live_partial_run_reads_its_completed_frames(tmp_path):
    # read_run on a live run's partial file failed in most calls ("unable to lock file"). A run
    # in progress is an index beside one file per frame, each complete once named: every call
    # reads the frames completed so far, each frame's arrays whole, and their number grows.
    import subprocess
    import time
    out = tmp_path / "live.h5"
    p = subprocess.Popen([os.environ.get("SMPM", "smpm"), "run",
                          str(SOURCE / "examples" / "block_impact.toml"), "-o", str(out), "-q",
                          "--set", "time.end=100", "--set", "output.every=0.01"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    partial = tmp_path / "live.partial.h5"
    counts = []
    try:
        deadline = time.time() + 120
        while len(counts) < 20 and time.time() < deadline and p.poll() is None:
            if partial.exists():
                run = smpm.read_run(partial)
                assert run.status == "running"
                if run.frames:
                    X = run.particles(-1)["X"]
                    assert X.shape[1] == 2 and np.all(np.isfinite(X))
                    # the series reach the last frame's step
                    assert run.series["step"][-1] >= run.particles(-1)["@step"]
                counts.append(len(run.frames))
            time.sleep(0.05)
        assert p.poll() is None, "the run ended before the reads"
    finally:
        p.kill()
        p.wait()
    assert len(counts) == 20 and counts == sorted(counts) and counts[-1] > counts[0]


def test_a_fifo_is_refused_not_waited_on(tmp_path):
    # read_run("fifo.h5") blocked forever: only regular files are opened.
    os.mkfifo(tmp_path / "fifo.h5")
    with pytest.raises(ValueError, match="must be a regular file"):
        smpm.read_run(tmp_path / "fifo.h5")
    with pytest.raises(FileNotFoundError):
        smpm.read_run(tmp_path / "none.h5")


def test_material_takes_its_first_parameters_by_position():
    # Material("steel", "linear", density, youngs, poisson) worked until the keyword form
    # replaced it; both forms make the same material.
    a = smpm.Material("steel", "linear", 7.8, 200.0, 0.3)
    b = smpm.Material("steel", "linear", density=7.8, youngs=200.0, poisson=0.3)
    for key in ("name", "model", "density", "youngs", "poisson"):
        assert getattr(a, key) == getattr(b, key)
    assert a.wave_speed(1) == pytest.approx((200.0 / 7.8) ** 0.5, rel=1e-15)  # c = sqrt(E / rho)
    c = smpm.Material("steel", "hyperelastic", 7.8, 200.0, 0.3, yield_stress=1.5)
    assert c.yield_stress == 1.5 and c.poisson == 0.3
