// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// ρ of a linear operator with rows(), perform_op(x, y) and dense() (internal): the one method of
// spectral_radius for the linearised step (stability.hpp) and the linearised transport step
// (transport_stability.hpp).

#include "sparsempm/errors.hpp"
#include "sparsempm/stability.hpp"

#include <Eigen/Eigenvalues>
#include <Spectra/GenEigsSolver.h>

#include <cmath>
#include <functional>
#include <limits>

namespace smpm::detail {

/// The search of critical_courant for any parameter x (C, or F of critical_fourier): the largest
/// x ≤ x_max with ρ(x)^{1/steps} ≤ 1 + tol, `radius(x, steps)` giving ρ at x (courant.cpp).
CriticalCourant critical_parameter(const std::function<SpectralRadius(double, int&)>& radius,
                                   const char* what, double tol, double x_max, double resolution,
                                   double hint, const std::atomic<int>* interrupt);

inline constexpr double kInf = std::numeric_limits<double>::infinity();

template <class Op>
SpectralRadius dense_radius(const Op& T) {
  Eigen::MatrixXd A;
  try {
    A = T.dense();
  } catch (const NumericalError&) { // a kernel met NaN or an infinite state
    return {kInf, SpectralStatus::NonFinite};
  }
  if (!A.allFinite())
    return {kInf, SpectralStatus::NonFinite};
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  if (es.info() != Eigen::Success)
    return {kInf, SpectralStatus::NotConverged};
  const double rho = es.eigenvalues().cwiseAbs().maxCoeff();
  if (!std::isfinite(rho))
    return {kInf, SpectralStatus::NonFinite};
  return {rho, SpectralStatus::Converged};
}

/// Spectra's operator concept over a const operator T.
template <class Op>
struct SpectraOperator {
  using Scalar = double; ///< the scalar Spectra reads
  const Op& T;
  Index rows() const { return T.rows(); }
  Index cols() const { return T.cols(); }
  void perform_op(const double* in, double* out) const { T.perform_op(in, out); }
};

/// spectral_radius of stability.hpp for any operator Op of this kind.
template <class Op>
SpectralRadius operator_radius(const Op& T, Index dense_limit) {
  if (T.rows() <= dense_limit)
    return dense_radius(T);
  // Large T: the spectrum crowds the unit circle (eigenvalue 1 for every force-free stress,
  // |λ| ≈ 1 for every elastic mode), where Arnoldi converges very slowly. Power iteration first
  // measures the growth per application over the second half of 300 applications; growth within
  // 10⁻³ of 1 is reported as ρ = 1. Otherwise an eigenvalue stands out and Spectra's Arnoldi
  // solver, started from the power iterate, resolves it.
  const Index n = T.rows();
  Eigen::VectorXd x = power_start(n), y(n);
  const int applications = kPowerApplications;
  double log_growth = 0;
  for (int k = 0; k < applications; ++k) {
    try {
      T.perform_op(x.data(), y.data());
    } catch (const NumericalError&) { // a kernel met NaN or an infinite state
      return {kInf, SpectralStatus::NonFinite};
    }
    const double g = y.norm();
    if (!std::isfinite(g))
      return {kInf, SpectralStatus::NonFinite};
    if (!(g > 0))
      return {0.0, SpectralStatus::Converged}; // T x = 0: x was in the null space
    if (k >= applications / 2)
      log_growth += std::log(g);
    x = y / g;
  }
  const double rate = std::exp(log_growth / (applications - applications / 2));
  if (std::abs(rate - 1) <= kUnitGrowthBand)
    return {1.0, SpectralStatus::Converged};
  if (rate < 1)
    return {rate, SpectralStatus::Converged};
  SpectraOperator<Op> op{T};
  Spectra::GenEigsSolver<SpectraOperator<Op>> eigs(op, 1, std::min<Index>(n, 30));
  eigs.init(x.data());
  try {
    eigs.compute(Spectra::SortRule::LargestMagn, 300, 1e-10);
  } catch (const NumericalError&) {
    return {kInf, SpectralStatus::NonFinite};
  }
  if (eigs.info() != Spectra::CompInfo::Successful)
    return {rate, SpectralStatus::NotConverged}; // the measured growth: beyond 1 + 10⁻³
  const double rho = std::abs(eigs.eigenvalues()[0]);
  if (!std::isfinite(rho))
    return {kInf, SpectralStatus::NonFinite};
  return {rho, SpectralStatus::Converged};
}

} // namespace smpm::detail
