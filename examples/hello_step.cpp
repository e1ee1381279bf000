// SPDX-License-Identifier: BSD-3-Clause
// hello_step: one MPM time step as matrix expressions, checked against the library's Stepper.
//
// What it shows: a 1D elastic bar (linear shape functions, 2 particles per cell) advanced by
// three USL steps with FLIP (FMPM 2026 Fig. 1, Eq. 8) and three with FMPM(4) (Eqs. 5-6 and 9),
// each step written as the products of the operators S, G, M, m, A, then by Stepper::step.
// How to run: build/examples/hello_step
// What to look at: the two ways agree to round-off ("matches the Stepper: yes"); the FMPM(4)
// grid velocity is the truncated series v⁺(4) = (I + A + A² + A³) m⁻¹ p⁺.

#include <sparsempm/sparsempm.hpp>

#include <iostream>

using namespace smpm;
using Vec = Eigen::VectorXd;

namespace {
// 1. The bar: 0.5 ≤ x ≤ 7.5 on a grid of 8 cells, E = ρ = 1, started with V = 0.1 sin(πX/8)
// and a stretch F = 1 + 0.02 cos(πX/8) (σ = E (F − 1)).
Model bar() {
  Model model(Grid(1, {0, 0, 0}, {1, 1, 1}, {8, 1, 1}));
  model.materials = {Material{.name = "bar", .density = 1, .youngs = 1}};
  model.particles = make_block(model.grid, {0.5, 0, 0}, {7.5, 0, 0}, {2, 1, 1}, 1.0, 0);
  Particles& P = model.particles;
  const Eigen::ArrayXd phase = EIGEN_PI / 8 * P.X.col(0).array();
  P.V.col(0) = 0.1 * phase.sin().matrix();
  P.F.col(0) = (1 + 0.02 * phase.cos()).matrix();
  P.stress.col(0) = (P.F.col(0).array() - 1).matrix();
  return model;
}

// 2. One USL step as matrices (1D: every field is a column). k = 0: FLIP with α = 1 (Eq. 8);
// k > 0: FMPM(k) with α = ½ (Eq. 9).
void matrix_step(Model& model, double dt, int k) {
  Particles& P = model.particles;
  const Operators ops = assemble(model.grid, P, Shape::Linear); // S, G, M, m, m⁻¹
  const SparseRowMatrix& S = ops.S;
  const SparseRowMatrix& G = ops.G[0];
  const auto minv = ops.m_inv.asDiagonal();
  const Vec V = P.V.col(0), J = P.F.col(0), sigma = P.stress.col(0);
  const Vec p = S.transpose() * ops.M.cwiseProduct(V);                            // task 1
  const Vec f = -(G.transpose() * P.volume0.cwiseProduct(J).cwiseProduct(sigma)); // task 2
  const Vec p_plus = p + dt * f;
  Vec v_plus = minv * p_plus; // task 3: v⁺(1) = m⁻¹ p⁺ ...
  if (k > 0) {                // ... and v⁺(k) = Σ_{ℓ<k} Aˡ m⁻¹ p⁺ (Eqs. 5-6)
    const SparseMatrix A = expansion_matrix(ops);
    Vec term = v_plus;
    for (int ell = 1; ell < k; ++ell) {
      term = A * term;
      v_plus += term;
    }
  }
  if (k == 0) { // task 4, FLIP (Eq. 8, α = 1): V ← V + S a Δt, X ← X + S v⁺ Δt
    P.V.col(0) = V + dt * (S * (minv * f));
    P.X.col(0) += dt * (S * v_plus);
  } else { // task 4, Eq. (9) with α = ½: V' = S v⁺, X ← X + (V' + V) Δt / 2
    P.V.col(0) = S * v_plus;
    P.X.col(0) += 0.5 * dt * (P.V.col(0) + V);
  }
  const Vec L = G * v_plus;                                  // task 5 (USL): L = G v⁺
  P.F.col(0) = J.cwiseProduct(Vec::Ones(J.size()) + dt * L); // F ← (1 + L Δt) F
  P.stress.col(0) = model.materials[0].youngs * (P.F.col(0).array() - 1).matrix(); // σ = E(F−1)
}

double difference(const Particles& a, const Particles& b) {
  return std::max({(a.X - b.X).cwiseAbs().maxCoeff(), (a.V - b.V).cwiseAbs().maxCoeff(),
                   (a.F - b.F).cwiseAbs().maxCoeff(), (a.stress - b.stress).cwiseAbs().maxCoeff()});
}
} // namespace

int main() {
  const double dt = 0.25;
  bool ok = true;
  for (const int k : {0, 4}) {
    // 3. The same step by the library: Stepper::step with the options of that expression.
    Model by_matrices = bar(), by_stepper = bar();
    for (int step = 0; step < 3; ++step)
      matrix_step(by_matrices, dt, k);
    StepOptions options{.shape = Shape::Linear};
    if (k > 0) {
      options.velocity = VelocityUpdate::FMPM;
      options.fmpm.order = k;
    }
    Stepper stepper(options);
    for (int step = 0; step < 3; ++step)
      stepper.step(by_stepper, dt);
    const double diff = difference(by_matrices.particles, by_stepper.particles);
    std::cout << (k ? "FMPM(4)" : "FLIP   ") << ": largest difference " << diff << "\n";
    ok = ok && diff < 1e-14;
  }
  std::cout << "matches the Stepper: " << (ok ? "yes" : "no") << "\n";
  return ok ? 0 : 1;
}
