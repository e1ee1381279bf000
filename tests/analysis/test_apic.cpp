// SPDX-License-Identifier: BSD-3-Clause
// The APIC transfer (StepOptions::transfer = Apic; Jiang, Schroeder, Selle, Teran & Stomakhin
// 2015, "The affine particle-in-cell method", ACM TOG 34(4):51): its weights Ĝ = D_p⁻¹ S Δ and
// mass operator m̃_A against a construction written here from the paper's definitions, the
// properties that make it a mass (symmetric, rows summing to m, exact on affine fields,
// m̃ ≤ m̃_A ≤ m), affine fields across P2G and G2P, and its exact update as the limit of FMPM(k).

#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/stability.hpp>

#include <Eigen/Dense>

#include <cmath>

using namespace smpm;

namespace {
using smpm::test::max_abs;

// m̃_A of the library (assemble_apic_mass), dense.
Eigen::MatrixXd apic_mass(const Operators& ops, const Particles& P, Shape shape) {
  ConsistentMass mt;
  assemble_apic_mass(ops, P.X, shape, mt);
  return Eigen::MatrixXd(mt.matrix);
}

// m̃_A written here from Jiang et al. 2015's transfer, dense: the P2G m_i v_i = Σ_p S_pi M_p
// (V_p + C_p Δ_pi) of the G2P V_p = Σ_j S_pj v_j, C_p = B_p D_p⁻¹, B_p = Σ_j v_j Δ_pjᵀ S_pj,
// D_p = Σ_j S_pj Δ_pj Δ_pjᵀ, in closed form Σ_p M_p S_pi S_pj (1 + Δ_piᵀ D_p⁻¹ Δ_pj), with D_p
// inverted per particle.
Eigen::MatrixXd reference_mass(const Operators& ops, const Particles& P) {
  const Eigen::MatrixXd S(ops.S);
  const int d = ops.grid.dim();
  const Index n = S.cols();
  Eigen::MatrixXd mA = Eigen::MatrixXd::Zero(n, n);
  for (Index p = 0; p < S.rows(); ++p) {
    std::vector<Index> nodes;
    for (Index i = 0; i < n; ++i)
      if (S(p, i) != 0)
        nodes.push_back(i);
    Eigen::MatrixXd delta(d, Index(nodes.size()));
    for (size_t k = 0; k < nodes.size(); ++k)
      delta.col(Index(k)) = ops.grid.node_position(nodes[k]).head(d) - P.X.row(p).transpose();
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(d, d);
    for (size_t k = 0; k < nodes.size(); ++k)
      D += S(p, nodes[k]) * delta.col(Index(k)) * delta.col(Index(k)).transpose();
    const Eigen::MatrixXd Dinv = D.inverse();
    for (size_t a = 0; a < nodes.size(); ++a)
      for (size_t b = 0; b < nodes.size(); ++b)
        mA(nodes[a], nodes[b]) += P.mass[p] * S(p, nodes[a]) * S(p, nodes[b]) *
                                  (1 + delta.col(Index(a)).dot(Dinv * delta.col(Index(b))));
  }
  return mA;
}

// The least eigenvalue of a symmetric matrix restricted to the active nodes (m_i > 0).
double least_eigenvalue(const Eigen::MatrixXd& A, const Eigen::VectorXd& m) {
  std::vector<Index> active;
  for (Index i = 0; i < m.size(); ++i)
    if (m[i] > 0)
      active.push_back(i);
  Eigen::MatrixXd B(Index(active.size()), Index(active.size()));
  for (size_t a = 0; a < active.size(); ++a)
    for (size_t b = 0; b < active.size(); ++b)
      B(Index(a), Index(b)) = A(active[a], active[b]);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(B, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .minCoeff();
}
} // namespace

TEST_CASE("APIC's mass m~_A is Jiang et al.'s transfer, symmetric, between m~ and m",
          "[transfer]") {
  // On random clouds (60 particles, deformed CPDI domains) in 1D, 2D and 3D for the four shapes
  // whose D_p is positive definite: m̃_A equals the construction from the paper's definitions
  // (reference_mass) to 1e-12 of its largest entry; it is symmetric to 1e-13 (entries (i, j) and
  // (j, i) are products equal in exact arithmetic, summed in another order), its rows sum to m
  // and it maps every affine field to m times it (1e-12 of m |v|); vᵀ m̃_A v lies between vᵀ m̃ v and
  // vᵀ m v (the least eigenvalues of m̃_A − m̃ and m − m̃_A on the active nodes are above
  // −1e-12 of the largest mass; 1D and 2D, the dense eigenproblem of 3D being 1331 nodes). With
  // linear hats the construction with D_p⁻¹ equals the velocity-gradient transfer's m̃_L (the
  // multilinear limit, where the library takes Ĝ = ∇S without D_p).
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI}) {
      CAPTURE(dim, to_string(shape));
      const Grid g = smpm::test::test_grid(dim, 10);
      const Particles P = smpm::test::random_cloud(g, 60, 11u + unsigned(dim), 3.0, true);
      const Operators ops = assemble(g, P, shape);
      const Eigen::MatrixXd mA = apic_mass(ops, P, shape);
      const double scale = max_abs(mA), mmax = ops.m.maxCoeff();
      if (shape == Shape::Linear) { // the construction with D_p⁻¹ (no particle on a node line)
        ConsistentMass mL;
        assemble_transfer_mass(ops, P.X, mL);
        CHECK(max_abs(reference_mass(ops, P) - Eigen::MatrixXd(mL.matrix)) <= 1e-12 * scale);
        continue;
      }
      CHECK(max_abs(mA - reference_mass(ops, P)) <= 1e-12 * scale);
      CHECK(max_abs(mA - mA.transpose()) <= 1e-13 * scale);
      CHECK(max_abs(mA.rowwise().sum() - ops.m) <= 1e-12 * mmax);
      const Eigen::MatrixXd L0 = Eigen::MatrixXd::Random(dim, dim);
      const Eigen::RowVectorXd V0 = Eigen::RowVectorXd::Random(dim);
      Eigen::MatrixXd v(ops.num_nodes(), dim);
      for (Index i = 0; i < v.rows(); ++i)
        v.row(i) = V0 + (L0 * g.node_position(i).head(dim)).transpose();
      CHECK(max_abs(mA * v - ops.m.asDiagonal() * v) <= 1e-12 * mmax * max_abs(v));
      if (dim < 3) {
        const Eigen::MatrixXd mt(consistent_mass(ops));
        CHECK(least_eigenvalue(mA - mt, ops.m) >= -1e-12 * mmax);
        CHECK(least_eigenvalue(Eigen::MatrixXd(ops.m.asDiagonal()) - mA, ops.m) >= -1e-12 * mmax);
      }
    }
}

TEST_CASE("APIC's weights: D_p = h^2/4 for quadratic B-splines, affine fields cross exactly",
          "[transfer]") {
  // Jiang et al. 2015: for quadratic B-splines on a uniform grid D_p = h²/4 I, so
  // Ĝ_pi,b = 4 S_pi Δ_pi,b / h_b² (1e-12 of 4/h_b). Then an affine field V = V₀ + L x with
  // C_p = L crosses P2G (with C_p's term, lumped solve) and APIC's G2P (V' = S v, C' = Σ v ⊗ Ĝ)
  // exactly for every shape (1e-12 of the field; the standard transfer misses it by 1e-3,
  // test_gradient_transfer.cpp).
  for (int dim = 1; dim <= 3; ++dim) {
    const Grid g = smpm::test::test_grid(dim, 10);
    const Particles P = smpm::test::random_cloud(g, 40, 5u + unsigned(dim), 3.0, false);
    for (Shape shape : {Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI}) {
      CAPTURE(dim, to_string(shape));
      const Operators ops = assemble(g, P, shape);
      const ParticleOperators op = particle_operators(ops);
      AffineOffsets offsets;
      affine_offsets(op, g, P.X, offsets);
      ApicWeights w;
      apic_weights(op, offsets, shape, w);
      if (shape == Shape::BSpline2)
        for (int b = 0; b < dim; ++b) {
          const double h = g.cell_size(b);
          double worst = 0;
          for (int k = 0; k < op.outer[op.rows]; ++k)
            worst = std::max(worst,
                             std::abs(w.g[size_t(b)][size_t(k)] -
                                      4 * op.S[k] * offsets.delta[size_t(b)][size_t(k)] / (h * h)));
          CHECK(worst <= 1e-12 * 4 / h);
        }
      const auto [exact, Lrows] = smpm::test::random_affine_field(P);
      Field V = exact, L = Lrows, p, v, X = P.X;
      const AffineMomentum affine{&offsets, &L}; // P2G: Σ S M (V + C Δ)
      map_momentum(op, V, p, &affine);
      lumped_solve(ops.m_inv, p, v);
      update_particles_pic(op, v, 0.0, 1.0, X, V);
      velocity_gradient(with_weights(op, w), v, L); // C_p = Σ v ⊗ Ĝ = B_p D_p⁻¹
      CHECK(max_abs(V - exact) <= 1e-12 * max_abs(exact));
      CHECK(max_abs(L - Lrows) <= 1e-12 * max_abs(Lrows));
    }
  }
  // A collapsed CPDI domain (F of rank 1 in 2D) on a node row has a singular D_p with hats:
  // every corner has y on the row, where the hat's D_yy = (y − y_0)(y_1 − y) is 0.
  Particles P;
  P.resize(2, 1);
  P.X.row(0) << 5.5, 5.0;
  P.half_length.row(0) << 0.25, 0.25;
  P.F.row(0) << 1, 0, 0, 0; // the domain spans x only
  P.mass[0] = 1;
  P.volume0[0] = 1;
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {10, 10, 1});
  const Operators ops = assemble(g, P, Shape::CPDI);
  AffineOffsets offsets;
  affine_offsets(particle_operators(ops), g, P.X, offsets);
  ApicWeights w;
  CHECK_THROWS_WITH(apic_weights(particle_operators(ops), offsets, Shape::CPDI, w),
                    Catch::Contains("particle 0 has a singular APIC inertia tensor"));
}

namespace {
// The largest growth rate |Im ω| of the semi-discrete bar, K v = ω² M v on the free active
// nodes (the node at x = 0 is held), K = Gᵀ diag(Ω E) G; complex ω² appear only when M is not
// symmetric.
double semi_discrete_growth(const Model& bar, const Operators& ops, const Eigen::MatrixXd& mass) {
  const Eigen::MatrixXd G(ops.G[0]);
  const double E = bar.materials[0].youngs;
  const Eigen::MatrixXd K = G.transpose() * (E * bar.particles.volume0).asDiagonal() * G;
  std::vector<Index> free;
  for (Index i = 0; i < ops.num_nodes(); ++i)
    if (ops.m[i] > 0 && std::abs(bar.grid.node_position(i)[0]) > 1e-12)
      free.push_back(i);
  const Index n = Index(free.size());
  Eigen::MatrixXd Kf(n, n), Mf(n, n);
  for (Index a = 0; a < n; ++a)
    for (Index b = 0; b < n; ++b) {
      Kf(a, b) = K(free[size_t(a)], free[size_t(b)]);
      Mf(a, b) = mass(free[size_t(a)], free[size_t(b)]);
    }
  const Eigen::VectorXcd w2 = Eigen::EigenSolver<Eigen::MatrixXd>(Mf.lu().solve(Kf)).eigenvalues();
  double growth = 0;
  for (Index k = 0; k < w2.size(); ++k)
    growth = std::max(growth, std::abs(std::sqrt(w2[k]).imag()));
  return growth;
}
} // namespace

TEST_CASE("APIC has no weak mode on the bar: its mass is symmetric", "[transfer][stability]") {
  // The §3.3 bar (CPDI) shifted by 1/8 cell: the last particle's domain enters the cell beyond
  // x = 40 by 1/8, and node 41 has 1/32 of an interior node's mass. The semi-discrete bar with
  // the velocity-gradient transfer's m̃_L (not symmetric) has one complex pair of ω², ω =
  // 3.621 ± 0.0270i, whose mode lies on that light node: a growth of 0.027 per unit time at
  // any Δt, the weak mode of the exact update (ρ(T) − 1 = 0.027 Δt at small C: measured
  // 1.35e-5 at C = 0.001, Δt = 5e-4) and of FMPM(k ≥ 8) as k grows. With APIC's m̃_A
  // (symmetric, positive definite on the active nodes) every ω² is real: asserted |Im ω| below
  // 1e-6 for m̃_A and m̃ and 0.027 ± 0.001 for m̃_L. The exact update with APIC is then stable
  // from C → 0 to C* = 1.059 at this shift (measured 1.0586; the bar's table, the least over
  // four shifts, has 0.9258 from shift 3/8, FMPM(k ≥ 8) the same) and ρ(T) ≤ 1 + 1e-10 at
  // C = 0.001, where the gradient transfer's exceeds 1 + 1e-6 (measured 1 + 1.35e-5).
  const Model bar = shifted(vibrating_bar({}), {0.125, 0, 0});
  const Operators ops = assemble(bar.grid, bar.particles, Shape::CPDI);
  ConsistentMass mL;
  assemble_transfer_mass(ops, bar.particles.X, mL);
  const Eigen::MatrixXd mA = apic_mass(ops, bar.particles, Shape::CPDI);
  CHECK(semi_discrete_growth(bar, ops, Eigen::MatrixXd(mL.matrix)) ==
        smpm::test::approx(0.027, 0.001));
  CHECK(semi_discrete_growth(bar, ops, mA) < 1e-6);
  CHECK(semi_discrete_growth(bar, ops, Eigen::MatrixXd(consistent_mass(ops))) < 1e-6);

  StepOptions apic{.shape = Shape::CPDI,
                   .velocity = VelocityUpdate::Exact,
                   .exact_solver = exact_solver_factory(),
                   .transfer = Transfer::Apic};
  StepOptions gradient = apic;
  gradient.transfer = Transfer::VelocityGradient;
  const auto rho = [&bar](const StepOptions& o, double C) {
    const LinearizedStep T(bar, o, stable_time_step(bar, C));
    return spectral_radius(T).rho_T;
  };
  CHECK(rho(apic, 0.001) <= 1 + 1e-10);
  CHECK(rho(gradient, 0.001) > 1 + 1e-6);
  const CriticalCourant c = critical_courant(bar, apic);
  CHECK(c.small == SmallCourant::Stable);
  CHECK(c.critical_courant == smpm::test::approx(1.0586, 0.001));
}

TEST_CASE("the exact update with APIC is CHOLMOD's solve of m~_A, FMPM(k -> infinity)",
          "[transfer][exact]") {
  // m̃_A is symmetric, so the exact update factors it by CHOLMOD (exact_solver_factory picks it;
  // cholmod_solver_factory accepts it). With ε = 0.2 the regularised (1 − ε) m̃_A + ε m equals
  // FMPM(400) blended with α = 0.8 (FMPM 2026 §3.3): ρ(0.8 (I − m⁻¹m̃_A)) ≤ 0.8 because the
  // spectrum of m⁻¹m̃_A lies in [0, 1] (m̃_A ≤ m), so 0.8⁴⁰⁰ ≈ 1e-39. One step of the bar
  // (shifted 0.1 cell) and of a 2D block fixed on its left edge: particle velocities and
  // affine velocities agree to 1e-10 of their size.
  Model block(Grid(2, {0, 0, 0}, {1, 1, 1}, {10, 8, 1}));
  block.materials = {smpm::test::material("block", MaterialModel::Linear, 100, 0.3)};
  block.particles = make_block(block.grid, {2, 2, 0}, {7, 6, 0}, {2, 2, 1}, 1.0, 0);
  for (Index q = 0; q < block.particles.size(); ++q) {
    const double x = block.particles.X(q, 0), y = block.particles.X(q, 1);
    block.particles.V.row(q) << 0.3 * std::sin(0.9 * x + 0.4 * y), 0.2 * std::cos(0.6 * x);
  }
  fix_plane(block.grid, 0, 2.0, {true, false, false}, block.bcs);
  for (const Model& model : {shifted(vibrating_bar({}), {0.1, 0, 0}), block})
    for (Shape shape : {Shape::CPDI, Shape::BSpline2}) {
      CAPTURE(model.grid.dim(), to_string(shape));
      const StepOptions base{.shape = shape, .transfer = Transfer::Apic};
      StepOptions exact = base, fmpm = base;
      exact.velocity = VelocityUpdate::Exact;
      exact.exact.regularization = 0.2;
      exact.exact_solver = cholmod_solver_factory();
      fmpm.velocity = VelocityUpdate::FMPM;
      fmpm.fmpm.order = 400;
      fmpm.fmpm.blend_alpha = 0.8;
      Model a = model, b = model;
      Stepper sa(exact), sb(fmpm);
      const double dt = 0.3 / courant_of(model, 1.0);
      sa.step(a, dt);
      sb.step(b, dt);
      CHECK(max_abs(a.particles.V - b.particles.V) <= 1e-10 * max_abs(b.particles.V));
      CHECK(max_abs(a.particles.gradient - b.particles.gradient) <=
            1e-10 * max_abs(b.particles.gradient));
    }
}
