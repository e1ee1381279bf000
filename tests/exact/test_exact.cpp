// SPDX-License-Identifier: BSD-3-Clause
// The exact consistent-mass inverse with CHOLMOD: residual, reuse of the symbolic analysis,
// FMPM(k) → m̃⁻¹ at the rate ρ(A)^k, the k → ∞ limit of the incremental BC method, and the
// error for a singular m̃.

#include "contact_support.hpp"
#include "exact_setup.hpp"

#include <sparsempm/exact.hpp>

#include <Eigen/Dense>

using namespace smpm;

namespace {
using Setup = smpm::test::ExactSetup;
Setup setup() {
  return smpm::test::exact_setup();
}
} // namespace

TEST_CASE("CHOLMOD solves m~ v = p on the active nodes and reuses its analysis", "[exact]") {
  const Setup s = setup();
  CholmodSolver solver;
  Field v;
  solver.solve(s.ops, s.mt.matrix, {}, s.p, v);
  const Field r = Field(s.mt.matrix * Eigen::MatrixXd(v)) - s.p; // residual m̃ v − p
  CHECK(r.norm() < 1e-12 * s.p.norm());
  solver.solve(s.ops, s.mt.matrix, {}, 2.0 * s.p, v); // same pattern: numeric factorisation only
  CHECK(solver.analyses() == 1);
  CHECK(solver.factorizations() == 2);
  CHECK(solver.last_rcond() > 0);
}

TEST_CASE("FMPM(k) approaches m~^-1 p at least as fast as C rho(A)^k", "[exact]") {
  // v_∞ − v_k = A^k v_∞ and A = m^{-1/2} B m^{1/2} with B symmetric, so
  // |v_∞ − v_k| ≤ √(max m / min m) ρ(A)^k |v_∞| (norms over the active nodes).
  const Setup s = setup();
  CholmodSolver solver;
  Field exact;
  solver.solve(s.ops, s.mt.matrix, {}, s.p, exact);
  const Eigen::VectorXi act = active_nodes(s.ops);
  const Eigen::MatrixXd A = Eigen::MatrixXd(expansion_matrix(s.ops))(act, act);
  const double rho = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().cwiseAbs().maxCoeff();
  const Eigen::VectorXd m = s.ops.m(act);
  const double C = std::sqrt(m.maxCoeff() / m.minCoeff());
  INFO("rho(A) = " << rho << ", C = " << C);
  REQUIRE(rho < 1);
  for (int k = 1; k <= 40; ++k) {
    Field v;
    lumped_solve(s.ops.m_inv, s.p, v);
    FmpmWorkspace w;
    fmpm_velocity(s.ops, s.mt.matrix, {.order = k}, {}, v, w);
    const double err = (v - exact).norm() / exact.norm();
    CAPTURE(k, err);
    CHECK(err <= C * std::pow(rho, k) * (1 + 1e-9));
  }
}

TEST_CASE("with axis velocity BCs the exact solve is the limit of the incremental method",
          "[exact]") {
  // FMPM 2026 §3.1: v⁺(k) = Σ (ΦA)^{ℓ−1} v⁺(1) → (I − ΦA)⁻¹ v⁺(1), i.e. m̃_FF v_F =
  // p_F − m̃_FC v_C with v_C prescribed.
  const Setup s = setup();
  BoundaryConditions bcs;
  fix_plane(s.grid, 1, 3.0, {true, true, false}, bcs);
  VelocityCondition pull;
  pull.nodes = nodes_on_plane(s.grid, 0, 5.0);
  pull.direction = Eigen::Vector3d::UnitX();
  pull.value = [](double, const Eigen::Vector3d& x) { return 0.2 + 0.1 * x[1]; };
  bcs.conditions.push_back(pull);
  const LoopConstraints bc{&s.grid, &bcs, 0.0};
  CholmodSolver solver;
  Field exact;
  solver.solve(s.ops, s.mt.matrix, bc, s.p, exact);
  Field v;
  lumped_solve(s.ops.m_inv, s.p, v);
  bcs.constrain_velocity(s.grid, 0.0, v, &s.ops.active);
  FmpmWorkspace w;
  fmpm_velocity(s.ops, s.mt.matrix, {.order = 3000}, bc, v, w);
  CHECK((v - exact).norm() < 1e-9 * exact.norm());
  for (Index i : pull.nodes)
    if (s.ops.active[i])
      CHECK(exact(i, 0) == smpm::test::approx(0.2 + 0.1 * s.grid.node_coordinate(i, 1), 1e-15));
}

TEST_CASE("a condition within round-off of an axis prescribes that axis", "[exact]") {
  // exact.hpp: conditions must be along axes; a direction within 1e-12 of one (a normalised
  // input) is taken as the axis, with its sign: the same solution as the exact axis, bit for bit.
  const Setup s = setup();
  auto solve = [&](const Eigen::Vector3d& direction) {
    BoundaryConditions bcs;
    VelocityCondition pull;
    pull.nodes = nodes_on_plane(s.grid, 0, 5.0);
    pull.direction = direction;
    pull.value = [](double, const Eigen::Vector3d& x) { return 0.2 + 0.1 * x[1]; };
    bcs.conditions.push_back(pull);
    Field v;
    CholmodSolver().solve(s.ops, s.mt.matrix, {&s.grid, &bcs, 0.0}, s.p, v);
    return v;
  };
  const Field axis = solve(-Eigen::Vector3d::UnitX());
  const Field near = solve(Eigen::Vector3d(-1, 1e-7, 0).normalized());
  CHECK(near == axis);
  for (Index i : nodes_on_plane(s.grid, 0, 5.0))
    if (s.ops.active[i])
      CHECK(axis(i, 0) == -(0.2 + 0.1 * s.grid.node_coordinate(i, 1)));
}

namespace {
// Two particles and four active nodes of a 1D grid of 10 cells (linear shape functions):
// rank(m̃) = 2 < 4, a singular consistent mass.
struct SingularBar {
  Grid grid{1, {0, 0, 0}, {1, 1, 1}, {10, 1, 1}};
  Particles particles = [] {
    Particles P;
    P.resize(1, 2);
    P.X.col(0) << 2.5, 4.5;
    P.mass.setOnes();
    P.half_length.setConstant(0.25);
    return P;
  }();
  Operators ops = assemble(grid, particles, Shape::Linear);
  ConsistentMass mt = [this] {
    ConsistentMass m;
    assemble_consistent_mass(ops, m);
    return m;
  }();
};
} // namespace

TEST_CASE("a singular consistent mass is reported with its nodes", "[exact]") {
  // Two particles and four active nodes (linear shape functions): rank(m̃) = 2 < 4.
  const SingularBar bar;
  const Grid& g = bar.grid;
  const Particles& P = bar.particles;
  const Operators& ops = bar.ops;
  ConsistentMass mt = bar.mt;
  Field p = Field::Ones(g.num_nodes(), 1), v;
  CholmodSolver solver;
  CHECK_THROWS_WITH(solver.solve(ops, mt.matrix, {}, p, v),
                    Catch::Contains("not positive definite") && Catch::Contains("at node") &&
                        Catch::Contains("smallest lumped masses: node"));
  // The documented regularisation (1 − ε) m̃ + ε m makes it solvable.
  CholmodSolver regularized({.regularization = 1e-6});
  CHECK_NOTHROW(regularized.solve(ops, mt.matrix, {}, p, v));
  // With a velocity field per particle the columns are α n_g + i: the message names node i of
  // the 11-node grid and its field, not column 11 + i (it said "node 13" for node 2 of field 1).
  Operators two;
  const Eigen::VectorXi field = (Eigen::VectorXi(2) << 0, 1).finished();
  assemble(g, P, Shape::Linear, two, 2, &field);
  assemble_consistent_mass(two, mt);
  Field p2 = Field::Ones(two.num_nodes(), 1);
  try {
    solver.solve(two, mt.matrix, {}, p2, v);
    FAIL("m̃ of one particle per field on two nodes each is singular");
  } catch (const NumericalError& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Matches(".*at node (2|3|4|5) of velocity field (0|1); smallest lumped "
                                    "masses: node [2-5] of velocity field [01] .*"));
  }
}

TEST_CASE("a failed factorisation names the nodal system it was given", "[exact]") {
  // The singular m̃ above, given to the solvers as each system (ExactOptions::system): the
  // messages name that matrix, its lumped quantity and its remedies by construction.
  const SingularBar bar;
  const Operators& ops = bar.ops;
  const ConsistentMass& mt = bar.mt;
  Field p = Field::Ones(bar.grid.num_nodes(), 1), v;
  auto message = [&](MassSolver&& solver) {
    try {
      solver.solve(ops, mt.matrix, {}, p, v);
    } catch (const NumericalError& e) {
      return std::string(e.what());
    }
    FAIL("the singular matrix was factored");
    return std::string();
  };
  const std::string mass = message(CholmodSolver());
  CHECK_THAT(mass, Catch::StartsWith("the consistent mass matrix m~ is not positive definite") &&
                       Catch::Contains("; smallest lumped masses: node ") &&
                       Catch::Contains(" (m = ") && Catch::EndsWith("(1 - eps) m~ + eps m)"));
  const std::string capacity = message(CholmodSolver({.system = NodalSystem::ConsistentCapacity}));
  CHECK_THAT(capacity,
             Catch::StartsWith("the consistent capacity matrix c~ is not positive definite") &&
                 Catch::Contains("; smallest lumped capacities: node ") &&
                 Catch::Contains(" (c = ") && Catch::Contains("their lumped temperature") &&
                 Catch::Contains("(1 - eps) c~ + eps c, positive definite for every eps > 0"));
  CHECK_THAT(capacity, !Catch::Contains("mass matrix") && !Catch::Contains("lumped mass"));
  const std::string gradient = message(UmfpackSolver({.system = NodalSystem::GradientMass}));
  CHECK_THAT(gradient, Catch::StartsWith("the mass matrix m~_L of the velocity-gradient transfer "
                                         "is singular on the active nodes (UMFPACK status ") &&
                           Catch::Contains("; smallest lumped masses: node ") &&
                           Catch::EndsWith("(1 - eps) m~_L + eps m)"));
  CHECK_THROWS_AS(CholmodSolver({.system = NodalSystem::GradientMass}), UsageError);
  CHECK(!is_symmetric(NodalSystem::GradientMass));
  CHECK(is_symmetric(NodalSystem::ConsistentMass));
  CHECK(is_symmetric(NodalSystem::ConsistentCapacity));
}

TEST_CASE("the exact transport solve names a singular capacity matrix as such", "[exact]") {
  // A conducting bar with one particle in every other cell (linear shape functions): c~ of
  // rank 5 on 10 active nodes. The step makes its transport solver for c~
  // (transport_solver_options), so the message names the capacity matrix, the lumped
  // capacities and the capacity's remedies.
  Model m(Grid(1, {-0.1, 0, 0}, {0.1, 1, 1}, {12, 1, 1}));
  Material mat = smpm::test::material("bar", MaterialModel::Linear, 1e-9, 0.0);
  mat.heat_capacity = 1;
  mat.conductivity = 1;
  mat.reference_temperature = 300;
  m.materials = {mat};
  for (int cell = 0; cell < 10; cell += 2)
    m.particles.append(
        make_block(m.grid, {0.1 * cell, 0, 0}, {0.1 * (cell + 1), 0, 0}, {1, 1, 1}, 1.0, 0));
  StepOptions o;
  o.shape = Shape::Linear;
  o.transport.update = TransportUpdate::Exact;
  o.exact_solver = exact_solver_factory();
  // The remedy the message gives first: (1 − ε) c̃ + ε c is positive definite for every ε > 0. Its
  // rows sum to c, so θ uniform on a particle's two nodes solves it: no particle shares a node,
  // so none exchanges heat and each keeps its own temperature (a gradient in T_p, 300 + 100 X)
  // to round-off. (The disk impact's c̃ is singular the same way: docs/studies/heat.md.)
  Model regularized = m;
  regularized.particles.temperature = (300 + 100 * regularized.particles.X.col(0).array()).matrix();
  const Eigen::VectorXd start = regularized.particles.temperature;
  StepOptions ro = o;
  ro.exact.regularization = 1e-8;
  Stepper rs(ro);
  const double heat = smpm::test::heat_content(regularized);
  for (int k = 0; k < 5; ++k)
    rs.step(regularized, 1e-3);
  CHECK(std::abs(smpm::test::heat_content(regularized) - heat) <= 1e-13 * heat);
  CHECK((regularized.particles.temperature - start).cwiseAbs().maxCoeff() <= 1e-12 * 400);
  Stepper stepper(o);
  CHECK_THROWS_WITH(
      stepper.step(m, 1e-3),
      Catch::StartsWith("step 1 (t = 0.001): heat transport: the consistent capacity matrix "
                        "c~ is not positive definite on the active nodes") &&
          Catch::Contains("; smallest lumped capacities: node ") && Catch::Contains(" (c = ") &&
          Catch::Contains("fewer particles reach a group of nodes than it has nodes: set "
                          "step.exact_regularization > 0"));
}

TEST_CASE("the regularised exact solve is the blended inverse and keeps a uniform translation",
          "[exact]") {
  // (1 − ε) m̃ + ε m = m (I − (1 − ε) A): its inverse is the k → ∞ limit of FMPM(k) blended
  // with α = 1 − ε, m = 1 (FMPM 2026 §3.3; 1e-9 at k = 3000). Its rows sum to m, so a uniform
  // velocity V is returned exactly (1e-14) — m̃ + ε m would return V / (1 + ε).
  const Setup s = setup();
  const double eps = 0.2;
  Field regularized;
  CholmodSolver({.regularization = eps}).solve(s.ops, s.mt.matrix, {}, s.p, regularized);
  Field v;
  lumped_solve(s.ops.m_inv, s.p, v);
  FmpmWorkspace w;
  fmpm_velocity(s.ops, s.mt.matrix, {.order = 3000, .blend_alpha = 1 - eps}, {}, v, w);
  CHECK((v - regularized).norm() < 1e-9 * regularized.norm());
  Field uniform(s.ops.num_nodes(), 2), u;
  for (Index i = 0; i < s.ops.num_nodes(); ++i)
    uniform.row(i) = s.ops.m[i] * Eigen::RowVector2d(0.3, -0.2);
  CholmodSolver({.regularization = eps}).solve(s.ops, s.mt.matrix, {}, uniform, u);
  for (Index i = 0; i < s.ops.num_nodes(); ++i)
    if (s.ops.active[i]) {
      CHECK(u(i, 0) == smpm::test::approx(0.3, 1e-14));
      CHECK(u(i, 1) == smpm::test::approx(-0.2, 1e-14));
    }
}

TEST_CASE("light nodes take their lumped velocity with a mass cutoff", "[exact]") {
  // The §3.3 bar shifted by 1/16 cell: the last particle's domain reaches 1/16 cell past the
  // node at x = 40, so the node at x = 41 (index 43 on this grid) is light. With cutoff
  // τ = 0.05 that node (and only it) takes v_i = p_i / m_i, the others solve
  // m̃_FF v_F = p_F − m̃_FC v_C (residual at round-off); τ = 0 is plain m̃⁻¹.
  Model bar = vibrating_bar({});
  bar.particles.X.array() += 1.0 / 16;
  const Operators ops = assemble(bar.grid, bar.particles, Shape::CPDI);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  Field p, v, plain;
  map_momentum(particle_operators(ops), bar.particles.V, p);
  CholmodSolver({.mass_cutoff = 0.05}).solve(ops, mt.matrix, {}, p, v);
  CholmodSolver().solve(ops, mt.matrix, {}, p, plain);
  std::vector<int> light, free;
  for (Index i = 0; i < ops.num_nodes(); ++i)
    if (ops.active[i])
      (ops.m[i] < 0.05 * ops.m.maxCoeff() ? light : free).push_back(int(i));
  CHECK(light == std::vector<int>{43});
  for (int i : light)
    CHECK(v(i, 0) == smpm::test::approx(p(i, 0) / ops.m[i], 1e-15, 1e-14));
  const Eigen::MatrixXd M(mt.matrix);
  double residual = 0, scale = 0;
  for (int i : free) {
    double r = -p(i, 0);
    for (Index j = 0; j < ops.num_nodes(); ++j)
      r += M(i, j) * v(j, 0);
    residual = std::max(residual, std::abs(r));
    scale = std::max(scale, std::abs(p(i, 0)));
  }
  CHECK(residual < 1e-12 * scale);
  CHECK((v - plain).norm() > 1e-6 * plain.norm()); // a departure from m̃⁻¹, as documented
}

TEST_CASE("the exact consistent-mass update runs the free-vibrating bar", "[exact][validation]") {
  // FMPM 2026 §3.3 bar with v⁺ = m̃⁻¹ p⁺ ("FMPM(∞)"), α = 1, C = 0.1: measured +0.0006%
  // after five periods (asserted within 0.01%). At C = 0.2 it becomes unstable, below the
  // FMPM(k) plateau of the paper (C ≈ 0.24 for k = 40, 80).
  const double change = smpm::test::bar_energy_change({.shape = Shape::CPDI,
                                                       .velocity = VelocityUpdate::Exact,
                                                       .position_alpha = 1.0,
                                                       .exact_solver = cholmod_solver_factory()},
                                                      0.1);
  INFO("energy change " << change);
  CHECK(std::abs(change) < 1e-4);
}

TEST_CASE("the exact update in multimaterial mode: each field's m~, contact at the Net limit",
          "[exact][contact]") {
  // Two materials cut along a random line (GIMP, jittered). The solver factors the blended
  // mass 0.9 m̃ + 0.1 m (exact_regularization = 0.1): with m̃ itself this block's exact update
  // is unstable at Δt = 0.01 in single material mode too (det F < 0 after 6 steps).
  using smpm::test::cut_block;
  using smpm::test::max_difference;
  using smpm::test::pair_law;
  const StepOptions opt{.shape = Shape::GIMP,
                        .velocity = VelocityUpdate::Exact,
                        .exact = {.regularization = 0.1},
                        .exact_solver = cholmod_solver_factory()};
  SECTION("bonded stick reverts to single material mode") {
    // FMPM 2026 §3.2: with Δp = Δp(0) on every node of two fields, v^α = (m̃^α)⁻¹(p^α ± Δp)
    // is the centre-of-mass field m̃⁻¹ p. 20 steps: measured 7e-16 of the velocity scale.
    for (unsigned seed : {4u, 5u}) {
      const ContactPair law = pair_law(ContactLaw::Stick, ContactDetection::Always);
      Model multi = cut_block(seed, &law), single = cut_block(seed, nullptr);
      Stepper a(opt), b(opt);
      for (int s = 0; s < 20; ++s) {
        a.step(multi, 0.01);
        b.step(single, 0.01);
      }
      CAPTURE(seed);
      CHECK(max_difference(multi.particles.V, single.particles.V) < 1e-12);
      CHECK(max_difference(multi.particles.X, single.particles.X) < 1e-12);
    }
  }
  SECTION("frictionless and Coulomb contact are the k -> infinity limit of FMPM(k) Net") {
    // One step from the same state. FMPM(k) Net with the same blending (α = 0.9 on every pass,
    // whose k → ∞ limit is the blended mass's inverse) approaches the exact update's contact
    // fixed point: measured 0.117, 1.2e-2, 5.7e-6, 1.1e-15 (frictionless) and 0.116, 7.7e-3,
    // 4.2e-6, 1.5e-15 (Coulomb, μ = 0.3) of the velocity scale for k = 5, 20, 80, 320. Momentum
    // is conserved to round-off.
    for (ContactLaw kind : {ContactLaw::Frictionless, ContactLaw::Coulomb}) {
      CAPTURE(int(kind));
      const ContactPair law = pair_law(kind, ContactDetection::Approaching, 0.3);
      const Model start = cut_block(6, &law);
      Model exact = start;
      Stepper(opt).step(exact, 0.01);
      const Eigen::RowVectorXd p0 = start.particles.mass.transpose() * start.particles.V;
      const Eigen::RowVectorXd p1 = exact.particles.mass.transpose() * exact.particles.V;
      CHECK((p1 - p0).norm() < 1e-13);
      const double scale = start.particles.V.cwiseAbs().maxCoeff();
      std::vector<double> error;
      for (int k : {5, 20, 80, 320}) {
        Model loop = start;
        StepOptions o{.shape = Shape::GIMP, .velocity = VelocityUpdate::FMPM};
        o.fmpm.order = k;
        o.fmpm.blend_alpha = 0.9;
        Stepper(o).step(loop, 0.01);
        error.push_back(max_difference(loop.particles.V, exact.particles.V) / scale);
      }
      CAPTURE(error[0], error[1], error[2], error[3]);
      CHECK(error[1] < 0.2 * error[0]);
      CHECK(error[2] < 1e-3 * error[1]);
      CHECK(error[3] < 1e-12);
    }
  }
}

TEST_CASE("the exact transport update: c~ θ = τ+ with held temperatures, second order in the bar",
          "[exact][transport]") {
  // The bar of tests/lib/test_transport.cpp (L = D = 1, T0 = 300, ends held at 400 and 350,
  // t = 0.05, F = 0.1, linear shape functions, 2 particles per cell) with T_p = S c~⁻¹ τ⁺ and
  // the ends as prescribed values of the solve (the limit k → ∞ of the incremental method): the
  // particle temperatures converge to the series solution at second order (measured 0.228,
  // 0.0558, 0.0136 K at 10, 20, 40 cells, as FMPM(16)), and FMPM(40) agrees with the exact
  // update to 1e-9 K.
  auto series = [](double x, double t) {
    double T = 400 - 50 * x;
    for (int n = 1; n <= 2000; ++n) {
      const double sign = n % 2 ? -1.0 : 1.0;
      const double B = 2 / (n * M_PI) * (-100 * (1 - sign) - 50 * sign);
      T += B * std::sin(n * M_PI * x) * std::exp(-n * n * M_PI * M_PI * t);
    }
    return T;
  };
  auto run = [&](int cells, TransportUpdate update, int order) {
    const double h = 1.0 / cells, t = 0.05;
    Model m(Grid(1, {-h, 0, 0}, {h, 1, 1}, {cells + 2, 1, 1}));
    Material mat = smpm::test::material("bar", MaterialModel::Linear, 1e-9, 0.0);
    mat.heat_capacity = 1;
    mat.conductivity = 1;
    mat.reference_temperature = 300;
    m.materials = {mat};
    m.particles = make_block(m.grid, {0, 0, 0}, {1, 0, 0}, {2, 1, 1}, 1.0, 0);
    m.particles.temperature.setConstant(m.particles.size(), 300);
    for (const auto& [at, value] : {std::pair{0.0, 400.0}, std::pair{1.0, 350.0}}) {
      VelocityCondition c;
      c.nodes = nodes_on_plane(m.grid, 0, at);
      c.value = [v = value](double, const Eigen::Vector3d&) { return v; };
      c.label = "temperature";
      m.temperature_bcs.conditions.push_back(c);
    }
    StepOptions o;
    o.shape = Shape::Linear;
    o.transport.update = update;
    o.transport.order = order;
    o.exact_solver = cholmod_solver_factory();
    Stepper stepper(o);
    while (m.time < t - 1e-12)
      stepper.step(m, std::min(0.1 * h * h, t - m.time));
    double e = 0;
    for (Index p = 0; p < m.particles.size(); ++p)
      e = std::max(e, std::abs(m.particles.temperature[p] - series(m.particles.X(p, 0), t)));
    return std::pair{e, m.particles.temperature};
  };
  std::vector<double> errors;
  for (int cells : {10, 20, 40})
    errors.push_back(run(cells, TransportUpdate::Exact, 1).first);
  CAPTURE(errors[0], errors[1], errors[2]);
  CHECK(std::log2(errors[1] / errors[2]) >= 1.9);
  CHECK(errors[2] < 0.02);
  const Eigen::VectorXd exact = run(20, TransportUpdate::Exact, 1).second;
  const Eigen::VectorXd series40 = run(20, TransportUpdate::FMPM, 40).second;
  CHECK((exact - series40).cwiseAbs().maxCoeff() <= 1e-9);
}
