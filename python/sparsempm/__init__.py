# SPDX-License-Identifier: BSD-3-Clause
"""sparsempm: the Material Point Method with every operator of a step an explicit sparse matrix.

The C++ library (S, G, M, m, the consistent mass m~ = S^T M S, S+ = m^-1 S^T M, A = I - S+ S,
the step, its linearisation and the stability analyses) with numpy arrays and scipy.sparse
matrices:

    import sparsempm as smpm
    model = smpm.Model.from_toml("examples/vibrating_bar.toml", {"step.velocity": "FMPM"})
    ops = smpm.assemble(model, "cpdi")          # ops.S, ops.G, ops.M, ops.m, ops.active
    A = ops.expansion_matrix()                  # scipy.sparse.csr_matrix
    print(smpm.mass_spectrum(ops).rho_A)

Heat transport (FMPM 2026 §3.5) has the same form with the capacities in the place of the masses:
transport_operators(model) gives c = S^T C 1, c~ = S^T C S (consistent_capacity()) and the
conductivity K; fmpm_temperature and exact_temperature apply c~_k^-1 and c~^-1 to a heat content;
critical_fourier(model) is the critical Fourier number F* of the transport (a CriticalFourier).

The tables of `smpm stability`, `smpm transport-stability` and `smpm spectrum` read with
read_table(path) (rows keyed by the columns' names, which are the results' names here:
critical_courant, simulation_courant, critical_fourier, rho_T, configuration; the earlier names of
EARLIER_COLUMNS are read too, in this release only).

Errors are InputError (bad input, the messages of `smpm run`) and NumericalError.
Threads: SMPM_THREADS at import (else OMP_NUM_THREADS or every core), or set_threads(n); the
results are the same bit for bit for any number. Waiting threads spin briefly, then sleep
(OMP_WAIT_POLICY=passive, GOMP_SPINCOUNT=1000, as `smpm`: set here unless the environment chose
either before the first OpenMP library was loaded), so that runs sharing the cores do not slow
each other down and a region's fork and join do not each go through the kernel.
"""

import os as _os

# libgomp reads the policy when it is loaded, that is when the extension below is imported.
if "OMP_WAIT_POLICY" not in _os.environ and "GOMP_SPINCOUNT" not in _os.environ:
    _os.environ["OMP_WAIT_POLICY"] = "passive"
    _os.environ["GOMP_SPINCOUNT"] = "1000"

import numpy as _np
from scipy.sparse.linalg import LinearOperator as _LinearOperator

from ._sparsempm import (  # noqa: F401
    AdvanceReport,
    BoundaryConditions,
    ConfigurationSweep,
    CriticalCourant,
    CriticalFourier,
    Energies,
    Grid,
    InputError,
    LinearizedStep,
    MassSpectrum,
    Material,
    Model,
    NumericalError,
    Operators,
    Particles,
    SimulationCourant,
    SpectralRadius,
    StepOptions,
    Stepper,
    ThermalSums,
    Transport,
    TransportState,
    UsageError,
    __version__,
    assemble,
    contact_momentum_change,
    courant_of,
    critical_courant,
    critical_fourier,
    diffusion_time,
    exact_temperature,
    exact_velocity,
    fmpm_temperature,
    fmpm_velocity,
    mass_spectrum,
    residual_polynomial,
    set_threads,
    simulation_courant,
    stable_time_step,
    sweep_shifts,
    thermal_sums,
    threads,
    transport_operators,
)
from ._sparsempm import _spectral_radius
from .runfile import Run, read_run  # noqa: F401
from .tables import EARLIER_COLUMNS, read_table  # noqa: F401

for _error in (InputError, NumericalError, UsageError):
    _error.__module__ = __name__  # tracebacks name sparsempm.InputError
InputError.__doc__ = ("Bad input (a ValueError): the one-line message of `smpm run`, naming the "
                      "file, key and value.")
NumericalError.__doc__ = ("A numerical failure (a RuntimeError): NaN, blow-up or a particle "
                          "leaving the grid, naming the step and the particle or node.")
UsageError.__doc__ = ("A call the object's state does not allow (a RuntimeError), e.g. a "
                      "Stepper used from a second thread.")


class LinearizedStepOperator(_LinearOperator):
    """The linearised step T(C) as a scipy LinearOperator on x = (V, sigma).

    Products use the dense T (computed once, one product per column) when T has at most
    `dense_limit` rows, and the library's matrix-free product otherwise. `step` is the
    underlying sparsempm.LinearizedStep.
    """

    def __init__(self, step, dense_limit):
        self.step = step
        self.dense_limit = dense_limit
        self._dense = step.dense() if step.rows <= dense_limit else None
        super().__init__(dtype=_np.float64, shape=(step.rows, step.rows))

    def _matvec(self, x):
        x = _np.asarray(x, dtype=_np.float64).reshape(-1)
        if self._dense is not None:
            return self._dense @ x
        return self.step.matvec(x)

    def _adjoint(self):
        return _LinearOperator(dtype=_np.float64, shape=self.shape,
                               matvec=lambda y: self.toarray().T @ y)

    def toarray(self):
        """T as a dense numpy array."""
        return self._dense if self._dense is not None else self.step.dense()


def linearized_step(model, options=None, courant=0.5, dense_limit=1500):
    """One step linearised at the model's frozen configuration, T(C), as a LinearOperator.

    options default to model.options; dt = stable_time_step(model, courant). Below
    `dense_limit` rows the dense T is formed once and used for the products.
    """
    return LinearizedStepOperator(LinearizedStep(model, options, courant), dense_limit)


def spectral_radius(T, dense_limit=1500):
    """rho(T) of a linearised step (linearized_step() or a LinearizedStep) by the library:
    dense eigenvalues up to `dense_limit` rows, power iteration and Arnoldi (Spectra) above.
    Returns a SpectralRadius (rho, status)."""
    step = T.step if isinstance(T, LinearizedStepOperator) else T
    return _spectral_radius(step, dense_limit)
