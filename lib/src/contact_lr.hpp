// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The Gauss–Newton fit of the logistic-regression contact plane (contact 2020 Eqs. 19–21,
// Appendix Eqs. 53–57) over any point accessor, so that the step fits a node's particle cloud
// in place (internal to sparsempm; the public form is logistic_regression_normal).

#include "sparsempm/contact.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace smpm::detail {

/// point(k) is the k-th position (a 3-vector, d entries used), cls(k) its class −1, +1 or 0
/// (0: not in the fit).
template <class Point, class Class>
LogisticFit logistic_fit(int d, Index count, Point&& point, Class&& cls, double cell) {
  using Vec4 = Eigen::Matrix<double, 4, 1>;
  using Mat4 = Eigen::Matrix<double, 4, 4>;
  const int u = d + 1; // φ_1 … φ_d and the offset
  Vec4 phi = Vec4::Zero(), lambda = Vec4::Zero();
  for (int j = 0; j < d; ++j)
    lambda[j] = 1e-7 * cell * cell; // the paper's penalty: normal components only
  LogisticFit fit;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (int it = 1; it <= 15; ++it) {
    Mat4 A = Mat4::Zero();
    Vec4 rhs = Vec4::Zero();
    for (Index k = 0; k < count; ++k) {
      const double c = cls(k);
      if (c == 0)
        continue;
      const Eigen::Vector3d x3 = point(k);
      Vec4 x = Vec4::Zero(); // (X_p, 1) of Eq. (19), zeros beyond the d + 1 unknowns
      for (int a = 0; a < d; ++a)
        x[a] = x3[a];
      x[d] = 1;
      const double s = x.dot(phi);
      // f = 2/(1 + e^{−s}) − 1 = tanh(s/2) and ψ = ∂f/∂s = 2e^{−s}/(1 + e^{−s})² (Eq. 53).
      const double f = std::tanh(0.5 * s), ch = std::cosh(0.5 * s), psi = 0.5 / (ch * ch);
      A.noalias() += (psi * psi) * x * x.transpose(); // Eqs. (54)–(55), w_p = 1
      rhs += (psi * (c - f)) * x;                     // Eq. (56)
    }
    for (int j = 0; j < u; ++j) {
      A(j, j) += lambda[j];
      rhs[j] -= lambda[j] * phi[j];
    }
    for (int j = u; j < 4; ++j) // unused unknowns: identity rows
      A(j, j) = 1;
    const Vec4 step = A.ldlt().solve(rhs); // Eq. (21)
    if (!step.allFinite())
      break; // a degenerate cloud (e.g. one class only): keep the last normal
    phi += step;
    double norm = 0;
    for (int a = 0; a < d; ++a)
      norm += phi[a] * phi[a];
    norm = std::sqrt(norm);
    if (!(norm > 0))
      break;
    fit.normal.setZero();
    for (int a = 0; a < d; ++a)
      fit.normal[a] = phi[a] / norm;
    fit.iterations = it;
    if (it > 1 && 1 - fit.normal.dot(previous) < 1e-5) { // Eq. (57)
      fit.converged = true;
      break;
    }
    previous = fit.normal;
  }
  return fit;
}

} // namespace smpm::detail
