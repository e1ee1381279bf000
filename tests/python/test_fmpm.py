# SPDX-License-Identifier: BSD-3-Clause
"""FMPM(k) and the exact inverse from Python against the same expressions in scipy
(FMPM 2026 Eqs. 5-6, §3.3; the limit k → ∞, m̃⁻¹)."""
import numpy as np
import pytest
import scipy.sparse.linalg

import sparsempm as smpm
from conftest import SOURCE


@pytest.fixture
def bar_state(bar):
    """Operators of the bar (CPDI) and the grid momentum of its first-mode velocity."""
    ops = smpm.assemble(bar)
    return ops, ops.momentum(bar.particles.V)


def lumped(ops, p):
    """m⁻¹ p on the active nodes, 0 elsewhere."""
    return ops.m_inv[:, None] * p


@pytest.mark.parametrize("k", range(1, 7))
def test_fmpm_is_the_truncated_series(bar_state, k):
    ops, p = bar_state
    A = ops.expansion_matrix()
    # v⁺(k) = Σ_{j<k} Aʲ m⁻¹ p (FMPM 2026 Eq. 5).
    term = lumped(ops, p)
    ref = np.zeros_like(p)
    for _ in range(k):
        ref += term
        term = A @ term
    v = smpm.fmpm_velocity(ops, p, k)
    assert v.shape == p.shape
    # Velocities of size 0.16: round-off of k products.
    assert np.abs(v - ref).max() < 1e-12
    if k > 1:  # the series changes v: the comparison cannot pass by returning m⁻¹ p
        assert np.abs(ref - lumped(ops, p)).max() > 1e-6
    # A vector p gives a vector v.
    assert np.abs(smpm.fmpm_velocity(ops, p[:, 0], k) - ref[:, 0]).max() < 1e-12


def test_blended_series(bar_state):
    ops, p = bar_state
    A = ops.expansion_matrix()
    alpha, every, k = 0.8, 2, 6
    # Δv(ℓ) = c_ℓ A Δv(ℓ−1), c_ℓ = α when ℓ mod m = 1 (FMPM 2026 §3.3, blend with FMPM(2)).
    dv = lumped(ops, p)
    ref = dv.copy()
    for ell in range(2, k + 1):
        dv = (alpha if ell % every == 1 else 1.0) * (A @ dv)
        ref += dv
    v = smpm.fmpm_velocity(ops, p, k, blend_alpha=alpha, blend_every=every)
    assert np.abs(v - ref).max() < 1e-12
    with pytest.raises(smpm.InputError):
        smpm.fmpm_velocity(ops, p, 0)


def test_exact_velocity_solves_the_consistent_mass(bar_state):
    ops, p = bar_state
    act = ops.active
    mt = ops.consistent_mass().tocsc()[act][:, act]
    ref = scipy.sparse.linalg.spsolve(mt, p[act, 0])
    v = smpm.exact_velocity(ops, p)
    # m̃_aa v_a = p_a on the active nodes a (CHOLMOD against SuperLU; the velocities are of
    # size 0.16 and cond(m̃) of the unshifted bar is moderate).
    assert np.abs(v[act, 0] - ref).max() < 1e-10
    assert np.all(v[~act] == 0)
    # FMPM(k) converges to it (ρ(A) = 0.75: 0.75^200 ≈ 1e-25).
    assert np.abs(smpm.fmpm_velocity(ops, p, 200) - v).max() < 1e-10


def test_exact_velocity_with_the_fixed_end(bar, bar_state):
    ops, p = bar_state
    fixed = np.flatnonzero(np.isclose(ops.grid.node_positions()[:, 0], 0.0))
    assert fixed.size == 1
    free = ops.active.copy()
    free[fixed] = False
    mt = ops.consistent_mass().tocsc()[free][:, free]
    ref = scipy.sparse.linalg.spsolve(mt, p[free, 0])
    v = smpm.exact_velocity(ops, p, bcs=bar.bcs)
    # The fixed node keeps v = 0 and the free ones solve m̃_FF v_F = p_F (exact.hpp).
    assert v[fixed[0], 0] == 0
    assert np.abs(v[free, 0] - ref).max() < 1e-10


@pytest.mark.parametrize("k", [1, 2, 4, 8])
def test_fmpm_velocity_holds_the_fixed_end_by_each_bc_method(bar, bar_state, k):
    # FMPM 2026 §3.1, Table 2: the incremental method (lumped BCs on v⁺(1), the BC direction of
    # every increment zeroed), the velocity method (BCs set on v⁺(k)) and the combined one keep
    # the fixed node at v = 0 for every k; the lumped method (BCs on v⁺(1) only) lets the
    # increments move it once k > 1. ops.bcs are the BCs a step from this configuration uses.
    ops, p = bar_state
    fixed = np.flatnonzero(np.isclose(ops.grid.node_positions()[:, 0], 0.0))[0]
    for method in ("incremental", "velocity", "combined"):
        v = smpm.fmpm_velocity(ops, p, k, bcs=ops.bcs, bc_method=method)
        assert v[fixed, 0] == 0, method
    lumped_only = smpm.fmpm_velocity(ops, p, k, bcs=ops.bcs, bc_method="lumped")
    assert (abs(lumped_only[fixed, 0]) > 1e-6) == (k > 1)
    # Without BCs the fixed node moves with its neighbours.
    assert abs(smpm.fmpm_velocity(ops, p, k)[fixed, 0]) > 1e-6


def test_the_model_bcs_of_a_model_with_walls_are_refused():
    # A wall's nodes are selected by each step on its own copy of the BCs (step_preparation.hpp):
    # model.bcs holds none, ops.bcs those at the model's time. fmpm_velocity and exact_velocity
    # refuse model.bcs with a wall (its velocities would silently be left free).
    model = smpm.Model.from_toml(str(SOURCE / "examples" / "two_block_compression.toml"))
    ops = smpm.assemble(model)
    p = ops.momentum(model.particles.V)
    assert model.bcs.walls == 1 and ops.bcs.num_constrained > model.bcs.num_constrained
    for call in (smpm.fmpm_velocity, smpm.exact_velocity):
        with pytest.raises(smpm.InputError, match="pass ops.bcs"):
            call(ops, p, bcs=model.bcs)
    v = smpm.fmpm_velocity(ops, p, 2, bcs=ops.bcs)
    assert v.shape == p.shape


def test_add_bc_checks_the_conditions_already_there():
    # FMPM 2026 Table 2: conditions sharing a node must be parallel or perpendicular, across
    # every add_bc as in one input file.
    model = smpm.Model.from_toml(str(SOURCE / "examples" / "two_block_compression.toml"))
    with pytest.raises(smpm.InputError, match="at an angle"):
        model.add_bc({"plane": {"axis": "y", "at": 0.0},
                      "velocity": {"direction": [1.0, 1.0], "value": 0.0}})


def test_the_conditions_of_another_grid_are_refused(bar_state):
    # A condition names nodes of its model's grid: on operators of a smaller grid a node beyond it
    # is refused with the condition's name (it was read and written out of bounds).
    ops, p = bar_state
    big = smpm.Model(smpm.Grid(cells=[2000000]), X=[1.5], mass=[1], volume0=[1],
                     materials=[smpm.Material()])
    big.fix_plane("x", 1999999.0, ["x"])
    for call in (smpm.fmpm_velocity, smpm.exact_velocity):
        with pytest.raises(smpm.InputError, match="names node 1999999, not a node of this grid"):
            call(ops, p, bcs=big.bcs)


def test_a_wall_of_ops_bcs_takes_the_time_of_the_product():
    # ops.bcs selects the wall's nodes at the model's time; its value v(t) + grad v (s - s_w(t))
    # is that of the time given to fmpm_velocity (the step's own copy is evaluated once, at the
    # step's time).
    path = SOURCE / "examples" / "two_block_compression.toml"
    text = path.read_text()
    k = text[:text.index("wall = {")].count("[[bc]]") - 1
    model = smpm.Model.from_toml(str(path), {"bc.%d.wall.velocity" % k: "-2*t"})
    ops = smpm.assemble(model)
    p = ops.momentum(model.particles.V)
    for t in (0.5, 1.5):  # the wall's nodes (a row of the 40 mm top, and those beyond it)
        v = smpm.fmpm_velocity(ops, p, 1, bcs=ops.bcs, time=t)
        assert np.isclose(v[:, 1], -2 * t, rtol=0, atol=1e-12).sum() >= 10
