// SPDX-License-Identifier: BSD-3-Clause
// FMPM's polynomial family in the loop (fmpm.hpp, Polynomial; docs/studies/polynomials.md): the
// non-symmetric m̃_L, the hooks of Table 1 on every increment, and the options.

#include "polynomial_setup.hpp"

using namespace smpm;
using namespace smpm::test::polynomial;

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
