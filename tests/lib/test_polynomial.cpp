// SPDX-License-Identifier: BSD-3-Clause
// The polynomial family of the FMPM loop (fmpm.hpp, Polynomial; docs/studies/polynomials.md):
// the members against their polynomials evaluated on the dense m⁻¹m̃, the squared member's form
// and sign, Chebyshev's error bound and the velocity BCs (test_polynomial_loop.cpp: m̃_L, the
// hooks and the options).

#include "polynomial_setup.hpp"

using namespace smpm;
using namespace smpm::test::polynomial;

TEST_CASE("each member of the family is its polynomial in m^-1 m~ applied to m^-1 p",
          "[fmpm][polynomial]") {
  const Setup s = setup();
  for (int k : {1, 2, 3, 5, 8}) {
    CAPTURE(k);
    FmpmOptions cheb{.order = k};
    cheb.polynomial = Polynomial::Chebyshev;
    cheb.interval_low = s.lambda_min;
    // The loop against R_k's closed form on the dense B (round-off: 1e-12 relative).
    CHECK(rel(loop(s, cheb), apply_q(chebyshev_residual(k, s.lambda_min), s.B, s.b)) < 1e-12);
    FmpmOptions ls = cheb;
    ls.polynomial = Polynomial::LeastSquares;
    for (double lo : {0.0, s.lambda_min}) {
      CAPTURE(lo);
      ls.interval_low = lo;
      // Against an independent monomial least-squares fit; its conditioning at k = 8 limits
      // the agreement to about 1e-12.
      CHECK(rel(loop(s, ls), apply_q(least_squares_residual(k, lo), s.B, s.b)) < 1e-11);
      // The scalar recurrence (residual_polynomial) and the assembled inverse give the same
      // (the monomial reference loses 2e-12 at λ = 1, k = 8, λ_lo = 0).
      for (double x : {0.0, 0.03, 0.3, 0.77, 1.0})
        CHECK(residual_polynomial(ls, x) ==
              Approx(value(least_squares_residual(k, lo), x)).margin(1e-11));
      const Eigen::MatrixXd sparse = Eigen::MatrixXd(fmpm_inverse(s.ops, ls) * s.p);
      CHECK(rel(sparse(s.act, Eigen::all), loop(s, ls)) < 1e-12);
    }
    for (double x : {0.0, 0.1, 0.5, 1.0})
      CHECK(residual_polynomial(cheb, x) ==
            Approx(value(chebyshev_residual(k, s.lambda_min), x)).margin(1e-13));
    // The series' residual polynomial is (1 − λ)^k (FMPM 2026 Eq. 5).
    CHECK(residual_polynomial({.order = k}, 0.4) == Approx(std::pow(0.6, k)).epsilon(1e-14));
  }
}

TEST_CASE("the squared Chebyshev member is (1 - lambda)^(1 or 2) C_m^2 and never amplifies a mode",
          "[fmpm][polynomial]") {
  const Setup s = setup();
  const double lo = s.lambda_min;
  FmpmOptions sq{};
  sq.polynomial = Polynomial::ChebyshevSquared;
  sq.interval_low = lo;
  FmpmOptions cheb = sq;
  cheb.polynomial = Polynomial::Chebyshev;
  for (int k = 1; k <= 12; ++k) {
    CAPTURE(k);
    sq.order = cheb.order = k;
    // R = (1 − λ) C_m² for k − 1 = 2m, (1 − λ)² C_m² for k − 1 = 2m + 1: B v⁺ = b − R(B) b with
    // C_m(B) = T_m((θ − B)/δ)/T_m(θ/δ) by T's recurrence on the dense B (well conditioned where
    // monomial coefficients are not; round-off 1e-12 relative to b).
    const int m = (k - 1) / 2;
    const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
    auto C = [&](const Eigen::MatrixXd& x) {
      if (m == 0)
        return Eigen::MatrixXd(x);
      Eigen::MatrixXd prev = x, cur = (theta * x - s.B * x) / delta;
      double tp = 1, tc = theta / delta;
      for (int j = 1; j < m; ++j) {
        Eigen::MatrixXd next = 2 * (theta * cur - s.B * cur) / delta - prev;
        prev = cur;
        cur = next;
        const double tn = 2 * (theta / delta) * tc - tp;
        tp = tc;
        tc = tn;
      }
      return Eigen::MatrixXd(cur / tc);
    };
    Eigen::MatrixXd Rb = C(C(s.b));
    Rb -= s.B * Rb; // (1 − B)
    if ((k - 1) % 2 == 1)
      Rb -= s.B * Rb;
    CHECK(rel(s.B * loop(s, sq), s.b - Rb) < 1e-12);
    // The particle update carries a mode λ by 1 − R_k(λ): within [0, 1] on [0, 1] for the series
    // and the squared member; Chebyshev exceeds 1 (by max |R_k| on the interval) for k ≥ 3.
    double sq_low = 1, sq_high = 0, cheb_high = 0;
    for (int i = 0; i <= 1000; ++i) {
      const double x = i / 1000.0;
      const double r = residual_polynomial(sq, x);
      sq_low = std::min(sq_low, r);
      sq_high = std::max(sq_high, r);
      cheb_high = std::max(cheb_high, 1 - residual_polynomial(cheb, x));
    }
    CHECK(sq_low >= -1e-15);
    CHECK(sq_high <= 1 + 1e-15);
    if (k >= 3)
      CHECK(cheb_high > 1 + 1e-12);
  }
  // Its error bound: max R on [λ_lo, 1] ≤ (1 − λ_lo)(2ρ^m)², the rate of Chebyshev's 2ρ^{k−1}.
  const double rho = (1 - std::sqrt(lo)) / (1 + std::sqrt(lo));
  for (int k : {9, 17, 25}) {
    sq.order = k;
    const int m = (k - 1) / 2;
    double worst = 0;
    for (int i = 0; i <= 1000; ++i)
      worst = std::max(worst, residual_polynomial(sq, lo + (1 - lo) * i / 1000.0));
    CHECK(worst <= (1 - lo) * 4 * std::pow(rho, 2 * m) * (1 + 1e-9));
  }
}

TEST_CASE("Chebyshev's error on an SPD m~ is within its bound; the series' is not",
          "[fmpm][polynomial]") {
  const Setup s = setup();
  const double lo = s.lambda_min, kappa = 1 / lo;
  const double rho = (std::sqrt(kappa) - 1) / (std::sqrt(kappa) + 1);
  // In the m inner product B is self-adjoint, so ‖R(B) b‖_m ≤ max_{λ ∈ [λ_lo, 1]} |R(λ)| ‖b‖_m,
  // and Chebyshev's R_k = (1 − λ) T_{k−1}(…)/T_{k−1}(θ/δ) is at most (1 − λ_lo)·2ρ^{k−1},
  // ρ = (√κ − 1)/(√κ + 1), κ = 1/λ_lo (Saad 2003, Thm. 6.6 and §12.3): one degree of the
  // textbook 2ρ^k goes to the factor (1 − λ) every member keeps (its first residual A v⁺(1)).
  auto mnorm = [&](const Eigen::MatrixXd& x) {
    return std::sqrt((s.m.asDiagonal() * x.cwiseProduct(x)).sum());
  };
  FmpmOptions cheb{};
  cheb.polynomial = Polynomial::Chebyshev;
  cheb.interval_low = lo;
  for (int k = 2; k <= 24; k += 2) {
    CAPTURE(k);
    cheb.order = k;
    const double residual = mnorm(s.b - s.B * loop(s, cheb)) / mnorm(s.b);
    CHECK(residual <= (1 - lo) * 2 * std::pow(rho, k - 1) * (1 + 1e-9));
  }
  // At k = 24 the series leaves about (1 − λ_min)^24 of the slowest mode, far above Chebyshev's
  // bound (here λ_min ≈ 0.02: 0.6 against 1e-2).
  const double series = mnorm(s.b - s.B * loop(s, {.order = 24})) / mnorm(s.b);
  CHECK(series > 10 * (1 - lo) * 2 * std::pow(rho, 23));
}

TEST_CASE("the members keep every velocity BC and converge to the constrained inverse",
          "[fmpm][polynomial]") {
  const Setup s = setup();
  BoundaryConditions bcs;
  VelocityCondition c;
  c.nodes = nodes_on_plane(s.grid, 0, 4.0); // a line of nodes inside the block, moving
  c.direction = Eigen::Vector3d(1, 1, 0).normalized();
  c.value = [](double, const Eigen::Vector3d& x) { return 0.1 + 0.05 * x[1]; };
  bcs.conditions.push_back(c);
  const LoopConstraints bc{&s.grid, &bcs, 0.0};
  auto run = [&](FmpmOptions opt) {
    Field v;
    lumped_solve(s.ops.m_inv, s.p, v);
    bcs.constrain_velocity(s.grid, 0, v, &s.ops.active); // Table 2, top block
    FmpmWorkspace w;
    fmpm_velocity(s.ops, s.mt.matrix, opt, bc, v, w);
    return v;
  };
  // The reference: the incremental series to (1 − λ_min)^k < 1e-14.
  const int k_series = int(std::ceil(std::log(1e-14) / std::log(1 - s.lambda_min)));
  const Field exact = run({.order = k_series});
  for (Polynomial p :
       {Polynomial::Chebyshev, Polynomial::LeastSquares, Polynomial::ChebyshevSquared}) {
    CAPTURE(to_string(p));
    FmpmOptions opt{.order = 80};
    opt.polynomial = p;
    opt.interval_low = s.lambda_min;
    const Field v = run(opt);
    double worst = 0; // every BC held exactly on every pass (Table 2, bottom block)
    for (Index i : c.nodes)
      if (s.ops.active[i])
        worst = std::max(
            worst, std::abs(v.row(i).dot(c.direction.head(2)) -
                            c.value_at(0, Eigen::Vector3d(4, s.grid.node_coordinate(i, 1), 0))));
    CHECK(worst < 1e-14);
    // 80 passes of Chebyshev leave 2ρ^79 ≈ 1e-10 here; least squares about as little.
    CHECK((v - exact).norm() / exact.norm() < 1e-8);
  }
}
