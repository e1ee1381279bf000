// SPDX-License-Identifier: BSD-3-Clause
// The polynomial family of the FMPM loop (fmpm.hpp, Polynomial; docs/studies/polynomials.md):
// the Chebyshev and least-squares members against their polynomials evaluated on the dense
// m⁻¹m̃, Chebyshev's error bound, the velocity BCs, the non-symmetric m̃_L and the options.

#include "support.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <complex>

using namespace smpm;

namespace {
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

Setup setup(Shape shape = Shape::CPDI) {
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
Eigen::MatrixXd loop(const Setup& s, const FmpmOptions& opt, const Operators* ops = nullptr,
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
Poly times(const Poly& a, const Poly& b) {
  Poly c(a.size() + b.size() - 1, 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j)
      c[i + j] += a[i] * b[j];
  return c;
}
Poly plus(const Poly& a, const Poly& b, double sb) {
  Poly c(std::max(a.size(), b.size()), 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    c[i] += a[i];
  for (size_t i = 0; i < b.size(); ++i)
    c[i] += sb * b[i];
  return c;
}
double value(const Poly& a, double x) {
  double y = 0;
  for (size_t i = a.size(); i-- > 0;)
    y = y * x + a[i];
  return y;
}

// The Chebyshev member's R_k(λ) = (1 − λ) T_{k−1}((θ − λ)/δ) / T_{k−1}(θ/δ), by T's own
// recurrence T_{j+1}(t) = 2t T_j(t) − T_{j−1}(t) on monomial coefficients.
Poly chebyshev_residual(int k, double lo) {
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
Poly least_squares_residual(int k, double lo) {
  const int n = 200, unknowns = k - 1;
  if (unknowns == 0)
    return {1.0, -1.0};
  const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
  Eigen::MatrixXd M(n, unknowns);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    const double x = theta + delta * std::cos((2.0 * i + 1) * M_PI / (2.0 * n));
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
Eigen::MatrixXd apply_q(const Poly& R, const Eigen::MatrixXd& B, const Eigen::MatrixXd& b) {
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(b.rows(), b.cols());
  for (size_t i = R.size(); i-- > 1;)
    v = B * v + (-R[i]) * b; // q_{i−1} = −R_i
  return v;
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}
} // namespace

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

TEST_CASE("with the non-symmetric m~_L each member is still its polynomial; two grow modes",
          "[fmpm][polynomial]") {
  // Measured on this lattice: with CPDI, m⁻¹m̃_L has a real spectrum in [0.448, 1]; with
  // quadratic B-splines it leaves the real line (complex pairs, |Im| up to 4.5e-4, real parts
  // down to 2.9e-4, below every member's interval [λ_min(m⁻¹m̃), 1]). Each member stays a
  // polynomial in m⁻¹m̃_L (the loop equals q(m⁻¹m̃_L) m⁻¹ p), and the transfer carries a mode z
  // by 1 − R_8(z): within the unit disc for the series and the squared member, beyond it for
  // Chebyshev and least squares, as on the real interval.
  for (Shape shape : {Shape::CPDI, Shape::BSpline2}) {
    CAPTURE(to_string(shape));
    const Setup s = setup(shape);
    ConsistentMass mtl;
    assemble_transfer_mass(s.ops, s.P.X, mtl);
    const Index na = s.act.size();
    const Eigen::MatrixXd dense = Eigen::MatrixXd(mtl.matrix);
    Eigen::MatrixXd BL(na, na);
    for (Index i = 0; i < na; ++i)
      for (Index j = 0; j < na; ++j)
        BL(i, j) = dense(s.act[i], s.act[j]) / s.m[i];
    const Eigen::VectorXcd eig = Eigen::EigenSolver<Eigen::MatrixXd>(BL).eigenvalues();
    double max_imag = 0;
    for (const std::complex<double>& z : eig)
      max_imag = std::max(max_imag, std::abs(z.imag()));
    CHECK((shape == Shape::BSpline2) == (max_imag > 1e-4));
    const int k = 8;
    FmpmOptions cheb{.order = k};
    cheb.polynomial = Polynomial::Chebyshev;
    cheb.interval_low = s.lambda_min;
    FmpmOptions ls = cheb;
    ls.polynomial = Polynomial::LeastSquares;
    const Poly rc = chebyshev_residual(k, s.lambda_min),
               rl = least_squares_residual(k, s.lambda_min);
    CHECK(rel(loop(s, cheb, &s.ops, &mtl.matrix), apply_q(rc, BL, s.b)) < 1e-12);
    CHECK(rel(loop(s, ls, &s.ops, &mtl.matrix), apply_q(rl, BL, s.b)) < 1e-11);
    // The particle update carries a mode z by 1 − R(z): max |1 − R(z)| over the eigenvalues.
    auto growth = [&](const Poly& R) {
      double w = 0;
      for (const std::complex<double>& z : eig) {
        std::complex<double> y = 0;
        for (size_t i = R.size(); i-- > 0;)
          y = y * z + R[i];
        w = std::max(w, std::abs(1.0 - y));
      }
      return w;
    };
    Poly series{1.0};
    for (int j = 0; j < k; ++j)
      series = times(series, Poly{1.0, -1.0});
    FmpmOptions sq = cheb;
    sq.polynomial = Polynomial::ChebyshevSquared;
    Poly rs(1, 0.0); // the squared member's R_8 = (1 − λ)² C_3², by residual_polynomial's values
    {                // at 9 points (degree 8: exact interpolation, Vandermonde on [0, 1])
      Eigen::MatrixXd V(9, 9);
      Eigen::VectorXd y(9);
      for (int i = 0; i < 9; ++i) {
        const double x = i / 8.0;
        for (int j = 0; j < 9; ++j)
          V(i, j) = std::pow(x, j);
        y[i] = residual_polynomial(sq, x);
      }
      const Eigen::VectorXd c = V.fullPivLu().solve(y);
      rs.assign(c.data(), c.data() + 9);
    }
    // Measured max |1 − R_8(z)|: 1 for the series and the squared member (at z = 1, R = 0), so no
    // mode grows; Chebyshev 1.037 (CPDI) and 1.951 (B-splines), least squares 1.020 and 1.219.
    CHECK(growth(series) <= 1 + 1e-12);
    CHECK(growth(rs) <= 1 + 1e-9); // the interpolated R_8: round-off 1e-10
    CHECK(growth(rc) > 1.01);
    CHECK(growth(rl) > 1.01);
  }
}

TEST_CASE("the members call the loop's hooks on every increment (Table 1, lines 1-3)",
          "[fmpm][polynomial]") {
  const Setup s = setup();
  for (Polynomial p :
       {Polynomial::Chebyshev, Polynomial::LeastSquares, Polynomial::ChebyshevSquared}) {
    CAPTURE(to_string(p));
    FmpmOptions opt{.order = 8};
    opt.polynomial = p;
    opt.interval_low = s.lambda_min;
    std::vector<int> bc_calls, contact_calls;
    FmpmHooks hooks;
    hooks.velocity_bcs = [&](int ell, Field&) { bc_calls.push_back(ell); };
    hooks.contact = [&](int ell, Field& dv, const Field& v) {
      contact_calls.push_back(ell);
      CHECK(v.rows() == dv.rows());
    };
    Field v;
    lumped_solve(s.ops.m_inv, s.p, v);
    FmpmWorkspace w;
    CHECK(fmpm_loop(s.ops.m_inv, s.mt.matrix, opt, hooks, v, w).order == 8);
    CHECK(bc_calls == std::vector<int>{2, 3, 4, 5, 6, 7, 8});
    CHECK(contact_calls == bc_calls);
    // Hooks that change nothing leave the member's v⁺(k) (the unfused passes: 1e-14).
    CHECK(rel(v(s.act, Eigen::all), loop(s, opt)) < 1e-14);
    if (p == Polynomial::ChebyshevSquared) { // not nested: no dynamic stopping
      opt.metric = ConvergenceMetric::Means;
      opt.dynamic_limit = 1e-3;
      CHECK_THROWS_WITH(validate(opt), Catch::Contains("dynamic_metric"));
      continue;
    }
    // Chebyshev and least squares are nested families: stopping at ℓ = 6 of order 20 gives the
    // member of order 6 (1e-14).
    hooks = {};
    hooks.converged = [](int ell, const Field&, const Field&, double& metric) {
      metric = 1.0 / ell;
      return ell == 6;
    };
    lumped_solve(s.ops.m_inv, s.p, v);
    opt.order = 20;
    CHECK(fmpm_loop(s.ops.m_inv, s.mt.matrix, opt, hooks, v, w).order == 6);
    opt.order = 6;
    CHECK(rel(v(s.act, Eigen::all), loop(s, opt)) < 1e-14);
  }
}

TEST_CASE("the family's options and names", "[fmpm][polynomial]") {
  FmpmOptions o{.order = 4};
  o.polynomial = Polynomial::Chebyshev;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("interval_low")); // λ_lo = 0
  o.interval_low = 0.1;
  CHECK_NOTHROW(validate(o));
  o.blend_alpha = 0.9;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("blend_alpha"));
  o.blend_alpha = 1;
  o.interval_low = 1;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("interval_low"));
  o.polynomial = Polynomial::Series; // checked even when unused
  CHECK_THROWS_WITH(validate(o), Catch::Contains("interval_low"));
  o.interval_low = 0;
  o.polynomial = Polynomial::LeastSquares;
  CHECK_NOTHROW(validate(o));
  o.order = kMaxLeastSquaresOrder + 1;
  CHECK_THROWS_WITH(validate(o), Catch::Contains("order"));
  StepOptions step;
  set_velocity(step, "least_squares");
  CHECK(step.velocity == VelocityUpdate::FMPM);
  CHECK(velocity_name(step) == "least_squares");
  set_velocity(step, "FMPM");
  CHECK(velocity_name(step) == "FMPM");
  // Heat transport keeps the series on c̃ whatever the velocity update's member.
  set_velocity(step, "chebyshev");
  step.fmpm.interval_low = 0.2;
  step.transport.update = TransportUpdate::FMPM;
  CHECK(transport_fmpm_options(step).polynomial == Polynomial::Series);
  CHECK(transport_fmpm_options(step).interval_low == 0);
  CHECK_THROWS_WITH(set_velocity(step, "cheb"),
                    Catch::Contains("chebyshev | least_squares | chebyshev_squared"));
}
