# SPDX-License-Identifier: BSD-3-Clause
"""The operators from Python: the invariants of FMPM 2026 §2.1 on the scipy matrices, the values
of S for the four particles of docs/guide/cpp.md, and numpy views of the particle fields."""
import numpy as np
import pytest
import scipy.linalg
import scipy.sparse

import sparsempm as smpm

from conftest import TWO_BLOCKS


@pytest.mark.parametrize("shape", ["linear", "gimp", "bspline2", "cpdi", "b2cpdi"])
def test_partition_of_unity_on_the_bar(bar, shape):
    ops = smpm.assemble(bar, shape)
    assert isinstance(ops.S, scipy.sparse.csr_matrix)
    assert ops.S.shape == (80, 49)
    # S 1 = 1 for every particle: the shape functions are a partition of unity (round-off).
    assert np.abs(ops.S @ np.ones(ops.num_nodes) - 1).max() < 1e-13
    # Σ_i G_pi = 0: the gradient of a constant (round-off of entries of size 1/cell).
    assert np.abs(ops.G[0] @ np.ones(ops.num_nodes)).max() < 1e-13
    # m = Sᵀ M (the definition of the lumped mass, to round-off of masses of size 0.25).
    assert np.abs(ops.S.T @ ops.M - ops.m).max() < 1e-14


def test_consistent_mass_rows_sum_to_lumped_mass(bar):
    ops = smpm.assemble(bar)
    mt = ops.consistent_mass()
    assert isinstance(mt, scipy.sparse.csr_matrix)
    # m̃ = Sᵀ diag(M) S, assembled by the library, equals the scipy product (round-off).
    assert abs(mt - ops.S.T @ scipy.sparse.diags(ops.M) @ ops.S).max() < 1e-15
    # Rows of m̃ sum to m (FMPM 2026 §2.1), to round-off relative to max m = 0.5.
    assert np.abs(np.asarray(mt.sum(axis=1)).ravel() - ops.m).max() < 1e-14 * ops.m.max()


@pytest.mark.parametrize("shape", ["gimp", "bspline2", "cpdi"])
def test_transfer_mass_of_the_velocity_gradient_transfer(bar, shape):
    # m̃_L = Sᵀ M S + Dᵀ M G with D = S ∘ (x_i − X_p) (operators.hpp), against scipy on the bar
    # shifted by ⅛ cell: round-off of entries of size 0.5; its rows sum to m and it maps an
    # affine field v = a + b x to m v (Σ_i S_pi (x_i − X_p) = 0, G x = 1); not symmetric.
    bar.particles.X = bar.particles.X + 0.125
    ops = smpm.assemble(bar, shape)
    x = bar.grid.node_positions()[:, 0]
    X = bar.particles.X[:, 0]
    D = scipy.sparse.csr_matrix(ops.S.multiply(x[None, :] - X[:, None]))
    expected = (ops.S.T @ scipy.sparse.diags(ops.M) @ ops.S + D.T @ scipy.sparse.diags(ops.M) @ ops.G[0]).toarray()
    mL = ops.transfer_mass()
    assert np.abs(mL.toarray() - expected).max() < 1e-14
    v = 0.3 - 2.0 * x
    assert np.abs(mL @ v - ops.m * v).max() < 1e-12 * np.abs(ops.m * v).max()
    assert abs(mL - mL.T).max() > 1e-3


@pytest.mark.parametrize("shape", ["gimp", "bspline2", "cpdi"])
def test_apic_mass(bar, shape):
    # m̃_A = Σ_p M_p S_pi S_pj (1 + Δ_pi Δ_pj / D_p) in 1D, D_p = Σ_i S_pi Δ_pi² (Jiang et al.
    # 2015), against scipy on the bar shifted by ⅛ cell: round-off of entries of size 0.5. It is
    # symmetric, its rows sum to m, it maps an affine field to m times it, and m̃ ≤ m̃_A ≤ m: the
    # eigenvalues of m^-½ (m̃_A − m̃) m^-½ and of I − m^-½ m̃_A m^-½ on the active nodes are ≥ 0
    # (to -1e-12).
    bar.particles.X = bar.particles.X + 0.125
    ops = smpm.assemble(bar, shape)
    x = bar.grid.node_positions()[:, 0]
    X = bar.particles.X[:, 0]
    D = ops.S.multiply(x[None, :] - X[:, None]).toarray()
    Dp = (D * (x[None, :] - X[:, None])).sum(axis=1)
    expected = ops.S.T.toarray() @ np.diag(ops.M) @ ops.S.toarray() + D.T @ np.diag(ops.M / Dp) @ D
    mA = ops.apic_mass().toarray()
    assert np.abs(mA - expected).max() < 1e-14
    assert np.abs(mA - mA.T).max() < 1e-15
    assert np.abs(mA.sum(axis=1) - ops.m).max() < 1e-14
    v = 0.3 - 2.0 * x
    assert np.abs(mA @ v - ops.m * v).max() < 1e-12 * np.abs(ops.m * v).max()
    act = ops.active
    s = 1 / np.sqrt(ops.m[act])
    mt = ops.consistent_mass().toarray()[np.ix_(act, act)]
    A = s[:, None] * mA[np.ix_(act, act)] * s[None, :]
    assert np.linalg.eigvalsh(A - s[:, None] * mt * s[None, :]).min() > -1e-12
    assert np.linalg.eigvalsh(np.eye(len(s)) - A).min() > -1e-12


def test_particle_gradients_and_the_transfer_option(bar):
    bar.options.transfer = "velocity_gradient"
    assert bar.options.transfer == "velocity_gradient"
    with pytest.raises(smpm.InputError, match="standard"):
        bar.options.transfer = "affine"
    assert bar.particles.gradient.shape[0] == 0  # none until a step with the transfer
    smpm.Stepper(bar.options).step(bar, 0.1)
    assert bar.particles.gradient.shape == (80, 1)  # L = G v⁺ of the step: ∂V/∂x of the mode
    assert np.abs(bar.particles.gradient).max() > 0
    bar.particles.gradient = np.full((80, 1), 0.5)
    assert np.all(bar.particles.gradient == 0.5)
    with pytest.raises(ValueError, match="gradient"):
        bar.particles.gradient = np.zeros((80, 2))


def test_expansion_matrix_spectrum_in_unit_interval(bar):
    ops = smpm.assemble(bar)
    A = ops.expansion_matrix().toarray()
    # A = I − m⁻¹ m̃ on the active nodes (FMPM 2026 Eq. 1), to round-off.
    act = ops.active
    mt = ops.consistent_mass().toarray()
    ref = np.eye(act.sum()) - mt[np.ix_(act, act)] / ops.m[act][:, None]
    assert np.abs(A[np.ix_(act, act)] - ref).max() < 1e-14
    # A is similar to a symmetric matrix: real eigenvalues in [0, 1) (FMPM 2026 §2.2); the
    # tolerance below 0 is the round-off of the dense eigensolver.
    mu = scipy.linalg.eigvals(A)
    assert np.abs(mu.imag).max() < 1e-10
    assert mu.real.min() > -1e-12 and mu.real.max() < 1
    # S⁺ S = I − A (the reverse map of FMPM 2026 §2.1).
    SpS = (ops.S_plus() @ ops.S).toarray()
    assert np.abs(SpS[np.ix_(act, act)] + A[np.ix_(act, act)] - np.eye(act.sum())).max() < 1e-14


def test_readme_four_particles_from_arrays():
    # docs/guide/cpp.md's "MPM as matrices": 4 particles of mass 1/4 at 0.75 ... 2.25 on nodes 0 ... 3.
    grid = smpm.Grid(cells=[3])
    model = smpm.Model(grid, X=[0.75, 1.25, 1.75, 2.25], mass=np.full(4, 0.25),
                       volume0=np.full(4, 0.5), materials=[smpm.Material("m", density=0.5)])
    ops = smpm.assemble(model, "linear")
    # Linear hats: S_pi = 1 − |X_p − x_i| (exact in binary).
    S_exact = np.array([[0.25, 0.75, 0, 0], [0, 0.75, 0.25, 0], [0, 0.25, 0.75, 0],
                        [0, 0, 0.75, 0.25]])
    assert np.array_equal(ops.S.toarray(), S_exact)
    assert np.array_equal(ops.m, [0.0625, 0.4375, 0.4375, 0.0625])
    # m̃ of docs/guide/cpp.md: 0.25 (S_pi S_pj) summed over particles, exact in binary.
    assert np.array_equal(ops.consistent_mass().toarray(), 0.25 * S_exact.T @ S_exact)


def test_particle_fields_are_views(bar):
    P = bar.particles
    assert P.X.shape == (80, 1) and P.F.shape == (80, 1) and P.mass.shape == (80,)
    P.V[:, 0] = 2.0  # writes the library's storage
    assert bar.energies().kinetic == pytest.approx(0.5 * 2.0**2 * P.mass.sum(), rel=1e-15)
    ops = smpm.assemble(bar)
    # p = Sᵀ (M ∘ V) of the library equals the scipy product (round-off).
    p = ops.momentum(P.V)
    assert np.abs(p - ops.S.T @ (ops.M[:, None] * P.V)).max() < 1e-14
    P.V = np.zeros((80, 1))  # assignment copies into the same storage
    assert bar.energies().kinetic == 0
    with pytest.raises(ValueError, match="expected shape"):
        P.V = np.zeros((79, 1))
    # Operators' arrays are read-only views of the assembled storage.
    with pytest.raises(ValueError):
        ops.S.data[0] = 1


def test_velocity_fields_are_blocks_of_columns():
    # Two blocks, each material its own velocity field ([[contact]]), as Stepper::step assembles
    # them: node i of field α is column α n_g + i (operators.hpp).
    model = smpm.Model.from_toml(str(TWO_BLOCKS))
    ops = smpm.assemble(model)
    n_g = ops.grid_node_count
    assert ops.fields == 2 and n_g == ops.grid.num_nodes == 13 * 25  # cells = [12, 24]
    assert ops.S.shape == (640, 2 * n_g)  # 2 × (40 × 50 mm / 2.5² mm² per particle)
    # Fields are numbered in the order of the materials (input_contact.cpp): lower 0, upper 1.
    field = ops.particle_field
    assert np.array_equal(field, model.particles.material) and np.bincount(field).tolist() == [320, 320]
    # Each particle's row of S (and of every G) has entries only in its field's block.
    for B in [ops.S, *ops.G]:
        C = B.tocoo()
        assert np.array_equal(C.col // n_g, field[C.row])
    # Each row still sums to 1 (partition of unity within the block; round-off).
    assert np.abs(ops.S @ np.ones(ops.num_nodes) - 1).max() < 1e-13
    # m summed over the blocks equals the single-field m (the same sums Σ_p M_p S_pi split by
    # field): 1e-12 relative to max m.
    single = smpm.assemble(smpm.Model.from_toml(str(TWO_BLOCKS), {"contact.0.law": "single-field"}))
    assert single.fields == 1 and single.S.shape == (640, n_g)
    summed = ops.m.reshape(2, n_g).sum(axis=0)
    assert np.abs(summed - single.m).max() <= 1e-12 * single.m.max()
    # Exactly the 9 nodes of the interface (y = 50 mm, 0 ≤ x ≤ 40 mm: grid row 12, columns 2 to
    # 10, x fastest) carry mass in both fields (GIMP particles end at the interface).
    both = (ops.m[:n_g] > 0) & (ops.m[n_g:] > 0)
    assert np.array_equal(np.nonzero(both)[0], 12 * 13 + np.arange(2, 11))
    # m̃ is block diagonal (FMPM 2026 Eq. 15): no entry couples two fields.
    C = ops.consistent_mass().tocoo()
    assert C.nnz > 0 and np.array_equal(C.row // n_g, C.col // n_g)
