// SPDX-License-Identifier: BSD-3-Clause
// The single-pass kernels of the step (stages.hpp) equal the Eigen expressions they implement
// (round-off: 1e-12 relative), on CPDI operators of random 1D, 2D and 3D clouds; a block of rows
// (one material) gives the same products as the whole; the F update reproduces exp(L Δt) and
// (I + L Δt) for known velocity gradients.

#include "support.hpp"

#include <cmath>
#include <numbers>

using namespace smpm;

namespace {
double max_abs(const Eigen::MatrixXd& a) {
  return a.cwiseAbs().maxCoeff();
}
} // namespace

TEST_CASE("kernels equal their Eigen expressions", "[stages]") {
  for (int dim = 1; dim <= 3; ++dim) {
    CAPTURE(dim);
    const Grid g = smpm::test::test_grid(dim, 10);
    Particles P = smpm::test::random_cloud(g, 80, 3u + dim, 3.0, true);
    P.V = Field::Random(P.size(), dim);
    P.stress = Field::Random(P.size(), dim * dim);
    const Operators ops = assemble(g, P, Shape::CPDI);
    const ParticleOperators op = particle_operators(ops);
    const Index n = g.num_nodes(), N = P.size();
    const Eigen::MatrixXd S(ops.S);
    // p = Sᵀ (M ∘ V)
    Field p;
    map_momentum(op, P.V, p);
    const Eigen::MatrixXd MV = ops.M.asDiagonal() * P.V;
    CHECK(max_abs(p - S.transpose() * MV) < 1e-13 * max_abs(MV));
    // f(i, a) = −Σ_b (G_bᵀ (Ω J σ)_{·(a,b)})_i
    Field f;
    internal_force(op, P.volume0, P.F, P.stress, f);
    const Eigen::VectorXd OJ = P.volume0.cwiseProduct(P.jacobian());
    Eigen::MatrixXd f_ref = Eigen::MatrixXd::Zero(n, dim);
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b)
        f_ref.col(a) -= ops.G[size_t(b)].transpose() * OJ.cwiseProduct(P.stress.col(a * dim + b));
    CHECK(max_abs(f - f_ref) < 1e-12 * max_abs(f_ref));
    // L(p, a d + b) = (G_b v)_{pa}
    const Field v = Field::Random(n, dim), acc = Field::Random(n, dim);
    Field L(N, dim * dim);
    velocity_gradient(op, v, L);
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b) {
        const Eigen::VectorXd expected = ops.G[size_t(b)] * v.col(a);
        CHECK((L.col(a * dim + b) - expected).cwiseAbs().maxCoeff() < 1e-12);
      }
    // PIC: V' = S v, X += (α V' + (1 − α) V) Δt;  FLIP: V += S a Δt, X += S v Δt − (1−α) S a Δt²
    const double dt = 0.1, alpha = 0.3;
    Field X = P.X, V = P.V;
    update_particles_pic(op, v, dt, alpha, X, V);
    const Eigen::MatrixXd Sv = S * v, Sa = S * acc;
    CHECK(max_abs(V - Sv) < 1e-13);
    CHECK(max_abs(X - (P.X + (alpha * Sv + (1 - alpha) * P.V) * dt)) < 1e-13);
    X = P.X;
    V = P.V;
    update_particles_flip(op, v, acc, dt, alpha, X, V);
    CHECK(max_abs(V - (P.V + dt * Sa)) < 1e-13);
    CHECK(max_abs(X - (P.X + dt * Sv - (1 - alpha) * dt * dt * Sa)) < 1e-13);
    // y = m⁻¹ m̃ x = S⁺ S x for 1, 2, 3 and 7 columns
    ConsistentMass mt;
    assemble_consistent_mass(ops, mt);
    for (int c : {1, 2, 3, 7}) {
      const Field x = Field::Random(n, c);
      Field y;
      reverse_map_product(ops.m_inv, mt.matrix, x, y);
      const Eigen::MatrixXd ref = ops.m_inv.asDiagonal() * (mt.matrix * x);
      CHECK(max_abs(y - ref) < 1e-12 * max_abs(ref));
    }
  }
}

TEST_CASE("a block of particle rows gives the products of those particles", "[stages]") {
  // Split the cloud into rows [0, 30) and [30, N): momenta and forces add up to the whole
  // (p = p¹ + p², FMPM 2026 Eq. 15), and the particle updates of a block touch only its rows.
  const Grid g = smpm::test::test_grid(2, 8);
  Particles P = smpm::test::random_cloud(g, 70, 11u, 2.0, true);
  P.V = Field::Random(P.size(), 2);
  P.stress = Field::Random(P.size(), 4);
  const Operators ops = assemble(g, P, Shape::CPDI);
  const ParticleOperators all = particle_operators(ops);
  const Index k = 30, rest = P.size() - k;
  const ParticleOperators a = all.block(0, k), b = all.block(k, rest);
  Field p, pa, pb, f, fa, fb;
  map_momentum(all, P.V, p);
  map_momentum(a, P.V.topRows(k), pa);
  map_momentum(b, P.V.bottomRows(rest), pb);
  CHECK(max_abs(pa + pb - p) < 1e-13 * max_abs(p));
  internal_force(all, P.volume0, P.F, P.stress, f);
  internal_force(b, P.volume0.tail(rest), P.F.bottomRows(rest), P.stress.bottomRows(rest), fb);
  internal_force(a, P.volume0.head(k), P.F.topRows(k), P.stress.topRows(k), fa);
  CHECK(max_abs(fa + fb - f) < 1e-12 * max_abs(f));
  const Field v = Field::Random(g.num_nodes(), 2);
  Field X = P.X, V = P.V;
  update_particles_pic(b, v, 0.1, 1.0, X.bottomRows(rest), V.bottomRows(rest));
  CHECK(max_abs(V.topRows(k) - P.V.topRows(k)) == 0.0); // block a untouched
  const Eigen::MatrixXd Sv = Eigen::MatrixXd(ops.S) * v;
  CHECK(max_abs(V.bottomRows(rest) - Sv.bottomRows(rest)) < 1e-13);
}

TEST_CASE("the F update: exp(L dt) F and (I + L dt) F for known velocity gradients", "[stages]") {
  // A grid velocity v_i = L₀ x_i has L_p = L₀ at every particle (Σ_i v_i ⊗ G_pi = L₀ Σ_i x_i ⊗
  // G_pi = L₀, the gradient identity of the shape tests), so F follows the closed forms:
  //   stretch L₀ = diag(a, b): exp(L₀Δt) = diag(e^{aΔt}, e^{bΔt});
  //   spin L₀ = [[0, −w], [w, 0]]: exp(L₀Δt) = rotation by wΔt;
  //   shear L₀ = [[0, γ], [0, 0]] (nilpotent): exp(L₀Δt) = I + L₀Δt.
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {8, 8, 1});
  const Particles P0 = make_block(g, {2, 2, 0}, {6, 6, 0}, {2, 2, 1}, 1.0, 0);
  const Operators ops = assemble(g, P0, Shape::GIMP);
  const double dt = 0.3;
  using M2 = Eigen::Matrix2d;
  auto run = [&](const M2& L0, DeformationUpdate kind) {
    Field v(g.num_nodes(), 2);
    for (Index i = 0; i < g.num_nodes(); ++i)
      v.row(i) =
          (L0 * Eigen::Vector2d(g.node_coordinate(i, 0), g.node_coordinate(i, 1))).transpose();
    Field F = P0.F;
    update_deformation(particle_operators(ops), v, dt, kind, F);
    return F;
  };
  auto check_all = [&](const Field& F, const M2& expected) {
    for (Index q = 0; q < F.rows(); ++q) {
      const M2 Fq = Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(F.row(q).data());
      CHECK(max_abs(Fq - expected) < 1e-12);
    }
  };
  const double a = 0.7, b = -0.4, w = 1.1, gamma = 0.5;
  check_all(run(M2{{a, 0}, {0, b}}, DeformationUpdate::Exponential),
            M2{{std::exp(a * dt), 0}, {0, std::exp(b * dt)}});
  check_all(run(M2{{0, -w}, {w, 0}}, DeformationUpdate::Exponential),
            M2{{std::cos(w * dt), -std::sin(w * dt)}, {std::sin(w * dt), std::cos(w * dt)}});
  check_all(run(M2{{0, gamma}, {0, 0}}, DeformationUpdate::Exponential),
            M2{{1, gamma * dt}, {0, 1}});
  check_all(run(M2{{a, 0}, {0, b}}, DeformationUpdate::Linear),
            M2{{1 + a * dt, 0}, {0, 1 + b * dt}});
  // A rigid spin keeps det F = 1 with the exponential update, not with the linear one.
  const Field spin_lin = run(M2{{0, -w}, {w, 0}}, DeformationUpdate::Linear);
  CHECK(spin_lin(0, 0) * spin_lin(0, 3) - spin_lin(0, 1) * spin_lin(0, 2) ==
        smpm::test::approx(1 + w * w * dt * dt, 1e-12));
}

TEST_CASE("library misuse is a UsageError naming the check, not an input error", "[stages]") {
  const Grid g2(2, {0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  const Particles P1 =
      make_block(Grid(1, {0, 0, 0}, {1, 1, 1}, {4, 1, 1}), {1, 0, 0}, {3, 0, 0}, {2, 1, 1}, 1.0, 0);
  CHECK_THROWS_AS(assemble(g2, P1, Shape::Linear), UsageError); // 1D particles, 2D grid
  const Particles P2 = make_block(g2, {1, 1, 0}, {3, 3, 0}, {2, 2, 1}, 1.0, 0);
  const Operators ops = assemble(g2, P2, Shape::Linear);
  Field p;
  const Field wrong = Field::Zero(P2.size() + 1, 2);
  CHECK_THROWS_WITH(map_momentum(particle_operators(ops), wrong, p),
                    Catch::Contains("map_momentum: V must be N x d") &&
                        Catch::Contains("failed at"));
}
