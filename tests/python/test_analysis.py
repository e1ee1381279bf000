# SPDX-License-Identifier: BSD-3-Clause
"""Spectra and stability from Python: the linearised step as a scipy LinearOperator, ρ(T) by
scipy against the library, C* against `smpm stability`, ρ(A) against a dense eigensolver."""
import signal
import warnings

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

import sparsempm as smpm

from conftest import BAR, interrupting, run_smpm


def options(bar, scheme, k=1):
    """The options of a row of `smpm stability` (make_rows of apps/stability_command.cpp)."""
    o = bar.options.copy()
    o.velocity = scheme
    o.order = k
    return o


def scipy_rho(T):
    """ρ(T) by ARPACK (scipy.sparse.linalg.eigs), to 1e-13."""
    mu = scipy.sparse.linalg.eigs(T, k=1, which="LM", tol=1e-13, return_eigenvectors=False)
    return abs(mu[0])


@pytest.mark.parametrize("scheme,k,courant", [("FLIP", 1, 1.0), ("FMPM", 4, 0.7)])
def test_linearised_spectral_radius_matches_scipy(bar, scheme, k, courant):
    # Unstable Courant numbers (above C* = 0.7555 and 0.5547): a dominant eigenvalue off the
    # unit circle, so that ARPACK converges.
    T = smpm.linearized_step(bar, options(bar, scheme, k), courant)
    assert isinstance(T, scipy.sparse.linalg.LinearOperator)
    assert T.shape == (160, 160)  # x = (V, σ): N d + N d² with N = 80, d = 1
    rho = smpm.spectral_radius(T)
    assert rho.status == "converged" and rho.rho_T > 1.01
    # The library's ρ (dense eigenvalues) against ARPACK on the LinearOperator.
    assert rho.rho_T == pytest.approx(scipy_rho(T), abs=1e-8)
    # The matrix-free operator (library products, no dense T) gives the same ARPACK result,
    # and the library's matrix-free path (power iteration + Spectra's Arnoldi) the same ρ.
    Tf = smpm.linearized_step(bar, options(bar, scheme, k), courant, dense_limit=0)
    x = np.random.default_rng(1).standard_normal(160)
    assert np.abs(Tf @ x - T @ x).max() < 1e-12
    assert scipy_rho(Tf) == pytest.approx(rho.rho_T, abs=1e-8)
    assert smpm.spectral_radius(Tf, dense_limit=0).rho_T == pytest.approx(rho.rho_T, abs=1e-8)


def stability_table(tmp_path, *args):
    out = tmp_path / "stability.csv"
    r = run_smpm("stability", BAR, "--order", "4", "--method", "spectral", "--no-exact", "-q",
                 "-o", out, *args)
    assert r.returncode == 0, r.stderr
    rows = smpm.read_table(out)
    flip = next(r for r in rows if r["velocity"] == "FLIP")
    fmpm = next(r for r in rows if r["order"] == "4" and r["blend_alpha"] == "1" and r["blend_every"] == "1"
                and r["periodic_cx"] == "")
    return flip, fmpm


def test_critical_courant_matches_the_command(bar, tmp_path):
    # One configuration (--shifts 1): critical_courant at the input's lattice.
    flip, fmpm = stability_table(tmp_path, "--shifts", "1")
    c_flip = smpm.critical_courant(bar, options(bar, "FLIP")).critical_courant
    c_fmpm = smpm.critical_courant(bar, options(bar, "FMPM", 4)).critical_courant
    # The table prints 4 significant digits (0.7555 and 0.5547 in docs/studies/stability.md's bar).
    assert f"{c_flip:.4g}" == flip["critical_courant"] and f"{c_fmpm:.4g}" == fmpm["critical_courant"]
    assert c_fmpm < c_flip - 0.1  # FMPM(4) is less stable than FLIP (FMPM 2026 Fig. 12A)
    # Started from a neighbour's C* (hint), the search finds the same grid point: from
    # FMPM(2)'s 0.641 in as many spectral radii (measured 18 and 18), from a close one in far
    # fewer (measured 8 from C* + 0.002). Every search first examines the same 4 small C (the
    # limit C -> 0 and 0.05 / 4^j for j = 1, 2, 3): the hint shortens the rest, 14 -> 4.
    small = 4
    c2 = smpm.critical_courant(bar, options(bar, "FMPM", 2)).critical_courant
    plain = smpm.critical_courant(bar, options(bar, "FMPM", 4))
    assert plain.small == "stable" and plain.small_courant == "stable to 0" and plain.stable_from == 0
    rest = plain.evaluations - small
    for hint, most in ((c2, rest), (plain.critical_courant + 0.002, rest // 2)):
        hinted = smpm.critical_courant(bar, options(bar, "FMPM", 4), hint=hint)
        assert hinted.critical_courant == plain.critical_courant and hinted.evaluations - small <= most
    # The default sweep over 4 lattice shifts (the numbers of docs/studies/stability.md's table: FLIP 0.755,
    # FMPM(4) 0.451).
    flip, fmpm = stability_table(tmp_path)
    s_flip = smpm.sweep_shifts(bar, options(bar, "FLIP"), 4)
    s_fmpm = smpm.sweep_shifts(bar, options(bar, "FMPM", 4), 4)
    assert f"{s_flip.minimum.critical_courant:.4g}" == flip["critical_courant"]
    assert f"{s_fmpm.minimum.critical_courant:.4g}" == fmpm["critical_courant"]
    assert s_fmpm.configuration == fmpm["configuration"]
    # The earlier attribute names, for one release, with a DeprecationWarning each.
    with pytest.warns(DeprecationWarning, match="'courant' is the earlier name of 'critical_courant'"):
        assert plain.courant == plain.critical_courant
    with pytest.warns(DeprecationWarning, match="'rho' is the earlier name of 'rho_T'"):
        assert plain.rho == plain.rho_T
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert float(plain) == plain.critical_courant  # the current names warn of nothing


def test_mass_spectrum_matches_dense_eigenvalues(bar):
    ops = smpm.assemble(bar)
    ms = smpm.mass_spectrum(ops)
    act = ops.active
    A = ops.expansion_matrix().toarray()[np.ix_(act, act)]
    # ρ(A) = max eigenvalue of A on the active nodes (spectrum.hpp), dense LAPACK round-off.
    assert ms.active == act.sum()
    assert ms.rho_A == pytest.approx(np.abs(scipy.linalg.eigvals(A)).max(), abs=1e-12)
    mt = ops.consistent_mass().toarray()[np.ix_(act, act)]
    w = scipy.linalg.eigvalsh(mt)
    assert ms.cond_mt == pytest.approx(w.max() / w.min(), rel=1e-9)


def test_the_matrix_free_product_of_a_c_ordered_block(bar):
    # T @ X with X C-ordered hands each column to matvec as a strided view; the matrix-free
    # product read it as contiguous memory (a wrong T @ X above the dense limit).
    T = smpm.linearized_step(bar, dense_limit=0)
    assert T.shape[0] > 3
    X = np.random.default_rng(7).standard_normal((T.shape[0], 3))
    Y = T @ X
    for j in range(3):
        np.testing.assert_array_equal(Y[:, j], T.step.matvec(np.ascontiguousarray(X[:, j])))
    np.testing.assert_array_equal(T @ np.asfortranarray(X), Y)


@pytest.mark.parametrize("search", ["sweep_shifts", "simulation_courant"])
def test_ctrl_c_stops_the_searches(bar, search):
    # The searches run with the GIL released; Python's handler ran only once they returned, with
    # their result. Now SIGINT stops them at the next evaluation of rho(T) (or step of a run):
    # Python's handler runs then (here one that raises nothing) and, as the search has no
    # result, the call raises KeyboardInterrupt.
    with interrupting(raises=False) as ctrl_c:
        with pytest.raises(KeyboardInterrupt):
            if search == "sweep_shifts":  # 300 shifts: about 20 s uninterrupted
                smpm.sweep_shifts(bar, None, 300, workers=1)
            else:  # about 20 s uninterrupted
                smpm.simulation_courant(bar, end=40 * bar.end)
    assert ctrl_c.seen and set(ctrl_c.seen) == {signal.SIGINT}
