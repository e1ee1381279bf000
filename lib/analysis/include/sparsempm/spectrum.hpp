// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file spectrum.hpp
/// Spectra of the mass matrices (FMPM 2026 §2.2, §3.3): ρ(A), the smallest eigenvalue of
/// m⁻¹m̃, cond(m̃), and the truncation error of FMPM(k) against the exact inverse.

#include "sparsempm/fmpm.hpp"
#include "sparsempm/operators.hpp"

namespace smpm {

/// The spectrum of the mass matrices of one configuration (mass_spectrum; FMPM 2026 §2.2).
struct MassSpectrum {
  double rho_A = 0;           ///< ρ(A) = 1 − λ_min(m⁻¹m̃) on the active nodes
  double min_eig_minv_mt = 0; ///< λ_min(m⁻¹m̃)
  double cond_mt = 0;         ///< λ_max(m̃) / λ_min(m̃) on the active nodes
  Index active = 0;           ///< number of active nodes
};

/// A = I − m⁻¹m̃ is similar to the symmetric I − B, B = m^{-1/2} m̃ m^{-1/2}, whose eigenvalues
/// lie in [0, 1): ρ(A) is the largest (Spectra SymEigsSolver; dense below `dense_limit`
/// active nodes); cond(m̃) likewise from the extreme eigenvalues of m̃ itself.
MassSpectrum mass_spectrum(const Operators& ops, const SparseRowMatrix& mt,
                           Index dense_limit = 2000);

/// ‖m̃_k⁻¹ p − v_exact‖ / ‖v_exact‖ for the FMPM(k) inverse of `opt` (order, blending) and the
/// exact v_exact = m̃⁻¹ p (FMPM 2026 Eq. 5 against Eq. 2's limit); 0 when both are zero (a
/// model at rest).
double truncation_error(const Operators& ops, const SparseRowMatrix& mt, const FmpmOptions& opt,
                        const Field& p, const Field& v_exact);

} // namespace smpm
