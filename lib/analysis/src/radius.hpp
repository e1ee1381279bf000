// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// ρ of a linear operator with rows(), perform_op(x, y) and dense() (internal): the one method of
// spectral_radius for the linearised step (stability.hpp) and the linearised transport step
// (transport_stability.hpp).

#include "dense_of.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/stability.hpp"

#include <Eigen/Eigenvalues>
#include <Spectra/GenEigsSolver.h>

#include <cmath>
#include <functional>
#include <limits>

namespace smpm::detail {

/// The search of critical_courant for any parameter x (C, or F of critical_fourier): the largest
/// x ≤ x_max with ρ(x)^{1/steps} ≤ 1 + tol on the stable interval that holds the smallest stable
/// x, `radius(x, steps)` giving ρ at x, `scan` how far below x = 0.05 it looks (courant.cpp); in
/// CriticalCourant (critical_fourier copies it into its CriticalFourier).
CriticalCourant critical_parameter(const std::function<SpectralRadius(double, int&)>& radius,
                                   const char* what, double tol, double x_max, double resolution,
                                   double hint, const std::atomic<int>* interrupt,
                                   const SmallCourantScan& scan);

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
  // Eigen's real Schur iteration can stall on a T near the identity (small C, its eigenvalues
  // crowding 1): measured on the §3.3 bar with quadratic B-splines, APIC and FMPM(4) blended
  // every 2nd pass, at C = 0.003125 only, even with ten times its sweeps. The complex Schur
  // iteration (other shifts) is tried before the matrix is reported as not converged.
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  double rho = kInf;
  if (es.info() == Eigen::Success) {
    rho = es.eigenvalues().cwiseAbs().maxCoeff();
  } else {
    Eigen::ComplexEigenSolver<Eigen::MatrixXcd> ces(A.cast<std::complex<double>>(), false);
    if (ces.info() != Eigen::Success)
      return {kInf, SpectralStatus::NotConverged};
    rho = ces.eigenvalues().cwiseAbs().maxCoeff();
  }
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

/// spectral_radius of stability.hpp for any operator Op of this kind: spectral_radius_rule on
/// Eigen vectors, with T's dense eigenvalues up to `dense_limit` rows and Spectra's Arnoldi
/// solver (GenEigsSolver) from the power iterate above.
template <class Op>
SpectralRadius operator_radius(const Op& T, Index dense_limit) {
  struct EigenAlgebra {
    const Op& T;
    Eigen::VectorXd x, y;
    Index rows() const { return T.rows(); }
    SpectralRadius small() const { return dense_radius(T); }
    void start() {
      x = power_start(T.rows());
      y.resize(T.rows());
    }
    bool apply() {
      try {
        T.perform_op(x.data(), y.data());
      } catch (const NumericalError&) { // a kernel met NaN or an infinite state
        return false;
      }
      return true;
    }
    double norm() const { return y.norm(); }
    void next(double g) { x = y / g; }
    SpectralRadius resolve(double rate) {
      SpectraOperator<Op> op{T};
      Spectra::GenEigsSolver<SpectraOperator<Op>> eigs(op, 1, std::min<Index>(T.rows(), 30));
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
  };
  EigenAlgebra alg{T, {}, {}};
  return spectral_radius_rule(alg, dense_limit);
}

} // namespace smpm::detail
