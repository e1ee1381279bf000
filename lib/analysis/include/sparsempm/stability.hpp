#pragma once
/// \file stability.hpp
/// Temporal stability of the MPM update (FMPM 2026 §3.3, Fig. 12): the one-step update
/// linearised at a frozen particle configuration is a linear operator T(C) on the particle
/// state x = (V, σ); the scheme is stable at Courant number C when ρ(T(C)) ≤ 1 + tol.

#include "sparsempm/step.hpp"

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace smpm {

/// One USL step linearised at a frozen configuration (positions, S, G, M, m, m̃, volumes and
/// the material tangent fixed), acting on x = (V, σ) with N d + N d² entries:
///   p = Φ Sᵀ M V,   f = Φ(−Σ_b G_bᵀ Ω J σ_b),   p⁺ = p + Δt f,
///   FLIP:  V' = V + Δt S m⁻¹ f,                     v = m⁻¹ p⁺
///   PIC, FMPM(k) (blending, BC method), exact:  V' = S v,  v = m̃_k⁻¹ p⁺  (Table 1, Eq. 9)
///   XPIC(m):  V' = S (m(u − u*) + Δt m⁻¹ f),  u = m⁻¹ p,  v = m⁻¹ p⁺   (contact 2020 Eq. 35)
///   σ' = σ + Δt 𝕂 : L,  L = Σ_i v_i ⊗ G_pi,
/// where Φ zeroes the constrained directions (the homogeneous part of the velocity BCs) and
/// 𝕂_p = ∂σ/∂L at F_p (from F' = (I + Δt L) F, by central differences; exact for the linear
/// model). Periodic FMPM with C_X (options.periodic_cx > 0) is the product of one FMPM step
/// and the ceil(C_X / C) − 1 FLIP steps between (the Stepper's period); steps_per_application()
/// says how many steps one application spans. The operator concept is Spectra's: rows(), cols(),
/// perform_op(x, y).
class LinearizedStep {
public:
  using Scalar = double;
  /// Throws InputError for options the linearisation does not cover (schemes other than USL,
  /// the improper BC ordering, the velocity BC method).
  LinearizedStep(const Model& model, const StepOptions& options, double dt);
  ~LinearizedStep();
  LinearizedStep(LinearizedStep&&) noexcept;

  /// Changes Δt (and so C) keeping every assembled operator.
  void set_dt(double dt);
  double dt() const;
  /// Time steps spanned by one application of T (1, or round(C_X / C) for periodic FMPM).
  int steps_per_application() const;
  Index rows() const;
  Index cols() const { return rows(); }
  /// y = T x.
  void perform_op(const double* x, double* y) const;
  /// T as a dense matrix (one perform_op per column; for small problems).
  Eigen::MatrixXd dense() const;
  /// The assembled operators of the frozen configuration.
  const Operators& operators() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// ρ(T): dense Eigen eigenvalues when T has at most `dense_limit` rows. Above, matrix-free:
/// 300 power iterations measure the growth per application; growth within 10⁻³ of 1 is
/// reported as ρ = 1 (T has the eigenvalue 1 of force-free stresses, and crowds the unit circle
/// with its elastic modes), otherwise Spectra's GenEigsSolver started from the power iterate
/// returns the dominant |λ| (or the measured growth if it does not converge).
double spectral_radius(const LinearizedStep& T, Index dense_limit = 1500);

/// Courant number C = Δt max(c_wave, max|V_p|) / Δx_min of a time step (FMPM 2026 §3.3).
double courant_of(const Model& model, double dt);

struct CriticalCourant {
  double courant = 0;  ///< largest C found with ρ(T(C)) ≤ 1 + tol (within `resolution`)
  double rho = 0;      ///< ρ(T) at that C
  int evaluations = 0; ///< spectral radii computed
};

/// The critical Courant number C* = max{C : ρ(T(C))^{1/s} ≤ 1 + tol}, s the steps spanned by
/// T (the growth per step), bracketed by doubling from C = 0.05 up to c_max and refined by
/// bisection to ±resolution/2.
CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol = 1e-6,
                                 double c_max = 2.0, double resolution = 1e-3);

/// The model with every particle translated by `shift` (in cells along each axis); boundary
/// conditions stay on their nodes. Throws NumericalError if a particle leaves the grid.
Model shifted(const Model& model, const std::array<double, 3>& shift);

struct ConfigurationSweep {
  CriticalCourant minimum;   ///< the smallest C* found
  std::string configuration; ///< which configuration set it, e.g. "shift (0.25)"
  std::vector<std::pair<std::string, double>> all; ///< every configuration and its C*
};

/// C* over uniform shifts of the particle lattice relative to the grid: j/shifts (j = 0 …
/// shifts − 1) of the particle spacing 2r⁰ (the lattice's period) along every axis at once;
/// reports the minimum and its shift (named in cells along x, e.g. "shift 0.125").
ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol = 1e-6, double resolution = 1e-3);

} // namespace smpm
