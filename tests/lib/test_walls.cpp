// SPDX-License-Identifier: BSD-3-Clause
// Moving-wall velocity BCs (FMPM 2026 §3.1, Fig. 2, Table 2): the nodes a wall selects, one BC
// value per step, superposition, and the incremental BC method of the FMPM loop on wall nodes.

#include "support.hpp"

#include <cmath>
#include <memory>

using namespace smpm;
using smpm::test::approx;

namespace {
constexpr double kRate = 3e-3; // ε̇ of the manufactured solution

// The right wall of the §3.1 bar: s_w = 10(1 + ε̇t), v = 10ε̇, ∇v = ε̇/(1 + ε̇t), so that
// v_i = ε̇ x_i/(1 + ε̇t) on the nodes it constrains.
MovingWall right_wall(double depth) {
  MovingWall w;
  w.normal = Eigen::Vector3d::UnitX();
  w.position = [](double t) { return 10 * (1 + kRate * t); };
  w.velocity = [](double) { return 10 * kRate; };
  w.gradient = [](double t) { return kRate / (1 + kRate * t); };
  w.depth = depth;
  w.label = "right wall";
  return w;
}

// A 2D strip 0 ≤ x ≤ 10 (cells of 0.25, 2 × 2 particles per cell) moving with the manufactured
// velocity V = ε̇X, its right end driven by the wall.
Model strip(double depth) {
  Model m(Grid(2, {-1, -1, 0}, {0.25, 0.25, 1}, {60, 12, 1}));
  m.materials = {smpm::test::material("bar", MaterialModel::NeoHookean, 0.75, 0)};
  m.particles = make_block(m.grid, {0, 0, 0}, {10, 1, 0}, {2, 2, 1}, 1.0, 0);
  m.particles.V.col(0) = kRate * m.particles.X.col(0);
  m.bcs.add_wall(right_wall(depth));
  return m;
}
} // namespace

TEST_CASE("a wall selects the massive nodes beyond it and within its depth inside", "[walls]") {
  // Independent check of Fig. 2's rule at several times: node i is constrained iff it has mass
  // and x_i ≥ x_wall(t) − d.
  for (double depth : {0.25, 0.5}) {
    Model m = strip(depth);
    const Field X0 = m.particles.X;
    for (double t : {0.0, 20.0, 55.0}) {
      CAPTURE(depth, t);
      m.particles.X.col(0) = (1 + kRate * t) * X0.col(0); // the manufactured motion
      const Operators ops = assemble(m.grid, m.particles, Shape::CPDI);
      m.bcs.select_wall_nodes(m.grid, ops.active, t);
      std::vector<Index> expected;
      const double xw = 10 * (1 + kRate * t);
      for (Index i = 0; i < m.grid.num_nodes(); ++i)
        if (ops.active[i] && m.grid.node_coordinate(i, 0) >= xw - depth - 1e-12)
          expected.push_back(i);
      CHECK(m.bcs.conditions[0].nodes == expected);
      CHECK(!expected.empty());
      for (Index i : expected) // the wall's value is the manufactured field there
        CHECK(m.bcs.conditions[0].value_at(t, m.grid.node_position(i)) ==
              approx(kRate * m.grid.node_coordinate(i, 0) / (1 + kRate * t), 1e-15, 1e-13));
    }
  }
}

TEST_CASE("one BC value per step: FLIP particles moving with the wall keep their velocity",
          "[walls]") {
  // V = ε̇X is the exact motion (zero acceleration). With the momentum reset after P2G and the
  // reaction force both at the start of the step, the wall nodes get zero acceleration; the
  // interior nodes feel the uniform stress only through Σ G = 0. The particles whose support
  // is inside the wall's depth keep V to round-off; evaluating the reaction at t + Δt instead
  // gives them −ε̇²x/(1 + ε̇t)² (here 1e-4 relative per step).
  Model m = strip(0.5);
  const Field V0 = m.particles.V;
  Stepper stepper({.shape = Shape::Linear, .velocity = VelocityUpdate::FLIP});
  for (int s = 0; s < 20; ++s)
    stepper.step(m, 0.05);
  double worst = 0;
  int checked = 0;
  for (Index q = 0; q < m.particles.size(); ++q)
    if (m.particles.X(q, 0) > m.bcs.walls[0].position(m.time) - 0.5 + 0.25) { // support in d
      worst = std::max(worst, std::abs(m.particles.V(q, 0) - V0(q, 0)) / V0(q, 0));
      ++checked;
    }
  CHECK(checked > 0);
  CHECK(worst < 1e-13);
}

TEST_CASE("conditions at an angle on one node are refused, parallel and perpendicular pass",
          "[walls]") {
  Model m = strip(0.5);
  const Operators ops = assemble(m.grid, m.particles, Shape::CPDI);
  VelocityCondition across; // perpendicular to the wall: allowed
  across.nodes = nodes_on_plane(m.grid, 1, 0.0);
  across.direction = Eigen::Vector3d::UnitY();
  across.label = "floor";
  m.bcs.conditions.push_back(across);
  CHECK_NOTHROW(m.bcs.select_wall_nodes(m.grid, ops.active, 0.0));
  VelocityCondition slanted = across;
  slanted.direction = Eigen::Vector3d(1, 1, 0).normalized();
  slanted.label = "slanted";
  m.bcs.conditions.push_back(slanted);
  CHECK_THROWS_WITH(m.bcs.select_wall_nodes(m.grid, ops.active, 0.0),
                    Catch::Contains("'right wall' and 'slanted'") ||
                        Catch::Contains("'floor' and 'slanted'"));
}

TEST_CASE("the incremental BC method keeps every wall node on its value for every k",
          "[walls][fmpm]") {
  // FMPM 2026 §3.1: lumped BCs on v⁺(1), then the BC directions of every Δv(ℓ) zeroed. After
  // the FMPM solve every wall node has v · n̂ = v_b to round-off for k ≤ 12; the combined method
  // (BCs only on v⁺(1) and v⁺(k)) equals it for k ≤ 2 and departs for k > 2 (§3.1).
  // A velocity field far from the manufactured one, so that every increment reaches the wall.
  Model m = strip(0.5);
  for (Index q = 0; q < m.particles.size(); ++q) {
    m.particles.V(q, 0) += 0.01 * std::sin(3 * m.particles.X(q, 0) + 2 * m.particles.X(q, 1));
    m.particles.V(q, 1) = 0.01 * std::cos(5 * m.particles.X(q, 0));
  }
  const Operators ops = assemble(m.grid, m.particles, Shape::CPDI);
  m.bcs.select_wall_nodes(m.grid, ops.active, 0.0);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  Field p;
  map_momentum(particle_operators(ops), m.particles.V, p);
  m.bcs.constrain_momentum(m.grid, ops.m, 0.0, p);
  const LoopConstraints bc{&m.grid, &m.bcs, 0.0};
  auto solve = [&](int k, BCMethod method) {
    Field v;
    lumped_solve(ops.m_inv, p, v);
    FmpmWorkspace w;
    fmpm_velocity(ops, mt.matrix, {.order = k, .bc_method = method}, bc, v, w);
    return v;
  };
  const auto& nodes = m.bcs.conditions[0].nodes;
  REQUIRE(nodes.size() > 4);
  for (int k = 1; k <= 12; ++k) {
    CAPTURE(k);
    const Field v = solve(k, BCMethod::Incremental);
    double worst = 0;
    for (Index i : nodes)
      worst = std::max(worst, std::abs(v(i, 0) - kRate * m.grid.node_coordinate(i, 0)));
    CHECK(worst < 1e-15);
    const Field c = solve(k, BCMethod::Combined);
    if (k <= 2)
      CHECK((c - v).cwiseAbs().maxCoeff() < 1e-15);
    else
      CHECK((c - v).cwiseAbs().maxCoeff() > 1e-8);
  }
}

TEST_CASE("a step selects the walls' nodes on its own copy of the BCs: the model's stay as given",
          "[walls][step]") {
  // prepare_step (step_preparation.hpp) copies the model's conditions and selects the wall's
  // nodes at the model's time (Fig. 2's rule); the model's wall condition keeps no nodes, so a
  // model stepped once and a fresh copy of it have the same BCs.
  Model m = strip(0.5);
  Stepper stepper(StepOptions{.shape = Shape::CPDI});
  stepper.step(m, 0.01);
  CHECK(m.bcs.conditions[0].nodes.empty());
  const auto& selected = stepper.preparation().bcs.conditions[0].nodes;
  REQUIRE(!selected.empty());
  const double xw = 10.0; // the wall at the start of the step, t = 0
  for (Index whole : selected)
    CHECK(m.grid.node_coordinate(whole, 0) >= xw - 0.5 - 1e-12);

  // A step prepared beforehand (a frame writer reads that preparation) is the same step, bit for
  // bit: prepare() then step() against step() alone, for FLIP and FMPM(4).
  for (const VelocityUpdate v : {VelocityUpdate::FLIP, VelocityUpdate::FMPM}) {
    const StepOptions opt{.shape = Shape::CPDI, .velocity = v, .fmpm = {.order = 4}};
    Model a = strip(0.5), b = strip(0.5);
    Stepper sa(opt), sb(opt);
    for (int s = 0; s < 5; ++s) {
      const StepPreparation& next = sa.prepare(a);
      CHECK(next.bcs.conditions[0].nodes.size() > 0);
      sa.step(a, 0.01);
      sb.step(b, 0.01);
    }
    CHECK(a.particles.X == b.particles.X);
    CHECK(a.particles.V == b.particles.V);
    CHECK(a.particles.stress == b.particles.stress);
  }
}

TEST_CASE("a step's conditions call the model's values: no copy of an expression a step",
          "[walls][step]") {
  // BoundaryConditions::step_conditions (prepare_step's): the walls' nodes as select_wall_nodes
  // selects them, and value functions that call the model's (an expression's copy re-parses it).
  struct Counted {
    std::shared_ptr<int> copies = std::make_shared<int>(0);
    Counted() = default;
    Counted(const Counted& o) : copies(o.copies) { ++*copies; }
    Counted& operator=(const Counted&) = default;
    double operator()(double t, const Eigen::Vector3d&) const { return 2.0 + t; }
  };
  Model m = strip(0.5);
  const Counted value;
  VelocityCondition c;
  c.nodes = nodes_on_plane(m.grid, 0, 0.0);
  c.direction = Eigen::Vector3d::UnitY();
  c.value = value;
  m.bcs.conditions.push_back(c);
  const int copies = *value.copies;
  const Operators ops = assemble(m.grid, m.particles, Shape::CPDI);
  BoundaryConditions step;
  for (int s = 0; s < 3; ++s)
    m.bcs.step_conditions(m.grid, ops.active, 0.5, step);
  CHECK(*value.copies == copies);
  REQUIRE(step.conditions.size() == 2);
  CHECK(step.conditions[1].value_at(0.5, Eigen::Vector3d::Zero()) == 2.5);
  BoundaryConditions selected = m.bcs;
  selected.select_wall_nodes(m.grid, ops.active, 0.5);
  CHECK(step.conditions[0].nodes == selected.conditions[0].nodes);
  CHECK(!step.conditions[0].nodes.empty());
  CHECK(m.bcs.conditions[0].nodes.empty()); // the model's stay as given
}
