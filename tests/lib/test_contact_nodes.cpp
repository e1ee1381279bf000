// SPDX-License-Identifier: BSD-3-Clause
// Contact nodes (find_contact_nodes; contact 2020 §3.1–3.4, FMPM 2026 §3.2): the normals and
// Δp(0) of nodes with velocity conditions, the logistic-regression plane and d_LR, R_p, and the
// DF edge fit and separation.

#include "contact_support.hpp"
#include "support.hpp"

#include <cmath>

using namespace smpm;
using smpm::test::approx;
using smpm::test::contact_nodes_of;
using smpm::test::cut_block;
using smpm::test::elastic;
using smpm::test::max_difference;
using smpm::test::pair_law;
using smpm::test::stacked_blocks_contact;

TEST_CASE("velocity conditions on a contact node: its normal and Δp(0) lose the fixed directions",
          "[contact]") {
  // find_contact_nodes with BCs (contact.hpp; NairnMPM's AdjustForSymmetry): on the nodes of a
  // roller fixing y, n̂ = (n_x, 0)/|n_x| of the unconstrained normal and free_part(Δp(0)) has
  // no y; on nodes fixing x and y there is no normal left; elsewhere nothing changes (the same
  // bits). The cut block's line is tilted, so its AG normals have both components.
  ContactPair law = pair_law(ContactLaw::Coulomb, ContactDetection::Always, 0.4);
  law.normal = ContactNormal::AverageGradient;
  const Model m = cut_block(5, &law);
  Operators ops;
  ContactNodes free, constrained;
  contact_nodes_of(m, ops, free);
  BoundaryConditions bcs;
  fix_box(m.grid, {0, 0, 0}, {12, 6, 0}, {false, true, false}, bcs);   // y below y = 6
  fix_box(m.grid, {0, 0, 0}, {12, 6, 0}, {false, true, false}, bcs);   // twice: parallel
  fix_box(m.grid, {0, 0, 0}, {12, 4.5, 0}, {true, false, false}, bcs); // and x below 4.5
  contact_nodes_of(m, ops, constrained, &bcs);
  REQUIRE(free.nodes.size() == constrained.nodes.size());
  int rollers = 0, fixed = 0, open = 0;
  for (size_t c = 0; c < free.nodes.size(); ++c) {
    const ContactNodes::Node &a = free.nodes[c], &b = constrained.nodes[c];
    const double y = m.grid.node_position(a.node)[1];
    CAPTURE(c, y, a.normal.transpose(), b.normal.transpose());
    const Eigen::Vector3d dp0(0.3, -0.7, 0);
    if (y > 6 + 1e-9) {
      ++open;
      CHECK(b.constrained < 0);
      CHECK(b.normal == a.normal);
      CHECK(b.separation == a.separation);
      CHECK(free_part(constrained, c, dp0) == dp0);
    } else if (y > 4.5 + 1e-9) {
      ++rollers;
      REQUIRE(std::abs(a.normal[0]) > 0.1);
      CHECK(b.normal[1] == 0);
      CHECK(b.normal[0] == approx(std::copysign(1.0, a.normal[0]), 1e-15));
      CHECK(b.area == approx(1.0, 1e-15)); // V_cell / h_n with n̂ = ±x̂
      CHECK(free_part(constrained, c, dp0).isApprox(Eigen::Vector3d(0.3, 0, 0), 1e-15));
    } else {
      ++fixed;
      CHECK(b.normal.norm() == 0);
      CHECK(free_part(constrained, c, dp0).norm() < 1e-15);
    }
  }
  CHECK(rollers > 0);
  CHECK(fixed > 0);
  CHECK(open > 0);
}

TEST_CASE("logistic regression finds the plane between two half-planes of particles",
          "[contact][lr]") {
  // Contact 2020 §3.1: two half-planes of particles (2 per cell per axis, cells of 1) whose
  // lattices are aligned with their common edge, at a random angle θ and a random offset from
  // the node: the cloud is every particle within 1.5 cells of the node. The LR normal recovers
  // θ within 0.01 rad (measured: at most 0.0084 over 20 angles; the paper's stopping rule,
  // 1 − n̂^(k+1)·n̂^(k) < 10⁻⁵, stops at a change of 0.0044 rad).
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const double theta = 2 * M_PI * u(rng), shift = 0.5 * u(rng) - 0.25, slide = u(rng);
    const Eigen::Vector2d n(std::cos(theta), std::sin(theta)), t(-n[1], n[0]);
    std::vector<Eigen::Vector2d> pts;
    std::vector<double> cls;
    for (int i = -8; i < 8; ++i)      // across the edge: centres at ±0.25, ±0.75, ...
      for (int j = -8; j <= 8; ++j) { // along it
        const double s = 0.5 * i + 0.25 + shift, r = 0.5 * (j + slide);
        const Eigen::Vector2d x = s * n + r * t;
        if (x.norm() > 1.5)
          continue;
        pts.push_back(x);
        cls.push_back(i < 0 ? -1.0 : 1.0);
      }
    Field X(Index(pts.size()), 2);
    for (Index k = 0; k < X.rows(); ++k)
      X.row(k) = pts[size_t(k)].transpose();
    const Eigen::VectorXd c = Eigen::Map<const Eigen::VectorXd>(cls.data(), Index(cls.size()));
    const LogisticFit fit = logistic_regression_normal(X, c, 1.0);
    CAPTURE(theta, shift, slide, fit.iterations);
    CHECK(std::acos(std::min(1.0, fit.normal.head<2>().dot(n))) < 0.01);
  }
}

TEST_CASE("R_p of a deformed particle is the radius of its ellipse along n (Eq. 25)",
          "[contact][lr]") {
  // r0 = (0.25, 0.25) stretched by F = diag(2, 1): the ellipse of semi-axes 0.5 and 0.25, whose
  // radius at angle φ is (cos²φ/a² + sin²φ/b²)^(−1/2): 0.5, 0.25 and 1/√10 at 45°.
  const double F[4] = {2, 0, 0, 1}, r0[2] = {0.25, 0.25};
  CHECK(particle_radius_along(2, F, r0, Eigen::Vector3d(1, 0, 0)) == approx(0.5, 1e-15));
  CHECK(particle_radius_along(2, F, r0, Eigen::Vector3d(0, 1, 0)) == approx(0.25, 1e-15));
  const Eigen::Vector3d diag = Eigen::Vector3d(1, 1, 0).normalized();
  CHECK(particle_radius_along(2, F, r0, diag) == approx(1 / std::sqrt(10.0), 1e-15));
  // A rotation carries the ellipse: F = R(30°) gives back the undeformed radii along R e_x.
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  const double R[4] = {c, -s, s, c}, r1[2] = {0.3, 0.1};
  CHECK(particle_radius_along(2, R, r1, Eigen::Vector3d(c, s, 0)) == approx(0.3, 1e-15));
}

TEST_CASE("d_LR is the gap between two blocks and changes sign when they touch (Fig. 3)",
          "[contact][lr]") {
  // Two blocks of particles (2 × 2 per cell, half-length 0.25) one above the other, their
  // domains a gap g apart (g < 0: overlapping): at every contact node the LR normal is ŷ and
  // d_LR = g (contact 2020 Eq. 24) to 1e-6 of a cell.
  for (double gap : {0.2, 0.05, -0.05, -0.2}) {
    CAPTURE(gap);
    ContactPair law = pair_law(ContactLaw::Frictionless, ContactDetection::LogisticRegression);
    law.normal = ContactNormal::LogisticRegression;
    Model m(Grid(1, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}));
    ContactNodes cn;
    stacked_blocks_contact(5.9, gap, law, m, cn);
    REQUIRE(cn.nodes.size() >= 9);
    for (const ContactNodes::Node& node : cn.nodes) {
      CAPTURE(node.node);
      CHECK(node.normal[1] == approx(1, 1e-6));
      CHECK(node.separation == approx(gap, 1e-6));
    }
  }
}

TEST_CASE("the DF fit of the edge position (contact 2020 Eq. 15, Fig. 1B)", "[contact][df]") {
  // d(s) = 1 − 2(−s/L)^r: −1 where the node's support ends (s = −L), +1 at the node, and with the
  // default r = ln 2 / ln(10/3) exactly 0 at s = −3/8, where the edge of undeformed uGIMP
  // particles at two per cell sits on the node (analysis/df_fit.py).
  const ContactPair p;
  CHECK(distance_function_edge(-1.25, p.df_exponent, p.df_reach) == approx(-1, 1e-15));
  CHECK(distance_function_edge(-0.375, p.df_exponent, p.df_reach) == approx(0, 1e-15));
  CHECK(distance_function_edge(0, p.df_exponent, p.df_reach) == 1);
  CHECK(distance_function_edge(0.3, p.df_exponent, p.df_reach) == 1);
}

TEST_CASE("the DF separation is the gap between two blocks, exact when they touch on a node",
          "[contact][df]") {
  // Two blocks of uGIMP particles (2 × 2 per cell) one above the other, their domains a gap g
  // apart (g < 0: overlapping), normal ŷ specified. With the interface on the grid line y = 6
  // and g = 0, the DF separation of contact 2020 Eq. (15) at the nodes of that line is 0 to
  // round-off (the fit is exact there); elsewhere it is g within twice the fit's largest error,
  // 0.021 cells (analysis/df_fit.py): asserted 0.045.
  for (double bottom : {6.0, 5.9})
    for (double gap : {0.0, 0.2, 0.05, -0.05, -0.2}) {
      CAPTURE(bottom, gap);
      ContactPair law = pair_law(ContactLaw::Frictionless, ContactDetection::DistanceFunction);
      law.normal = ContactNormal::Specified;
      Model m(Grid(1, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}));
      ContactNodes cn;
      stacked_blocks_contact(bottom, gap, law, m, cn);
      REQUIRE(cn.nodes.size() >= 9);
      for (const ContactNodes::Node& node : cn.nodes) {
        CAPTURE(node.node, m.grid.node_position(node.node)[1]);
        REQUIRE(node.a == 0);
        if (gap == 0 && bottom == 6.0 && m.grid.node_position(node.node)[1] == 6.0)
          CHECK(std::abs(node.separation) < 1e-12);
        else
          CHECK(node.separation == approx(gap, 0.045));
      }
    }
}
