# SPDX-License-Identifier: BSD-3-Clause
"""Errors from Python are the command's: InputError with the message `smpm run` prints after
"smpm: error: ", NumericalError with the one after "smpm: numerical failure: "."""
import numpy as np
import pytest

import sparsempm as smpm

from conftest import BAR, run_smpm


def cli_message(r, prefix):
    assert r.stderr.startswith(prefix), r.stderr
    return r.stderr[len(prefix):].rstrip("\n")


@pytest.mark.parametrize("old,new", [
    ("youngs = 2.0", "youngs = -2.0"),                     # a bad value
    ("courant = 0.5", "courrant = 0.5"),                   # an unknown key (nearest named)
    ('shape = "cpdi"', 'shape = "cpd"'),                   # an unknown name
])
def test_bad_input_file(tmp_path, old, new):
    text = BAR.read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    r = run_smpm("run", bad, "-q", "-o", tmp_path / "out.h5")
    assert r.returncode == 2
    expected = cli_message(r, "smpm: error: ")
    with pytest.raises(smpm.InputError) as e:
        smpm.Model.from_toml(str(bad))
    assert str(e.value) == expected
    assert isinstance(e.value, ValueError)


def test_bad_override(tmp_path):
    r = run_smpm("run", BAR, "-q", "-o", tmp_path / "out.h5", "--set", "step.order=0",
                 "--set", "step.velocity=FMPM")
    assert r.returncode == 2
    expected = cli_message(r, "smpm: error: ")
    with pytest.raises(smpm.InputError) as e:
        smpm.Model.from_toml(str(BAR), {"step.order": 0, "step.velocity": "FMPM"})
    assert str(e.value) == expected


def test_numerical_failure_message(tmp_path):
    # C = 1.5 is above FLIP's limit (0.86): the energy test stops the run (docs/getting-started.md).
    r = run_smpm("run", BAR, "-q", "-o", tmp_path / "out.h5", "--set", "time.courant=1.5")
    assert r.returncode == 3
    expected = cli_message(r, "smpm: numerical failure: ")
    model = smpm.Model.from_toml(str(BAR), {"time.courant": 1.5})
    with pytest.raises(smpm.NumericalError) as e:
        smpm.Stepper(model.options).advance(model, model.end, model.courant, stop_every=10.0)
    assert str(e.value) == expected


def test_arrays_outside_the_grid():
    grid = smpm.Grid(cells=[3])
    with pytest.raises(smpm.InputError, match="particle 1 lies outside the grid"):
        smpm.Model(grid, X=[0.5, 3.5], mass=[1, 1], volume0=[1, 1], materials=[smpm.Material()])
    with pytest.raises(smpm.InputError, match="material id 1 has no material"):
        smpm.Model(grid, X=[0.5, 1.5], mass=[1, 1], volume0=[1, 1], material=[0, 1],
                   materials=[smpm.Material()])
    with pytest.raises(smpm.InputError, match="poisson"):
        smpm.Material(poisson=0.5)
    with pytest.raises(smpm.InputError, match="expected"):
        smpm.StepOptions(velocity="FLOP")
    assert np.isfinite(smpm.Material(youngs=4, density=1).wave_speed(1))


def test_sizes_beyond_the_caps_are_refused(bar):
    # The CLI's --shifts cap (1 to 1000) holds for the library's sweep as well: a million
    # shifts were a million spectral searches with no way to stop them.
    with pytest.raises(smpm.InputError, match="lattice shifts must be 1 to 1000, got 1000000"):
        smpm.sweep_shifts(bar, None, 10**6)
    # cells + 1 nodes per axis wrapped around int: num_nodes was 0 for 2^31 - 1 cells.
    with pytest.raises(smpm.InputError, match=r"cells\[0\] must be 1 to 1073741824"):
        smpm.Grid([2**31 - 1] * 3)
    with pytest.raises(smpm.InputError, match="more than the 1125899906842624 a grid can number"):
        smpm.Grid([2**20] * 3)
    assert smpm.Grid([2**30]).num_nodes == 2**30 + 1
    assert smpm.Grid([2**16, 2**16, 2**16 - 2]).num_nodes == (2**16 + 1)**2 * (2**16 - 1)


def test_out_of_range_arguments_are_refused(bar):
    # Each of these ran before: a step backwards in time, a NaN clock, a failure test turned
    # off by NaN, C* = 0 for a negative tolerance, a negative mass set through the arrays' view.
    stepper = smpm.Stepper(bar.options)
    with pytest.raises(smpm.InputError, match="time step must be positive and finite, got -0.1"):
        stepper.step(bar, -0.1)
    with pytest.raises(smpm.InputError, match="time must be finite, got nan"):
        bar.time = float("nan")
    with pytest.raises(smpm.InputError, match="energy_growth must be a number"):
        stepper.advance(bar, end=1.0, energy_growth=float("nan"))
    with pytest.raises(smpm.InputError, match="tol must be non-negative and finite, got -1"):
        smpm.critical_courant(bar, tol=-1)
    bar.particles.mass[3] = -1.0
    with pytest.raises(smpm.InputError, match="particle 3: mass -1 must be positive and finite"):
        stepper.step(bar, 0.25)
    bar.particles.mass[3] = 1.0
    bar.particles.volume0[5] = float("inf")
    with pytest.raises(smpm.InputError, match="particle 5: volume0 inf must be positive"):
        stepper.step(bar, 0.25)
    assert bar.step == 0 and bar.time == 0
