# SPDX-License-Identifier: BSD-3-Clause
"""A program's part seen from Python: the module built with the toy part of
tests/parts/toy_part.cpp linked in (each particle's path length s_p = ∫ |V_p| dt, registered when
the module loads) has the part's column as a particle property like the library's own columns:
a view of the storage the step advances, set by a number or the particles' values within the
column's range, carried by copies; the linearised step refuses the part with its sentence."""
import os
from pathlib import Path

import numpy as np
import pytest

import sparsempm as smpm

# ctest runs this file against the module built with the part (python.toy_part sets
# SMPM_TOY_PART); a run of tests/python against the module without it passes over it.
if "SMPM_TOY_PART" not in os.environ:
    pytest.skip("needs the module built with tests/parts/toy_part.cpp (ctest -R python.toy_part)",
                allow_module_level=True)

# A block in free flight at V = (0.3, 0.4): |V| = 0.5, no force, so s_p = 0.5 t (the C++ tests'
# block).
TOY = Path(os.environ["SMPM_SOURCE"]) / "tests" / "parts" / "toy.toml"


@pytest.fixture
def model():
    return smpm.Model.from_toml(str(TOY))


def test_the_parts_column_is_a_particle_property(model):
    doc = type(model.particles).path_length.__doc__
    assert doc.startswith("N path length of each particle since t = 0")
    # No step yet: the part gives the particles its column when a Stepper first steps them.
    assert model.particles.path_length.shape == (0,)


def test_the_step_advances_the_storage_python_sees(model):
    stepper = smpm.Stepper(model.options)
    for _ in range(20):
        stepper.step(model, 0.1)
    s = model.particles.path_length
    assert s.shape == (len(model.particles),) and len(model.particles) == 36
    # s_p = |V| t = 0.5 × 2.0: the block translates rigidly, its velocities change by rounding
    # only (tolerance 1e-12 of s).
    assert np.max(np.abs(s - 1.0)) < 1e-12
    # The array is a view of the part's storage: written from Python, the next step adds
    # |V| Δt = 0.05 to what Python wrote, and the same array sees it.
    s[:] = np.arange(36.0)
    stepper.step(model, 0.1)
    assert np.max(np.abs(s - (np.arange(36.0) + 0.05))) < 1e-12
    # Set by a number (every particle), through the property.
    model.particles.path_length = 2.0
    stepper.step(model, 0.1)
    assert np.max(np.abs(model.particles.path_length - 2.05)) < 1e-12
    # A copy of the model carries the column, in storage of its own.
    other = model.copy()
    assert np.array_equal(other.particles.path_length, model.particles.path_length)
    other.particles.path_length = 0.0
    assert model.particles.path_length[0] == pytest.approx(2.05, abs=1e-12)


def test_values_outside_the_columns_range_are_refused(model):
    smpm.Stepper(model.options).step(model, 0.1)
    # The column's range (ColumnRange::NonNegative): a negative length names the particle.
    values = np.full(36, 0.5)
    values[7] = -1.0
    with pytest.raises(smpm.InputError, match="path_length: particle 7 has -1"):
        model.particles.path_length = values
    with pytest.raises(ValueError):
        model.particles.path_length = np.zeros(35)  # not one value per particle
    assert np.max(np.abs(model.particles.path_length - 0.05)) < 1e-12  # unchanged


def test_the_linearised_step_refuses_the_part(model):
    with pytest.raises(smpm.InputError,
                       match="^the particles' path lengths are not linear in the step's state$"):
        smpm.linearized_step(model, courant=0.5)
