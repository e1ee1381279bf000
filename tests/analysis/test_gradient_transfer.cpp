// SPDX-License-Identifier: BSD-3-Clause
// The velocity-gradient transfer (StepOptions::transfer; Wallstedt & Guilkey 2007, FMPM 2026
// §3.3's Ref. [30]): affine velocity fields cross P2G and G2P exactly, linear momentum is kept to
// round-off and the angular momentum of a spinning block far better than by the standard PIC
// transfer, the linearised step with the gradients in its state is the derivative of the
// Stepper's step, the exact update (UMFPACK on m̃_L) is FMPM(k → ∞), and multimaterial contact
// keeps single material mode and momentum.

#include "contact_support.hpp"
#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/stability.hpp>

#include <cmath>

using namespace smpm;

namespace {
using smpm::test::max_abs;

// One P2G (p by the transfer; v = m⁻¹ p) and a PIC G2P (V' = S v, L' = G v) of the particles'
// V and L on their operators; X is not moved (Δt = 0).
void round_trip(const Grid& g, const Particles& P, Shape shape, bool gradient, Field& V, Field& L) {
  const Operators ops = assemble(g, P, shape);
  const ParticleOperators op = particle_operators(ops);
  Field p, v;
  AffineOffsets offsets;
  affine_offsets(op, g, P.X, offsets);
  const AffineMomentum affine{&offsets, &L};
  map_momentum(op, V, p, gradient ? &affine : nullptr);
  lumped_solve(ops.m_inv, p, v);
  Field X = P.X;
  update_particles_pic(op, v, 0.0, 1.0, X, V);
  velocity_gradient(op, v, L);
}
} // namespace

TEST_CASE("an affine velocity field crosses P2G and G2P exactly with the gradient term",
          "[transfer]") {
  // V(x) = V₀ + L x with L_p = L: p_i = Σ_p S_ip M_p (V₀ + L x_i) = m_i (V₀ + L x_i), so v is
  // the field on the nodes, S v = V₀ + L X_p (every family reproduces linear fields inside the
  // grid: Σ_i S_ip = 1, Σ_i S_ip x_i = X_p) and G v = L. Asserted to 1e-12 of the field's size
  // on random clouds of 1D, 2D and 3D for every shape family; the standard transfer misses it
  // by more than 1e-3 (it maps V₀ + L X_p, not V₀ + L x_i, to node i).
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI}) {
      CAPTURE(dim, to_string(shape));
      const Grid g = smpm::test::test_grid(dim, 10);
      const Particles P = smpm::test::random_cloud(g, 60, 7u + unsigned(dim), 3.0, true);
      const auto [exact, Lrows] = smpm::test::random_affine_field(P);
      const double scale = max_abs(exact);
      Field V = exact, L = Lrows;
      round_trip(g, P, shape, true, V, L);
      CHECK(max_abs(V - exact) <= 1e-12 * scale);
      CHECK(max_abs(L - Lrows) <= 1e-12 * max_abs(Lrows));
      V = exact;
      L = Lrows;
      round_trip(g, P, shape, false, V, L);
      CHECK(max_abs(V - exact) > 1e-3 * scale);
    }
}

namespace {
// A free 2D block (8 × 8 cells of 1, 2 ppc, neo-Hookean E = 1000, ν = 0.3, ρ = 1) spinning at
// ω = 0.2 about its centre c = (10, 10) and translating at (0.1, −0.05), with L_p = the spin's
// gradient; `steps` steps at C = 0.2.
struct Spin {
  double angular0, angular, momentum_change;
};
Spin spin(const StepOptions& opt, int steps) {
  Model m(Grid(2, {0, 0, 0}, {1, 1, 1}, {20, 20, 1}));
  m.materials = {smpm::test::material("block", MaterialModel::NeoHookean, 1000, 0.3)};
  m.particles = make_block(m.grid, {6, 6, 0}, {14, 14, 0}, {2, 2, 1}, 1.0, 0);
  Particles& P = m.particles;
  const double w = 0.2;
  P.gradient.setZero(P.size(), 4);
  for (Index q = 0; q < P.size(); ++q) {
    P.V(q, 0) = 0.1 - w * (P.X(q, 1) - 10);
    P.V(q, 1) = -0.05 + w * (P.X(q, 0) - 10);
    P.gradient(q, 1) = -w; // L = [[0, −ω], [ω, 0]]
    P.gradient(q, 2) = w;
  }

  auto angular = [&] { // about the centre of mass, in the centre-of-mass frame
    const double M = P.mass.sum();
    const Eigen::RowVector2d xc = P.mass.transpose() * P.X / M, vc = P.mass.transpose() * P.V / M;
    double h = 0;
    for (Index q = 0; q < P.size(); ++q)
      h += P.mass[q] *
           ((P.X(q, 0) - xc[0]) * (P.V(q, 1) - vc[1]) - (P.X(q, 1) - xc[1]) * (P.V(q, 0) - vc[0]));
    return h;
  };
  auto momentum = [&] { return Eigen::RowVector2d(P.mass.transpose() * P.V); };
  const double h0 = angular();
  const Eigen::RowVector2d p0 = momentum();
  Stepper stepper(opt);
  const double dt = stable_time_step(m, 0.2);
  for (int s = 0; s < steps; ++s)
    stepper.step(m, dt);
  return {h0, angular(), (momentum() - p0).norm() / p0.norm()};
}
} // namespace

TEST_CASE("a spinning block keeps its momenta under the affine transfers", "[transfer][long]") {
  // 200 steps (about 0.2 rad of spin) of the free block of spin(): linear momentum to 1e-8 of
  // its size (measured ≤ 7e-11, and ≤ 3e-9 with the standard transfer: nodes below the mass
  // tolerance keep none), the angular momentum about the centre of mass within 5e-4 (measured
  // 1.2e-4 to 2.1e-4 for PIC, FMPM(4) and XPIC(4), ≤ 2e-5 for FLIP, with the velocity-gradient
  // transfer; 1.4e-4 to 1.6e-4 and ≤ 2e-5 with APIC). The same runs with the
  // standard transfer lose it all with PIC, 7–11% with FMPM(4), 23–32% with XPIC(4) and 2–3%
  // with FLIP (asserted: more than 1%).
  for (Shape shape : {Shape::GIMP, Shape::BSpline2, Shape::CPDI})
    for (VelocityUpdate v :
         {VelocityUpdate::PIC, VelocityUpdate::FLIP, VelocityUpdate::FMPM, VelocityUpdate::XPIC})
      for (Transfer transfer : {Transfer::VelocityGradient, Transfer::Apic}) {
        CAPTURE(to_string(shape), to_string(v), to_string(transfer));
        const StepOptions gradient{
            .shape = shape, .velocity = v, .fmpm = {.order = 4}, .transfer = transfer};
        const Spin s = spin(gradient, 200);
        CHECK(s.momentum_change <= 1e-8);
        CHECK(std::abs(s.angular / s.angular0 - 1) <= 5e-4);
        if (transfer == Transfer::Apic)
          continue;
        StepOptions standard = gradient;
        standard.transfer = Transfer::Standard;
        const Spin t = spin(standard, 200);
        CHECK(t.momentum_change <= 1e-8);
        CHECK(t.angular / t.angular0 - 1 < -0.01);
      }
}

TEST_CASE("the exact update with gradients is the k -> infinity limit of FMPM(k) on m~_L",
          "[transfer][exact]") {
  // v = m̃_L⁻¹ p⁺ with the velocity BCs eliminated (UMFPACK's LU, exact_solver_factory) is the
  // limit of the incremental FMPM(k) loop on m̃_L. With CPDI, ρ(I − m⁻¹m̃_L) ≤ 0.8 on the bar
  // (fixed at x = 0, shifted 0.1 cell) and 0.56 on a 2D plane-strain block aligned with the
  // grid (fixed on its left edge, a smooth velocity field), so FMPM(400) is that limit to
  // round-off (once the block moves off the grid lines, light corner nodes bring ρ to 0.9986
  // and FMPM(400) is off by 14% after 5 steps). One step of each: particle velocities and
  // gradients agree to 1e-10 of their size (measured ≤ 5.4e-14), and with
  // ε = 0.2 the regularised (1 − ε) m̃_L + ε m equals FMPM(400) blended with α = 0.8 (FMPM 2026
  // §3.3).
  Model block(Grid(2, {0, 0, 0}, {1, 1, 1}, {10, 8, 1}));
  block.materials = {smpm::test::material("block", MaterialModel::Linear, 100, 0.3)};
  block.particles = make_block(block.grid, {2, 2, 0}, {7, 6, 0}, {2, 2, 1}, 1.0, 0);
  for (Index q = 0; q < block.particles.size(); ++q) {
    const double x = block.particles.X(q, 0), y = block.particles.X(q, 1);
    block.particles.V.row(q) << 0.3 * std::sin(0.9 * x + 0.4 * y), 0.2 * std::cos(0.6 * x);
  }
  fix_plane(block.grid, 0, 2.0, {true, false, false}, block.bcs);
  for (const Model& model : {shifted(vibrating_bar({}), {0.1, 0, 0}), block})
    for (const double eps : {0.0, 0.2}) {
      CAPTURE(model.grid.dim(), eps);
      const StepOptions base{.shape = Shape::CPDI, .transfer = Transfer::VelocityGradient};
      StepOptions exact = base, fmpm = base;
      exact.velocity = VelocityUpdate::Exact;
      exact.exact.regularization = eps;
      exact.exact_solver = exact_solver_factory();
      fmpm.velocity = VelocityUpdate::FMPM;
      fmpm.fmpm.order = 400;
      fmpm.fmpm.blend_alpha = 1 - eps;
      Model a = model, b = model;
      Stepper sa(exact), sb(fmpm);
      const double dt = 0.3 / courant_of(model, 1.0);
      sa.step(a, dt);
      sb.step(b, dt);
      CHECK(max_abs(a.particles.V - b.particles.V) <= 1e-10 * max_abs(b.particles.V));
      CHECK(max_abs(a.particles.gradient - b.particles.gradient) <=
            1e-10 * max_abs(b.particles.gradient));
    }
  // A CHOLMOD solver is for symmetric matrices: made for m̃_L it says so in one line.
  StepOptions cholmod{.velocity = VelocityUpdate::Exact, .transfer = Transfer::VelocityGradient};
  cholmod.exact_solver = cholmod_solver_factory();
  CHECK_THROWS_WITH(Stepper(cholmod), Catch::Contains("factors symmetric matrices"));
}

TEST_CASE("UMFPACK's solve of a symmetric m~ equals CHOLMOD's", "[exact]") {
  // The general solver on the consistent mass of the bar (fixed at x = 0; the BCs eliminated
  // by the same rules) and with the mass cutoff: the same v to 1e-12 of its size.
  const Model m = shifted(vibrating_bar({}), {0.1, 0, 0});
  const Operators ops = assemble(m.grid, m.particles, Shape::CPDI);
  const SparseRowMatrix mt(consistent_mass(ops));
  Field p(ops.num_nodes(), 1);
  for (Index i = 0; i < p.rows(); ++i)
    p(i, 0) = ops.m[i] * std::sin(0.3 * double(i));
  for (const double cutoff : {0.0, 0.05}) {
    CAPTURE(cutoff);
    CholmodSolver c({.mass_cutoff = cutoff});
    UmfpackSolver u({.mass_cutoff = cutoff, .system = NodalSystem::GradientMass});
    const LoopConstraints bc{&m.grid, &m.bcs, 0.0};
    Field vc, vu;
    c.solve(ops, mt, bc, p, vc);
    u.solve(ops, mt, bc, p, vu);
    CHECK(max_abs(vc - vu) <= 1e-12 * max_abs(vc));
    CHECK(u.factorizations() == 1);
  }
}

TEST_CASE("the linearised step with gradients is the derivative of the Stepper's step",
          "[transfer]") {
  // The §3.3 bar shifted by 0.1 cell (as in test_stability.cpp) and a 2D plane-strain block
  // fixed on its left edge, at rest and unstressed. With the velocity-gradient transfer the
  // state is x = (V, σ, L): the Stepper takes one step from V = ±ε V̂, σ = ±ε σ̂ (F to match),
  // L = ±ε L̂, and its result is ±ε T x̂ + O(ε²) (L enters P2G multiplied by x_i − X_p, which
  // moves by O(ε)); the central difference cancels the O(ε²) term. Asserted:
  // |(step(+ε) − step(−ε))/2ε − T x̂| ≤ 1e-6 |T x̂| with ε = 1e-5 (measured ≤ 2.7e-11 in 1D,
  // ≤ 6.7e-10 in 2D; a one-sided difference met 1e-6 in 1D only).
  Model block(Grid(2, {0, 0, 0}, {1, 1, 1}, {10, 8, 1}));
  block.materials = {smpm::test::material("block", MaterialModel::Linear, 100, 0.3)};
  block.particles = make_block(block.grid, {2, 2, 0}, {7, 6, 0}, {2, 2, 1}, 1.0, 0);
  fix_plane(block.grid, 0, 2.0, {true, false, false}, block.bcs);
  for (const Model& model :
       {shifted(vibrating_bar({}), {0.1, 0, 0}), shifted(block, {0.1, 0.1, 0})}) {
    const int d = model.grid.dim(), d2 = d * d;
    const Index N = model.particles.size();
    const Material& mat = model.materials[0];
    const double lam = mat.lame_lambda(), G = mat.shear_modulus(), eps0 = 1e-5;
    const double dt = 0.3 / courant_of(model, 1.0);
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(N * (d + 2 * d2), -1.0, 1.0).array().sin();
    for (Index q = 0; d == 2 && q < N; ++q)
      x[2 * N + 4 * q + 2] = x[2 * N + 4 * q + 1]; // σ_yx = σ_xy
    // The state after one application of the Stepper's step from ε x̂.
    auto stepped = [&](const StepOptions& opt, double eps, int steps) {
      Model m = model;
      Particles& P = m.particles;
      P.V = eps * Eigen::Map<const Field>(x.data(), N, d);
      P.gradient = eps * Eigen::Map<const Field>(x.data() + N * (d + d2), N, d2);
      for (Index q = 0; q < N; ++q) {
        const double* s = x.data() + N * d + d2 * q;
        // F = I + ε E with E the strain of σ̂: 1D σ = E ε; plane strain tr σ = 2(λ + G) tr E
        const double trE = d == 1 ? 0.0 : (s[0] + s[3]) / (2 * (lam + G));
        for (int c = 0; c < d2; ++c) {
          P.stress(q, c) = eps * s[c];
          const bool diag = c % (d + 1) == 0;
          const double E_c =
              d == 1 ? s[c] / mat.youngs : (s[c] - (diag ? lam * trE : 0.0)) / (2 * G);
          P.F(q, c) = (diag ? 1.0 : 0.0) + eps * E_c;
        }
      }
      Stepper stepper(opt);
      for (int k = 0; k < steps; ++k) // periodic FMPM: its whole period
        stepper.step(m, dt);
      Eigen::VectorXd out(x.size());
      out << Eigen::Map<const Eigen::VectorXd>(Field(P.V).data(), N * d),
          Eigen::Map<const Eigen::VectorXd>(Field(P.stress).data(), N * d2),
          Eigen::Map<const Eigen::VectorXd>(Field(P.gradient).data(), N * d2);
      return out;
    };
    auto check = [&](const StepOptions& opt) {
      const LinearizedStep T(model, opt, dt);
      const int steps = T.steps_per_application();
      const Eigen::VectorXd fd =
          (stepped(opt, eps0, steps) - stepped(opt, -eps0, steps)) / (2 * eps0);
      REQUIRE(T.rows() == x.size());
      Eigen::VectorXd Tx(x.size());
      T.perform_op(x.data(), Tx.data());
      CHECK((fd - Tx).norm() <= 1e-6 * Tx.norm());
    };
    for (UpdateScheme s : {UpdateScheme::USL, UpdateScheme::USF, UpdateScheme::USLPlus})
      for (VelocityUpdate v : {VelocityUpdate::FLIP, VelocityUpdate::PIC, VelocityUpdate::FMPM,
                               VelocityUpdate::XPIC}) {
        CAPTURE(d, to_string(s), to_string(v));
        for (Transfer t : {Transfer::VelocityGradient, Transfer::Apic}) {
          CAPTURE(to_string(t));
          check({.shape = Shape::CPDI,
                 .scheme = s,
                 .velocity = v,
                 .fmpm = {.order = 4},
                 .transfer = t});
        }
      }
    CAPTURE(d);
    StepOptions blended{.shape = Shape::CPDI,
                        .velocity = VelocityUpdate::FMPM,
                        .fmpm = {.order = 8, .blend_alpha = 0.8, .blend_every = 2},
                        .transfer = Transfer::VelocityGradient};
    check(blended);
    blended.periodic_cx = 1.0; // periodic: FLIP steps, then FMPM
    check(blended);
  }
}

TEST_CASE("with gradients, bonded stick contact is single material mode and friction keeps the "
          "momentum",
          "[transfer][contact]") {
  // Multimaterial mode: each field's P2G carries its own particles' gradient term and the
  // FMPM(k) and XPIC passes iterate on the fields' blocks of m̃_L, whose sum over the fields is
  // the single-field m̃_L (it is linear in the particles). So bonded stick contact (detection
  // "always", contact 2020 §3.2) reverts to the single-field run as with the standard transfer
  // (test_contact.cpp): two materials cut along a random line, 20 steps; asserted 1e-7 of the
  // velocity scale, the bound of the standard transfer's FMPM(k) test (a node where both
  // fields are below the active tolerance while their sum is above it). XPIC(m) too, with
  // contact on the increments of its loop (the default; contact 2020's closed form with the
  // term of its Eq. 37 differs by a term in V − S v, its §3.3: 0.02 of the velocity scale here
  // with the standard transfer, 0.06 with gradients).
  using smpm::test::cut_block;
  using smpm::test::max_difference;
  using smpm::test::pair_law;
  using smpm::test::step_side_by_side;
  for (VelocityUpdate v :
       {VelocityUpdate::FLIP, VelocityUpdate::PIC, VelocityUpdate::FMPM, VelocityUpdate::XPIC})
    for (ContactFmpmMethod method : {ContactFmpmMethod::Net, ContactFmpmMethod::Evolving}) {
      CAPTURE(to_string(v), int(method));
      ContactPair law = pair_law(ContactLaw::Stick, ContactDetection::Always);
      law.fmpm_method = method;
      // APIC with quadratic B-splines (whose Ĝ is not ∇S; with GIMP domains inside a cell
      // it is, and APIC would repeat the velocity-gradient transfer).
      for (const auto& [shape, transfer] : {std::pair{Shape::GIMP, Transfer::VelocityGradient},
                                            std::pair{Shape::BSpline2, Transfer::Apic}}) {
        CAPTURE(to_string(transfer));
        Model multi = cut_block(4, &law), single = cut_block(4, nullptr);
        const StepOptions opt{
            .shape = shape, .velocity = v, .fmpm = {.order = 4}, .transfer = transfer};
        step_side_by_side(opt, multi, single, 20);
        CHECK(max_difference(multi.particles.V, single.particles.V) < 1e-7);
        CHECK(max_difference(multi.particles.gradient, single.particles.gradient) < 1e-6);
        CHECK(max_difference(multi.particles.X, single.particles.X) < 1e-7);
      }
    }
  // Coulomb friction (μ = 0.4, contact where the fields approach): the contact momenta cancel
  // in pairs (contact 2020 Eq. 7) and the gradient term of P2G moves no momentum (Σ_i D_b = 0:
  // Σ_i S_pi x_i = X_p), so Σ M V is kept to round-off (asserted 1e-12 of Σ M |V|).
  for (VelocityUpdate v : {VelocityUpdate::FLIP, VelocityUpdate::FMPM, VelocityUpdate::XPIC}) {
    CAPTURE(to_string(v));
    const ContactPair law = pair_law(ContactLaw::Coulomb, ContactDetection::Approaching, 0.4);
    Model m = cut_block(6, &law);
    const auto momentum = [&m] {
      return Eigen::Vector2d(m.particles.mass.transpose() * m.particles.V);
    };
    const Eigen::Vector2d before = momentum();
    const double scale = m.particles.mass.dot(m.particles.V.rowwise().norm());
    Stepper stepper({.shape = Shape::GIMP,
                     .velocity = v,
                     .fmpm = {.order = 4},
                     .transfer = Transfer::VelocityGradient});
    for (int s = 0; s < 20; ++s)
      stepper.step(m, 0.01);
    CHECK((momentum() - before).norm() <= 1e-12 * scale);
  }
}
