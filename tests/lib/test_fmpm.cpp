// SPDX-License-Identifier: BSD-3-Clause
// FMPM(k) (Nairn 2026 §2.2, Table 1, Eqs. 4–6), blending (§3.3), velocity BC methods (§3.1),
// dynamic FMPM (§3.4) and XPIC(m) (contact 2020 Eqs. 36, 41–43) against explicit matrix forms.

#include "support.hpp"

#include <Eigen/Dense>

using namespace smpm;
using smpm::test::approx;

namespace {
struct Setup {
  Grid grid = Grid(2, {0, 0, 0}, {1, 1, 1}, {8, 8, 1});
  Particles P;
  Operators ops;
  ConsistentMass mt;
  Field p; // n × 2 grid momentum of a random particle velocity field
};

Setup setup(unsigned seed = 3) {
  Setup s;
  s.P = smpm::test::jittered_lattice(s.grid, 2, 4, 2, 0.3, seed);
  for (Index q = 0; q < s.P.size(); ++q) // a fixed, non-trivial velocity field
    s.P.V.row(q) << std::sin(1.3 * s.P.X(q, 0) + 0.2 * q), std::cos(0.7 * s.P.X(q, 1) - 0.1 * q);
  assemble(s.grid, s.P, Shape::CPDI, s.ops);
  assemble_consistent_mass(s.ops, s.mt);
  map_momentum(particle_operators(s.ops), s.P.V, s.p);
  return s;
}

Field lumped(const Setup& s) {
  Field v;
  lumped_solve(s.ops.m_inv, s.p, v);
  return v;
}

Field loop(const Setup& s, FmpmOptions opt, const LoopConstraints& bc = {}) {
  Field v = lumped(s);
  FmpmWorkspace w;
  fmpm_velocity(s.ops, s.mt.matrix, opt, bc, v, w);
  return v;
}

double rel(const Field& a, const Field& b) {
  return (a - b).norm() / b.norm();
}

// Dense A on all nodes (inactive rows and columns zero) and dense m⁻¹.
Eigen::MatrixXd dense_A(const Setup& s) {
  return Eigen::MatrixXd(expansion_matrix(s.ops));
}
} // namespace

TEST_CASE("the FMPM loop equals the explicit polynomial (sum A^j) m^-1 p", "[fmpm]") {
  const Setup s = setup();
  const Eigen::MatrixXd A = dense_A(s);
  const Eigen::MatrixXd minv_p = s.ops.m_inv.asDiagonal() * Eigen::MatrixXd(s.p);
  Eigen::MatrixXd term = minv_p, sum = minv_p;
  for (int k = 1; k <= 10; ++k) {
    CAPTURE(k);
    // FMPM 2026 Eq. (5): v⁺(k) = (Σ_{ℓ=1}^{k} A^{ℓ−1}) m⁻¹ p⁺ (round-off: 1e-12 relative).
    CHECK(rel(loop(s, {.order = k}), Field(sum)) < 1e-12);
    // The assembled sparse inverse m̃_k⁻¹ gives the same.
    CHECK(rel(Field(fmpm_inverse(s.ops, {.order = k}) * Eigen::MatrixXd(s.p)), Field(sum)) < 1e-12);
    term = A * term;
    sum += term;
  }
}

TEST_CASE("the prior binomial form (Eq. 4) equals the incremental form (Eq. 5)", "[fmpm]") {
  const Setup s = setup();
  for (int k = 1; k <= 8; ++k) {
    CAPTURE(k);
    // Eq. (4): v⁺(k) = Σ_{ℓ=1}^{k} (−1)^{ℓ+1} v*_ℓ, v*_1 = k m⁻¹p⁺, v*_ℓ = (k+1−ℓ)/ℓ S⁺S v*_{ℓ−1}.
    Field vstar = double(k) * lumped(s), v = vstar, next;
    for (int ell = 2; ell <= k; ++ell) {
      next = s.ops.m_inv.asDiagonal() * (s.mt.matrix * vstar); // S⁺S v*, Eigen's product
      vstar = (double(k + 1 - ell) / ell) * next;
      v += (ell % 2 == 0 ? -1.0 : 1.0) * vstar;
    }
    CHECK(rel(loop(s, {.order = k}), v) < 1e-12);
  }
}

TEST_CASE("blended recursions equal their series (FMPM 2026 §3.3)", "[fmpm]") {
  const Setup s = setup();
  const Eigen::MatrixXd A = dense_A(s);
  const Eigen::MatrixXd minv_p = s.ops.m_inv.asDiagonal() * Eigen::MatrixXd(s.p);
  const double alpha = 0.8;
  // m = 2: (I + A + αA² + αA³ + α²A⁴ + α²A⁵ + …) m⁻¹ p.
  Eigen::MatrixXd term = minv_p, sum = minv_p;
  for (int k = 2; k <= 9; ++k) {
    term = A * term;
    sum += std::pow(alpha, (k - 1) / 2) * term; // coefficient of A^{k−1}
    CAPTURE(k);
    CHECK(rel(loop(s, {.order = k, .blend_alpha = alpha, .blend_every = 2}), Field(sum)) < 1e-12);
  }
  // m = 1: the limit is (I − αA)⁻¹ m⁻¹ p; ρ(αA) ≤ 0.8, so 300 terms leave < 0.8^300.
  const Eigen::MatrixXd exact =
      (Eigen::MatrixXd::Identity(A.rows(), A.cols()) - alpha * A).partialPivLu().solve(minv_p);
  CHECK(rel(loop(s, {.order = 300, .blend_alpha = alpha, .blend_every = 1}), Field(exact)) < 1e-12);
}

TEST_CASE("a block in uniform motion gives dv(2) = 0 (FMPM 2026 §3.4)", "[fmpm]") {
  Setup s = setup();
  s.P.V.col(0).setConstant(0.7);
  s.P.V.col(1).setConstant(-0.3);
  map_momentum(particle_operators(s.ops), s.P.V, s.p);
  const Field v1 = loop(s, {.order = 1}), v2 = loop(s, {.order = 2});
  // Δv(2) = (I − S⁺S) S⁺V = 0 for constant V: zero up to round-off (1e-15 relative).
  CHECK((v2 - v1).norm() < 1e-15 * v1.norm());
}

TEST_CASE("velocity BC methods: incremental keeps every BC, combined departs for k > 2", "[fmpm]") {
  const Setup s = setup();
  BoundaryConditions bcs;
  VelocityCondition c;
  c.nodes = nodes_on_plane(s.grid, 0, 4.0); // a line of nodes inside the block
  c.direction = Eigen::Vector3d(1, 1, 0).normalized();
  c.value = [](double, const Eigen::Vector3d& x) { return 0.1 + 0.05 * x[1]; };
  bcs.conditions.push_back(c);
  const LoopConstraints bc{&s.grid, &bcs, 0.0};
  auto violation = [&](const Field& v) {
    double worst = 0;
    for (Index i : c.nodes)
      if (s.ops.active[i])
        worst = std::max(
            worst, std::abs(v.row(i).dot(c.direction.head(2)) -
                            c.value_at(0, Eigen::Vector3d(4, s.grid.node_coordinate(i, 1), 0))));
    return worst;
  };
  auto run = [&](BCMethod method, int k) {
    Field v = lumped(s);
    if (method != BCMethod::Velocity)
      bcs.constrain_velocity(s.grid, 0, v, &s.ops.active); // Table 2, top block
    FmpmWorkspace w;
    fmpm_velocity(s.ops, s.mt.matrix, {.order = k, .bc_method = method}, bc, v, w);
    return v;
  };
  for (int k = 1; k <= 8; ++k) {
    CAPTURE(k);
    CHECK(violation(run(BCMethod::Incremental, k)) < 1e-14); // every k
    if (k >= 2)
      CHECK(violation(run(BCMethod::Lumped, k)) > 1e-4); // the loop undoes lumped BCs
  }
  // The new method equals the combined one for k ≤ 2 and departs from it for k > 2 (§3.1).
  CHECK(rel(run(BCMethod::Combined, 2), run(BCMethod::Incremental, 2)) < 1e-14);
  CHECK(rel(run(BCMethod::Combined, 3), run(BCMethod::Incremental, 3)) > 1e-6);
}

TEST_CASE("dynamic FMPM stops at the first order whose metric is below the limit", "[fmpm]") {
  const Setup s = setup();
  for (auto metric : {ConvergenceMetric::Means, ConvergenceMetric::Changes}) {
    CAPTURE(to_string(metric));
    // Metric of each increment from full loops of increasing order.
    std::vector<double> m(21, 0.0);
    for (int ell = 2; ell <= 20; ++ell)
      m[size_t(ell)] =
          convergence_metric(metric, loop(s, {.order = ell}) - loop(s, {.order = ell - 1}),
                             loop(s, {.order = ell}), s.ops);
    const double limit = 0.5 * (m[4] + m[5]); // between ℓ = 4 and 5 when the metric decreases
    int expected = 20;
    for (int ell = 2; ell <= 20; ++ell)
      if (m[size_t(ell)] < limit) {
        expected = ell;
        break;
      }
    Field v = lumped(s);
    FmpmWorkspace w;
    const FmpmReport r = fmpm_velocity(
        s.ops, s.mt.matrix, {.order = 20, .metric = metric, .dynamic_limit = limit}, {}, v, w);
    CHECK(r.order == expected);
    CHECK(r.metric == approx(m[size_t(expected)], 1e-14, 1e-12));
    CHECK(rel(v, loop(s, {.order = expected})) < 1e-14);
    // The trace of the metric (Fig. 13A) holds the metric of every pass ℓ = 2 … order.
    REQUIRE(w.metrics.size() == size_t(expected - 1));
    for (int ell = 2; ell <= expected; ++ell)
      CHECK(w.metrics[size_t(ell - 2)] == approx(m[size_t(ell)], 1e-14, 1e-12));
    // A limit of 0 never stops the loop: the whole curve to the order.
    Field u = lumped(s);
    fmpm_velocity(s.ops, s.mt.matrix, {.order = 20, .metric = metric, .dynamic_limit = 0}, {}, u,
                  w);
    REQUIRE(w.metrics.size() == 19);
    CHECK(w.metrics.back() == approx(m[20], 1e-14, 1e-12));
  }
}

TEST_CASE("XPIC(m) is the projection (I - (I - S S+)^m) V (contact 2020 Eq. 36)", "[fmpm]") {
  const Setup s = setup();
  const Eigen::MatrixXd S(s.ops.S);
  const Eigen::MatrixXd Sp(S_plus(s.ops));
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(S.rows(), S.rows()) - S * Sp; // I − SS⁺
  const Eigen::MatrixXd V(s.P.V);
  Eigen::MatrixXd Qm = Eigen::MatrixXd::Identity(S.rows(), S.rows());
  for (int m = 1; m <= 5; ++m) {
    Qm = Qm * Q;
    Field u;
    FmpmWorkspace w;
    xpic_grid_velocity(s.ops, s.mt.matrix, m, lumped(s), u, w);
    const Eigen::MatrixXd PV = V - Qm * V;
    CAPTURE(m);
    CHECK((S * Eigen::MatrixXd(u) - PV).norm() < 1e-12 * PV.norm());
  }
}

TEST_CASE("XPIC(m) is the FMPM loop run from v: m (v - v*) = sum_{j<m} A^j v", "[fmpm]") {
  // The binomial identity behind XpicContact::Increments: contact 2020 Eqs. (41)–(43) (the
  // recursion of xpic_grid_velocity) and m − 1 passes of Table 1's loop from v⁺(1) = v give the
  // same grid velocity, Σ_{k=1}^{m} (−1)^{k−1} C(m, k) (S⁺S)^{k−1} v; round-off 1e-13, m = 1 … 8.
  const Setup s = setup();
  for (int m = 1; m <= 8; ++m) {
    Field u, v = lumped(s);
    FmpmWorkspace w;
    xpic_grid_velocity(s.ops, s.mt.matrix, m, v, u, w);
    fmpm_loop(s.ops.m_inv, s.mt.matrix, {.order = m}, {}, v, w);
    CAPTURE(m);
    CHECK(rel(v, u) < 1e-13);
  }
}

TEST_CASE("the FMPM loop calls its hooks on every increment (Table 1, lines 1-3)", "[fmpm]") {
  // A contact-like hook (line 2) that drops every increment after ℓ = 3 leaves v⁺(3); the BC
  // hook (line 1) sees each Δv(ℓ) first; the convergence hook (line 3) stops at ℓ = 6 with the
  // metric it reports. Each v⁺ is compared with the loop without hooks (round-off 1e-14).
  const Setup s = setup();
  std::vector<int> bc_calls, contact_calls;
  FmpmHooks hooks;
  hooks.velocity_bcs = [&](int ell, Field&) { bc_calls.push_back(ell); };
  hooks.contact = [&](int ell, Field& dv, const Field& v) {
    contact_calls.push_back(ell);
    CHECK(v.rows() == dv.rows()); // the evolving v⁺(ℓ − 1) comes with the increment
    if (ell > 3)
      dv.setZero();
  };
  Field v = lumped(s);
  FmpmWorkspace w;
  const FmpmReport r = fmpm_loop(s.ops.m_inv, s.mt.matrix, {.order = 8}, hooks, v, w);
  CHECK(r.order == 8);
  CHECK(bc_calls == std::vector<int>{2, 3, 4, 5, 6, 7, 8});
  CHECK(contact_calls == bc_calls);
  CHECK(rel(v, loop(s, {.order = 3})) < 1e-14);
  hooks = {};
  hooks.converged = [](int ell, const Field&, const Field&, double& metric) {
    metric = 1.0 / ell;
    return ell == 6;
  };
  v = lumped(s);
  const FmpmReport stop = fmpm_loop(s.ops.m_inv, s.mt.matrix, {.order = 20}, hooks, v, w);
  CHECK(stop.order == 6);
  CHECK(stop.metric == 1.0 / 6);
  CHECK(rel(v, loop(s, {.order = 6})) < 1e-14);
}

TEST_CASE("the BC method's sequence around the loop is FMPM 2026 §3.1's, for any algebra",
          "[fmpm][boundary]") {
  // grid_velocity_bc_sequence is the one sequence of the serial updated_velocity and of its PETSc
  // twin (both instantiate it on their vectors). Here on an algebra that records its calls,
  // against §3.1's text: the lumped method applies the BCs in step 2.a (on p⁺) only; the
  // velocity method skips 2.a and sets the BC velocities on v⁺(k) after step 3.b; the combined
  // method does both; the incremental method (the paper's new one) applies 2.a and corrects
  // each increment inside the loop (Table 2's bottom block, a hook of the loop). With k = 1
  // there is no loop: every method is the lumped update (2.a, then v⁺(1) = m⁻¹ p⁺).
  struct Recorder {
    std::string calls;
    void constrain_momentum() { calls += "2a "; }
    void lumped_solve() { calls += "v1 "; }
    FmpmReport loop() {
      calls += "loop ";
      return {};
    }
    void constrain_velocity() { calls += "vk "; }
  };
  const std::pair<BCMethod, const char*> expected[] = {{BCMethod::Lumped, "2a v1 loop "},
                                                       {BCMethod::Velocity, "v1 loop vk "},
                                                       {BCMethod::Combined, "2a v1 loop vk "},
                                                       {BCMethod::Incremental, "2a v1 loop "}};
  for (const auto& [method, calls] : expected) {
    CAPTURE(int(method));
    Recorder k4, k1, free;
    grid_velocity_bc_sequence({.order = 4, .bc_method = method}, true, true, k4);
    CHECK(k4.calls == calls);
    grid_velocity_bc_sequence({.order = 1, .bc_method = method}, true, true, k1);
    CHECK(k1.calls == "2a v1 ");
    grid_velocity_bc_sequence({.order = 4, .bc_method = method}, false, true, free);
    CHECK(free.calls == "v1 loop "); // no conditions: nothing to constrain
  }
}
