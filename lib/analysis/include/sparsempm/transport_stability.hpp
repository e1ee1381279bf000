// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file transport_stability.hpp
/// Temporal stability of heat transport by MPM (FMPM 2026 §3.5 with the stability study of
/// §3.3): one transport step at a frozen configuration is a linear operator 𝒯(F) on the particle
/// temperatures, F = D_max Δt / Δx_min² the Fourier number (D = κ/(ρ C_V)); the update is stable
/// when ρ(𝒯(F)) ≤ 1 + tol (critical_fourier), the analogue of the critical Courant number of the
/// velocities (FMPM 2026 Fig. 12A) for the lumped, FMPM(k) and exact capacity inverses.

#include "sparsempm/stability.hpp"
#include "sparsempm/transport.hpp"

#include <atomic>
#include <memory>

namespace smpm {

/// One transport step at a frozen configuration as a linear operator on the N particle
/// temperatures: the Stepper's transport stages (transport_content, transport_update,
/// transport_particles of scheme.hpp) on the configuration's operators, with homogeneous
/// temperature conditions (the conditions' nodes held at zero: the linear part of the step) and
/// no contact heat or sources. In matrix form, with τ = Sᵀ 𝗖 T and the conduction's K c⁻¹:
///   lumped  𝒯 = I − Δt S c⁻¹ K c⁻¹ Sᵀ 𝗖,
///   FMPM(k) 𝒯 = S c̃_k⁻¹ (I − Δt K c⁻¹) Sᵀ 𝗖,  c̃_k⁻¹ = Σ_{j<k} A_cʲ c⁻¹ (exact: c̃⁻¹),
/// each with the conditions' rows. The operator concept is Spectra's: rows(), cols(),
/// perform_op(x, y).
class TransportStep {
public:
  using Scalar = double; ///< the scalar of Spectra's operator concept
  /// Validates the options; throws InputError unless they have heat transport and every
  /// material carries heat (prepare_transport).
  TransportStep(const Model& model, const StepOptions& options, double dt);
  ~TransportStep();
  /// Takes over the frozen configuration and its operators.
  TransportStep(TransportStep&&) noexcept;

  /// Changes Δt keeping every assembled operator.
  void set_dt(double dt);
  /// The time step Δt of 𝒯.
  double dt() const;
  /// N, the particle temperatures.
  Index rows() const;
  /// rows(): 𝒯 is square.
  Index cols() const { return rows(); }
  /// y = 𝒯 x. Throws NumericalError when a stage meets a non-finite value.
  void perform_op(const double* x, double* y) const;
  /// 𝒯 as a dense matrix (one perform_op per column; for small problems).
  Eigen::MatrixXd dense() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// ρ(𝒯) by the method of spectral_radius(const LinearizedStep&): dense eigenvalues up to
/// `dense_limit` rows, else power iteration and Arnoldi (Spectra).
SpectralRadius spectral_radius(const TransportStep& T, Index dense_limit = 1500);

/// The critical Fourier number F* of critical_fourier, with the cost of its search. The names are
/// the columns of `smpm transport-stability` (critical_fourier, rho_T, evaluations).
struct CriticalFourier {
  /// F*: the upper end of the stable interval [stable_from, F*], the largest F found with
  /// ρ(𝒯(F)) ≤ 1 + tol (within `resolution`) above the smallest stable F
  double critical_fourier = 0;
  double stable_from = 0; ///< its lower end (CriticalCourant::stable_from): 0 when stable to 0
  SmallCourant small = SmallCourant::Stable; ///< what lies below (CriticalCourant::small)
  double floor = 0;                          ///< the lowest F examined, the limit F → 0 aside
  /// ρ(𝒯) as F → 0 (CriticalCourant::rho_limit)
  double rho_limit = std::numeric_limits<double>::quiet_NaN();
  /// γ: ρ(𝒯(F)) ≈ ρ(𝒯(0)) + γ F as F → 0 (CriticalCourant::growth_rate)
  double growth_rate = std::numeric_limits<double>::quiet_NaN();
  double rho_T = 0;      ///< ρ(𝒯) at F*
  int evaluations = 0;   ///< spectral radii computed
  int not_converged = 0; ///< of them, Arnoldi runs that did not converge
  int non_finite = 0;    ///< of them, non-finite results (counted as unstable)
};

/// The critical Fourier number F* = max{F : ρ(𝒯(F)) ≤ 1 + tol} with Δt = F Δx_min² / D_max
/// (diffusion_time), by the search of critical_courant: the small F first (0.05 / 4^j down to
/// kCourantFloor and the limit F → 0), then doubling from F = 0.05 up to f_max and bisection to
/// `resolution`; `hint` > 0 starts the bracket search there. Throws InputError unless the
/// options have heat transport, and Interrupted when `interrupt` is set.
CriticalFourier critical_fourier(const Model& model, const StepOptions& options, double tol = 1e-6,
                                 double f_max = 4.0, double resolution = 1e-3, double hint = 0,
                                 const std::atomic<int>* interrupt = nullptr);

} // namespace smpm
