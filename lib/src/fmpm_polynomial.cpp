// SPDX-License-Identifier: BSD-3-Clause
// FMPM's polynomial family (fmpm.hpp, Polynomial; docs/studies/polynomials.md): the passes
// a_ℓ, b_ℓ of the Chebyshev, least-squares and squared Chebyshev members from the recurrences of
// their orthogonal polynomials, and R_k(λ) by the loop's own control on scalars.
#include "sparsempm/fmpm.hpp"

#include <Eigen/Core>

#include <cmath>
#include <numbers>
#include <vector>

namespace smpm {

namespace {
// The monic orthogonal polynomials π_{j+1} = (λ − α_j) π_j − γ_j π_{j−1} whose values at 0
// normalise R̂_j = π_j / π_j(0), for j = 0 … n − 1.
struct Recurrence {
  std::vector<double> alpha, gamma; // γ_0 unused
};

// Chebyshev polynomials on [λ_lo, 1] (weight 1/√((λ − λ_lo)(1 − λ))): α_j = θ, γ_1 = δ²/2,
// γ_j = δ²/4 for j ≥ 2 (T_j mapped from [−1, 1] by λ = θ + δ t, made monic).
Recurrence chebyshev_recurrence(int n, double lo) {
  const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
  Recurrence r{std::vector<double>(size_t(n), theta), std::vector<double>(size_t(n), 0.0)};
  for (int j = 1; j < n; ++j)
    r.gamma[size_t(j)] = delta * delta * (j == 1 ? 0.5 : 0.25);
  return r;
}

// The kernel polynomials of the least-squares member: R = (1 − λ) R̂ minimises ∫ R² w dλ with
// R̂(0) = 1 when R̂ ∝ Σ_i p_i(0) p_i(λ), p_i orthonormal for (1 − λ)² w; those are orthogonal for
// λ (1 − λ)² w. Their recurrence by the Stieltjes procedure (Gautschi, "Orthogonal
// polynomials: computation and approximation", 2004, §2.2.3.1) on the Gauss–Chebyshev points of
// [λ_lo, 1], which integrate λ (1 − λ)² π_i π_j w exactly for i + j ≤ 2N − 4; the vectors are
// normalised on each step (no under- or overflow at large k).
Recurrence least_squares_recurrence(int n, double lo) {
  const double theta = (1 + lo) / 2, delta = (1 - lo) / 2;
  const int points = 2 * n + 8;
  Eigen::ArrayXd lambda(points), weight(points);
  for (int i = 0; i < points; ++i) {
    const double t = std::cos((2.0 * i + 1) * std::numbers::pi / (2.0 * points));
    lambda[i] = theta + delta * t;
    weight[i] = lambda[i] * (1 - lambda[i]) * (1 - lambda[i]);
  }
  Recurrence r{std::vector<double>(size_t(n), 0.0), std::vector<double>(size_t(n), 0.0)};
  Eigen::ArrayXd prev = Eigen::ArrayXd::Zero(points), cur = Eigen::ArrayXd::Ones(points);
  cur /= std::sqrt((weight * cur * cur).sum());
  double beta = 0; // ‖π_j‖ / ‖π_{j−1}‖
  for (int j = 0; j < n; ++j) {
    r.alpha[size_t(j)] = (weight * lambda * cur * cur).sum();
    r.gamma[size_t(j)] = beta * beta;
    Eigen::ArrayXd next = (lambda - r.alpha[size_t(j)]) * cur - beta * prev;
    beta = std::sqrt((weight * next * next).sum());
    prev = cur;
    cur = next / beta;
  }
  return r;
}
} // namespace

namespace {
// The passes of R̂_1 … R̂_n from the recurrence of π: Δv(j + 2) = −u_j r(j + 2) + w_j Δv(j + 1),
// u_j = π_j(0)/π_{j+1}(0), w_j = γ_j u_{j−1} u_j, since R̂_{j+1} = R̂_j + u_j λ R̂_j + w_j (R̂_j −
// R̂_{j−1}) from π's recurrence and R̂_{j+1}(0) = 1.
void append_passes(const Recurrence& rec, int n, PolynomialPasses& p) {
  double u_prev = 0; // π_{−1} = 0
  for (int j = 0; j < n; ++j) {
    const double u = 1 / (-rec.alpha[size_t(j)] - rec.gamma[size_t(j)] * u_prev);
    p.a.push_back(-u);
    p.b.push_back(rec.gamma[size_t(j)] * u_prev * u);
    u_prev = u;
  }
}
} // namespace

PolynomialPasses polynomial_passes(const FmpmOptions& opt) {
  validate(opt);
  PolynomialPasses p;
  p.polynomial = opt.polynomial;
  p.order = opt.order;
  p.interval_low = opt.interval_low;
  const int n = opt.order - 1; // passes ℓ = 2 … k: R̂_1 … R̂_{k−1}
  switch (opt.polynomial) {
  case Polynomial::Series:
    break;
  case Polynomial::Chebyshev:
    append_passes(chebyshev_recurrence(n, opt.interval_low), n, p);
    break;
  case Polynomial::LeastSquares:
    append_passes(least_squares_recurrence(n, opt.interval_low), n, p);
    break;
  case Polynomial::ChebyshevSquared: {
    const int m = n / 2;
    if (n % 2 == 1) { // one series pass: Δv = r (a = 1, b = 0)
      p.a.push_back(1);
      p.b.push_back(0);
    }
    const Recurrence rec = chebyshev_recurrence(m, opt.interval_low);
    append_passes(rec, m, p); // C_m ...
    append_passes(rec, m, p); // ... again from the residual it left (b = 0 on its first pass)
    break;
  }
  }
  return p;
}

const PolynomialPasses& polynomial_passes(const FmpmOptions& opt, PolynomialPasses& cache) {
  if (cache.polynomial != opt.polynomial || cache.order != opt.order ||
      cache.interval_low != opt.interval_low)
    cache = polynomial_passes(opt);
  return cache;
}

double residual_polynomial(const FmpmOptions& opt, double lambda) {
  // The loop of fmpm_recursion with m⁻¹m̃ = λ and v⁺(1) = 1: R_k(λ) = 1 − λ v⁺(k).
  struct ScalarLoop {
    const FmpmOptions& opt;
    double lambda, v = 1, dv = 1, r = 1;
    PolynomialPasses cache;
    bool corrects() const { return false; }
    const PolynomialPasses& passes() { return polynomial_passes(opt, cache); }
    void pass(double c, bool) {
      dv = c * (dv - lambda * dv);
      v += dv;
    }
    void polynomial_pass(double a, double b, bool first, bool) {
      r = (first ? dv : r) - lambda * dv;
      dv = a * r + b * dv;
      v += dv;
    }
    void correct(int) {}
    void accumulate() {}
    bool tests_convergence() const { return false; }
    bool converged(int, double&) { return false; }
  };
  validate(opt);
  ScalarLoop loop{opt, lambda, 1, 1, 1, {}};
  std::vector<double> metrics;
  fmpm_recursion(opt, loop, metrics);
  return 1 - lambda * loop.v;
}

} // namespace smpm
