// SPDX-License-Identifier: BSD-3-Clause
// Grid numbering (Buzzi Eq. 21), particles set-up and boundary selection.

#include "support.hpp"

#include <random>

using namespace smpm;
using smpm::test::approx;

TEST_CASE("node index and (i, j, k) are inverse maps", "[grid]") {
  const Grid g(3, {1, 2, 3}, {0.5, 1, 2}, {4, 3, 2});
  CHECK(g.num_nodes() == 5 * 4 * 3);
  for (Index n = 0; n < g.num_nodes(); ++n) {
    const auto ijk = g.node_ijk(n);
    CHECK(g.node_index(ijk[0], ijk[1], ijk[2]) == n);
  }
  CHECK(g.node_index(1, 2, 1) == 1 + 5 * (2 + 4 * 1)); // Buzzi Eq. 21 numbering
  CHECK(g.node_coordinate(g.node_index(4, 3, 2), 0) == approx(3.0, 1e-15));
  CHECK(g.node_coordinate(g.node_index(4, 3, 2), 2) == approx(7.0, 1e-15));
  CHECK(g.min_cell_size() == 0.5);
}

TEST_CASE("bad grids are rejected with the offending value", "[grid]") {
  CHECK_THROWS_WITH(Grid(4, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}), Catch::Contains("dimension"));
  CHECK_THROWS_WITH(Grid(2, {0, 0, 0}, {1, -1, 1}, {1, 1, 1}), Catch::Contains("cell_size[1]"));
  CHECK_THROWS_WITH(Grid(1, {0, 0, 0}, {1, 1, 1}, {0, 1, 1}), Catch::Contains("cells[0]"));
}

TEST_CASE("make_block fills a box with ppc^d particles per cell", "[particles]") {
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {10, 10, 1});
  const Particles P = make_block(g, {1, 2, 0}, {4, 4, 0}, {2, 3, 1}, 2.0, 0);
  CHECK(P.size() == 6 * 6);                          // (3·2) × (2·3)
  CHECK(P.mass.sum() == approx(2.0 * 3 * 2, 1e-13)); // ρ × area
  CHECK(P.volume0.sum() == approx(6.0, 1e-13));
  CHECK(P.X.col(0).minCoeff() == approx(1.25, 1e-15)); // half a spacing in
  CHECK(P.half_length(0, 1) == approx(1.0 / 6.0, 1e-15));
  CHECK_THROWS_AS(make_block(g, {1, 2, 0}, {14, 4, 0}, {2, 2, 1}, 1.0, 0), InputError);
  CHECK_THROWS_AS(make_block(g, {1, 2, 0}, {4, 4, 0}, {2, 2, 1}, -1.0, 0), InputError);
}

TEST_CASE("fixed planes select the nodes on them", "[boundary]") {
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {4, 3, 1});
  BoundaryConditions bc = BoundaryConditions::none(g);
  CHECK(fix_plane(g, 0, 0.0, {true, false, false}, bc) == 4); // the x = 0 column
  CHECK(bc.num_constrained() == 4);
  CHECK(fix_box(g, {3.5, -1, 0}, {5, 5, 0}, {true, true, false}, bc) == 4);
  CHECK(bc.num_constrained() == 12);
  CHECK_THROWS_WITH(fix_plane(g, 0, 0.5, {true, false, false}, bc),
                    Catch::Contains("contains no grid node"));
}

TEST_CASE("planes and boxes select by index the nodes a scan of the grid selects", "[boundary]") {
  // nodes_on_plane and nodes_in_box find a plane's or box's index range along each axis and
  // list its nodes; the reference is the scan of every node with the same tolerance (10⁻⁹ of a
  // cell), on grids with round-off in their coordinates, on windows, and at the tolerance.
  auto scan = [](const Grid& g, auto&& inside) {
    std::vector<Index> out;
    for (Index i = 0; i < g.num_nodes(); ++i)
      if (inside(g.node_position(i)))
        out.push_back(i);
    return out;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int d = 1 + trial % 3;
    const std::array<double, 3> origin{-0.3 + u(rng), 1.7 * u(rng), -u(rng)};
    const std::array<double, 3> h{0.1 + 0.01 * std::floor(10 * u(rng)), 0.3, 1.0 / 3};
    const std::array<int, 3> cells{3 + trial % 7, 2 + trial % 5, 1 + trial % 4};
    Grid g(d, origin, h, cells);
    if (trial % 4 == 3) // a window of the grid
      g = g.window({1, d > 1 ? 1 : 0, d > 2 ? 1 : 0},
                   {cells[0] - 1, d > 1 ? cells[1] : 1, d > 2 ? cells[2] : 1});
    const int axis = trial % d;
    const double tol = 1e-9 * h[size_t(axis)];
    const int q = int(std::floor(u(rng) * (cells[size_t(axis)] + 1)));
    for (const double offset : {0.0, 0.9 * tol, -0.9 * tol, 1.1 * tol, 0.5 * h[size_t(axis)]}) {
      const double at = origin[size_t(axis)] + h[size_t(axis)] * q + offset;
      const auto expected =
          scan(g, [&](const Eigen::Vector3d& x) { return std::abs(x[axis] - at) <= tol; });
      if (expected.empty())
        CHECK_THROWS_WITH(nodes_on_plane(g, axis, at), Catch::Contains("contains no grid node"));
      else
        CHECK(nodes_on_plane(g, axis, at) == expected);
    }
    std::array<double, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double span = h[size_t(a)] * (cells[size_t(a)] + 2);
      lo[size_t(a)] = origin[size_t(a)] - h[size_t(a)] + span * u(rng);
      hi[size_t(a)] = lo[size_t(a)] + span * u(rng) * 0.6;
      if (trial % 5 == 0) // a bound on a node, just outside the tolerance
        lo[size_t(a)] = origin[size_t(a)] + h[size_t(a)] + 1.1e-9 * h[size_t(a)];
    }
    const auto expected = scan(g, [&](const Eigen::Vector3d& x) {
      bool inside = true;
      for (int a = 0; a < d; ++a) {
        const double t = 1e-9 * h[size_t(a)];
        inside = inside && x[a] >= lo[size_t(a)] - t && x[a] <= hi[size_t(a)] + t;
      }
      return inside;
    });
    if (expected.empty())
      CHECK_THROWS_WITH(nodes_in_box(g, lo, hi), Catch::Contains("contains no grid node"));
    else
      CHECK(nodes_in_box(g, lo, hi) == expected);
  }
}

TEST_CASE("parallel velocity conditions add their values (FMPM 2026 Table 2)", "[boundary]") {
  // Top block of Table 2: zero every BC direction, then add Σ_b v_b n̂_b; perpendicular
  // conditions set their own components.
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {2, 2, 1});
  BoundaryConditions bc;
  for (double value : {0.1, 0.2}) {
    VelocityCondition c;
    c.nodes = {4};
    c.direction = Eigen::Vector3d::UnitX();
    c.value = [value](double, const Eigen::Vector3d&) { return value; };
    bc.conditions.push_back(c);
  }
  VelocityCondition y;
  y.nodes = {4};
  y.direction = Eigen::Vector3d::UnitY();
  y.value = [](double, const Eigen::Vector3d&) { return -0.5; };
  bc.conditions.push_back(y);
  Field v = Field::Constant(g.num_nodes(), 2, 7.0);
  bc.constrain_velocity(g, 0.0, v);
  CHECK(v(4, 0) == approx(0.3, 1e-15));
  CHECK(v(4, 1) == approx(-0.5, 1e-15));
  CHECK(v(3, 0) == 7.0); // other nodes untouched
}

TEST_CASE("a window numbers a box of the grid's nodes and keeps their positions",
          "[grid][window]") {
  // Grid::window: the nodes first ≤ (i, j, k) < first + count, numbered x fastest from the first;
  // (i, j, k), coordinates and positions are those of the whole grid, bit for bit.
  const Grid g(3, {-1.0, 0.25, 3.0}, {0.1, 0.3, 0.7}, {20, 9, 7});
  const Grid w = g.window({3, 2, 1}, {5, 4, 6});
  CHECK(w.is_window());
  CHECK_FALSE(g.is_window());
  CHECK(w.num_nodes() == 5 * 4 * 6);
  CHECK(w.whole_num_nodes() == g.num_nodes());
  CHECK(w.same_whole_grid(g));
  for (Index i = 0; i < w.num_nodes(); ++i) {
    const Index whole = w.whole_node(i);
    CHECK(g.node_ijk(whole) == w.node_ijk(i));
    CHECK(g.node_position(whole) == w.node_position(i)); // == : the same arithmetic
    CHECK(w.node_of_whole(whole) == i);
    const auto ijk = w.node_ijk(i);
    CHECK(w.node_index(ijk[0], ijk[1], ijk[2]) == i);
  }
  CHECK(w.whole_node(0) == g.node_index(3, 2, 1));
  CHECK(w.whole_node(1) == g.node_index(4, 2, 1)); // x fastest
  CHECK(w.whole_node(5) == g.node_index(3, 3, 1));
  Index outside = 0;
  for (Index n = 0; n < g.num_nodes(); ++n)
    outside += w.node_of_whole(n) < 0;
  CHECK(outside == g.num_nodes() - w.num_nodes());
  CHECK(w.node_of_whole(-1) == -1);
  CHECK(w.node_of_whole(g.num_nodes()) == -1);
  // A window of the whole grid is the grid; a window must lie inside it.
  CHECK_FALSE(g.window({0, 0, 0}, {21, 10, 8}).is_window());
  CHECK_THROWS_WITH(g.window({18, 0, 0}, {4, 1, 1}),
                    "grid window: nodes 18 to 21 along axis 0 are not inside the grid's 0 to 20");
  CHECK_THROWS_AS(g.window({0, -1, 0}, {1, 1, 1}), InputError);
  CHECK_THROWS_AS(g.window({0, 0, 0}, {1, 0, 1}), InputError);
}
