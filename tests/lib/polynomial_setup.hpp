// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the tests of FMPM's polynomial family share (test_polynomial.cpp, test_polynomial_loop.cpp):
// a jittered CPDI lattice with its dense m⁻¹m̃ on the active nodes, and the members' residual
// polynomials worked out independently of the library (closed forms, a monomial least-squares fit).

#include "support.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace smpm::test::polynomial {

struct Setup {
  Grid grid = Grid(2, {0, 0, 0}, {1, 1, 1}, {8, 8, 1});
  Particles P;
  Operators ops;
  ConsistentMass mt;
  Field p;
  Eigen::VectorXi act;   // the active nodes
  Eigen::MatrixXd B;     // m⁻¹m̃ on the active nodes
  Eigen::MatrixXd b;     // m⁻¹ p on the active nodes
  Eigen::VectorXd m;     // the lumped masses of the active nodes
  double lambda_min = 0; // λ_min(m⁻¹m̃)
};

inline Setup setup(Shape shape = Shape::CPDI) {
  Setup s;
  s.P = smpm::test::jittered_lattice(s.grid, 2, 4, 2, 0.3, 7u);
  for (Index q = 0; q < s.P.size(); ++q)
    s.P.V.row(q) << std::sin(1.7 * s.P.X(q, 0) + 0.3 * q), std::cos(0.9 * s.P.X(q, 1) - 0.2 * q);
  assemble(s.grid, s.P, shape, s.ops);
  assemble_consistent_mass(s.ops, s.mt);
  map_momentum(particle_operators(s.ops), s.P.V, s.p);
  s.act = active_nodes(s.ops);
  const Index na = s.act.size();
  const Eigen::MatrixXd mt = Eigen::MatrixXd(s.mt.matrix);
  s.B.resize(na, na);
  s.b.resize(na, 2);
  s.m.resize(na);
  for (Index i = 0; i < na; ++i) {
    s.m[i] = s.ops.m[s.act[i]];
    s.b.row(i) = s.p.row(s.act[i]) / s.m[i];
    for (Index j = 0; j < na; ++j)
      s.B(i, j) = mt(s.act[i], s.act[j]) / s.m[i];
  }
  // B is similar to the symmetric m^{-1/2} m̃ m^{-1/2}.
  const Eigen::VectorXd r = s.m.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd C = r.asDiagonal() * mt(s.act, s.act) * r.asDiagonal();
  s.lambda_min = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(C).eigenvalues().minCoeff();
  return s;
}

// v⁺(k) of the loop on the active nodes.
inline Eigen::MatrixXd loop(const Setup& s, const FmpmOptions& opt, const Operators* ops = nullptr,
                            const SparseRowMatrix* mt = nullptr) {
  const Operators& o = ops ? *ops : s.ops;
  Field v;
  lumped_solve(o.m_inv, s.p, v);
  FmpmWorkspace w;
  fmpm_velocity(o, mt ? *mt : s.mt.matrix, opt, {}, v, w);
  return v(s.act, Eigen::all);
}

// A polynomial in λ by its monomial coefficients (c[i] multiplies λ^i).
using Poly = std::vector<double>;
inline Poly times(const Poly& a, const Poly& b) {
  Poly c(a.size() + b.size() - 1, 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j)
      c[i + j] += a[i] * b[j];
  return c;
}
inline Poly plus(const Poly& a, const Poly& b, double sb) {
  Poly c(std::max(a.size(), b.size()), 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    c[i] += a[i];
  for (size_t i = 0; i < b.size(); ++i)
    c[i] += sb * b[i];
  return c;
}
inline double value(const Poly& a, double x) {
  double y = 0;
  for (size_t i = a.size(); i-- > 0;)
    y = y * x + a[i];
  return y;
}

// The Chebyshev member's R_k(λ) = (1 − λ) T_{k−1}((θ − λ)/δ) / T_{k−1}(θ/δ), by T's own
// recurrence T_{j+1}(t) = 2t T_j(t) − T_{j−1}(t) on monomial coefficients.
inline Poly chebyshev_residual(int k, double lo) {
  const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
  const Poly t{theta / delta, -1 / delta};
  Poly prev{1.0}, cur = t;
  if (k - 1 == 0)
    cur = prev;
  for (int j = 1; j < k - 1; ++j) {
    const Poly next = plus(times(Poly{2 * t[0], 2 * t[1]}, cur), prev, -1.0);
    prev = cur;
    cur = next;
  }
  const double norm = value(cur, 0.0);
  for (double& c : cur)
    c /= norm;
  return times(Poly{1.0, -1.0}, cur);
}

// The least-squares member's R_k = (1 − λ) L(λ), L(0) = 1 of degree k − 1, minimising
// ∫ R² w on [λ_lo, 1] (w the Chebyshev weight), by a weighted linear least-squares fit of L's
// monomial coefficients on 200 Gauss–Chebyshev points (exact for these degrees).
inline Poly least_squares_residual(int k, double lo) {
  const int n = 200, unknowns = k - 1;
  if (unknowns == 0)
    return {1.0, -1.0};
  const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
  Eigen::MatrixXd M(n, unknowns);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    const double x = theta + delta * std::cos((2.0 * i + 1) * std::numbers::pi / (2.0 * n));
    const double f = 1 - x; // √w is the constant π/n on Gauss–Chebyshev points
    for (int j = 0; j < unknowns; ++j)
      M(i, j) = f * std::pow(x, j + 1);
    rhs[i] = -f;
  }
  const Eigen::VectorXd c = M.colPivHouseholderQr().solve(rhs);
  Poly L{1.0};
  for (int j = 0; j < unknowns; ++j)
    L.push_back(c[j]);
  return times(Poly{1.0, -1.0}, L);
}

// v = q(B) b with q(λ) = (1 − R(λ))/λ, by Horner on the dense B.
inline Eigen::MatrixXd apply_q(const Poly& R, const Eigen::MatrixXd& B, const Eigen::MatrixXd& b) {
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(b.rows(), b.cols());
  for (size_t i = R.size(); i-- > 1;)
    v = B * v + (-R[i]) * b; // q_{i−1} = −R_i
  return v;
}

inline double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

} // namespace smpm::test::polynomial
