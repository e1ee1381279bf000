// SPDX-License-Identifier: BSD-3-Clause
// Shape functions: partition of unity, linear completeness and gradient consistency
// (Buzzi Eqs. 17–18; Sadeghirad et al. 2011 for CPDI), on seeded random clouds.

#include "support.hpp"

#include <Eigen/Dense>
#include <algorithm>

using namespace smpm;
using smpm::test::approx;

namespace {
const Shape kAllShapes[] = {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI,
                            Shape::B2CPDI};
}

TEST_CASE("shape functions reproduce constant and linear fields", "[shape]") {
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : kAllShapes) {
      CAPTURE(dim, to_string(shape));
      const Grid g = smpm::test::test_grid(dim, 10);
      // 3 cells from every edge: supports (≤ 1.5 cells + deformed domain) stay inside.
      const Particles P = smpm::test::random_cloud(g, 60, 17u + dim, 3.0, true);
      SparseRowMatrix S;
      std::array<SparseRowMatrix, 3> G;
      std::vector<ShapeSupport> support;
      assemble_shape(g, P, shape, S, G, support);
      const Eigen::MatrixXd x = g.node_positions();
      const Eigen::VectorXd one = Eigen::VectorXd::Ones(g.num_nodes());

      // Partition of unity, S 1 = 1 (exact up to round-off: 1e-13).
      CHECK((S * one - Eigen::VectorXd::Ones(P.size())).cwiseAbs().maxCoeff() < 1e-13);
      // Linear completeness, S x = X (round-off on coordinates of size ≤ 25: 1e-12).
      CHECK((S * x - P.X).cwiseAbs().maxCoeff() < 1e-12);
      for (int b = 0; b < dim; ++b) {
        // Σ_i G_pi = 0 (gradient of a constant), relative to 1/h ≥ 0.5: 1e-12.
        CHECK((G[b] * one).cwiseAbs().maxCoeff() < 1e-12);
        // Σ_i (G_b)_pi x_ia = δ_ab (gradient of a linear field).
        for (int a = 0; a < dim; ++a) {
          const double expected = a == b ? 1.0 : 0.0;
          CHECK(((G[b] * x.col(a)).array() - expected).abs().maxCoeff() < 1e-11);
        }
      }
      // Weights are non-negative (all five families are).
      CHECK(Eigen::Map<const Eigen::VectorXd>(S.valuePtr(), S.nonZeros()).minCoeff() >= 0.0);
    }
}

TEST_CASE("1D CPDI is the corner average of the hat and its secant slope", "[shape]") {
  // Issue definition: S_pi = ½(N_i(a) + N_i(b)), G_pi = (N_i(b) − N_i(a))/(b − a).
  const Grid g(1, {0, 0, 0}, {1, 1, 1}, {6, 1, 1});
  Particles P;
  P.resize(1, 1);
  P.X(0, 0) = 2.3;
  P.half_length(0, 0) = 0.25;
  P.F(0, 0) = 1.2; // domain [a, b] = [2.0, 2.6]
  P.mass[0] = 1;
  const Operators ops = assemble(g, P, Shape::CPDI);
  const Eigen::MatrixXd S = Eigen::MatrixXd(ops.S), G = Eigen::MatrixXd(ops.G[0]);
  // N_2(2.0) = 1, N_2(2.6) = 0.4, N_3(2.6) = 0.6.
  CHECK(S(0, 2) == approx(0.7, 1e-15));
  CHECK(S(0, 3) == approx(0.3, 1e-15));
  CHECK(G(0, 2) == approx((0.4 - 1.0) / 0.6, 1e-14));
  CHECK(G(0, 3) == approx((0.6 - 0.0) / 0.6, 1e-14));
}

TEST_CASE("2D CPDI gradient is the domain average of the corner interpolant's gradient",
          "[shape]") {
  // Independent evaluation of G_pi = (1/V_p) ∫ ∇(Σ_c Q_c N_i(x_c)) dV over a sheared
  // parallelogram by a 40×40 midpoint rule in the reference square; the integrand is linear in
  // ξ, so the rule is exact and the two agree to round-off (1e-12).
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {6, 6, 1});
  Particles P;
  P.resize(2, 1);
  P.X.row(0) << 2.4, 2.7;
  P.half_length.row(0) << 0.3, 0.4;
  P.F.row(0) << 1.1, 0.35, -0.2, 0.9; // F = [[1.1, 0.35], [−0.2, 0.9]]
  P.mass[0] = 1;
  const Operators ops = assemble(g, P, Shape::CPDI);
  Eigen::Matrix2d F;
  F << 1.1, 0.35, -0.2, 0.9;
  const Eigen::Matrix2d R = F * Eigen::Vector2d(0.3, 0.4).asDiagonal();
  auto hat = [](double r) { return std::max(0.0, 1 - std::abs(r)); };
  for (Index i = 0; i < g.num_nodes(); ++i) {
    const Eigen::Vector2d xi(g.node_coordinate(i, 0), g.node_coordinate(i, 1));
    double Nc[4];
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector2d s((c & 1) ? 1 : -1, (c & 2) ? 1 : -1);
      const Eigen::Vector2d xc = Eigen::Vector2d(2.4, 2.7) + R * s;
      Nc[c] = hat(xc[0] - xi[0]) * hat(xc[1] - xi[1]);
    }
    // ∇_x = R^{-T} ∇_ξ of Σ_c N_c (1 + s1 ξ1)(1 + s2 ξ2)/4, averaged over ξ ∈ [−1, 1]².
    Eigen::Vector2d avg = Eigen::Vector2d::Zero();
    const int q = 40;
    for (int a = 0; a < q; ++a)
      for (int b = 0; b < q; ++b) {
        const double x1 = -1 + (a + 0.5) * 2.0 / q, x2 = -1 + (b + 0.5) * 2.0 / q;
        Eigen::Vector2d gxi = Eigen::Vector2d::Zero();
        for (int c = 0; c < 4; ++c) {
          const double s1 = (c & 1) ? 1 : -1, s2 = (c & 2) ? 1 : -1;
          gxi[0] += Nc[c] * s1 * (1 + s2 * x2) / 4;
          gxi[1] += Nc[c] * s2 * (1 + s1 * x1) / 4;
        }
        avg += R.transpose().inverse() * gxi / double(q * q);
      }
    CAPTURE(i);
    CHECK(Eigen::MatrixXd(ops.G[0])(0, i) == approx(avg[0], 1e-12));
    CHECK(Eigen::MatrixXd(ops.G[1])(0, i) == approx(avg[1], 1e-12));
  }
}

TEST_CASE("the sparsity pattern is reused while no particle changes its node box", "[shape]") {
  const Grid g = smpm::test::test_grid(2, 10);
  Particles P = smpm::test::random_cloud(g, 30, 5u, 3.0, true);
  Operators ops = assemble(g, P, Shape::CPDI);
  const int* inner_before = ops.S.innerIndexPtr();
  P.X.array() += 1e-9; // too small to cross a cell boundary for this seed
  assemble(g, P, Shape::CPDI, ops);
  CHECK(ops.S.innerIndexPtr() == inner_before);
  const Operators fresh = assemble(g, P, Shape::CPDI);
  // Same values as a fresh assembly: exact.
  CHECK((Eigen::MatrixXd(ops.S) - Eigen::MatrixXd(fresh.S)).cwiseAbs().maxCoeff() == 0.0);
  CHECK((Eigen::MatrixXd(ops.G[1]) - Eigen::MatrixXd(fresh.G[1])).cwiseAbs().maxCoeff() == 0.0);
}

namespace {
// Pattern and values equal (==): outer and inner indices and values of S and G, m and the
// column index with its row spans.
void check_same_operators(const Operators& a, const Operators& b, int dim) {
  auto same = [](const SparseRowMatrix& x, const SparseRowMatrix& y) {
    REQUIRE(x.nonZeros() == y.nonZeros());
    REQUIRE(x.rows() == y.rows());
    CHECK(std::equal(x.outerIndexPtr(), x.outerIndexPtr() + x.rows() + 1, y.outerIndexPtr()));
    CHECK(std::equal(x.innerIndexPtr(), x.innerIndexPtr() + x.nonZeros(), y.innerIndexPtr()));
    CHECK(std::equal(x.valuePtr(), x.valuePtr() + x.nonZeros(), y.valuePtr()));
  };
  same(a.S, b.S);
  for (int k = 0; k < dim; ++k)
    same(a.G[size_t(k)], b.G[size_t(k)]);
  CHECK(a.m == b.m);
  CHECK(a.columns.entry == b.columns.entry);
  CHECK(a.columns.row == b.columns.row);
  // The row spans the node sums read (ColumnIndex::span): each row's first and last node, kept
  // up to date as rows move in place (stored only where they changed).
  REQUIRE(a.columns.span.size() == size_t(2 * a.S.rows()));
  CHECK(a.columns.span == b.columns.span);
  const int* outer = a.S.outerIndexPtr();
  const int* inner = a.S.innerIndexPtr();
  for (Index p = 0; p < a.S.rows(); ++p) {
    REQUIRE(outer[p + 1] > outer[p]);
    CHECK(a.columns.span[size_t(2 * p)] == inner[outer[p]]);
    CHECK(a.columns.span[size_t(2 * p + 1)] == inner[outer[p + 1] - 1]);
  }
}
} // namespace

TEST_CASE("boxes that move are rewritten in place and equal a fresh assembly", "[shape]") {
  // Every third particle moves by exactly one cell along x (boxes keep their sizes: S's rows
  // are rewritten in place), then every fifth by 0.37 cells (uGIMP and CPDI boxes change size:
  // a new pattern). After each move, the operators equal those assembled afresh.
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : kAllShapes)
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const Grid g = smpm::test::test_grid(dim, 10);
        Particles P = smpm::test::random_cloud(g, 40, 29u + dim, 3.0, true);
        Eigen::VectorXi field(P.size());
        for (Index p = 0; p < P.size(); ++p)
          field[p] = int(p % fields);
        const Eigen::VectorXi* f = fields > 1 ? &field : nullptr;
        Operators ops;
        assemble(g, P, shape, ops, fields, f);
        for (double shift : {1.0, 0.37}) {
          CAPTURE(shift);
          const long version = ops.pattern_version;
          for (Index p = 0; p < P.size(); p += shift == 1.0 ? 3 : 5)
            P.X(p, 0) += shift * g.cell_size(0);
          assemble(g, P, shape, ops, fields, f);
          CHECK(ops.pattern_version != version);
          Operators fresh;
          assemble(g, P, shape, fresh, fields, f);
          check_same_operators(ops, fresh, dim);
        }
      }
}

TEST_CASE("the pattern follows a new grid, new fields and a failed assembly", "[shape]") {
  // Boxes unchanged in node coordinates but columns changed: a grid of 5 × 10 nodes, then one of
  // 10 × 5 (the same number of nodes); then the particle fields swapped. And an assembly that
  // throws (a particle leaves the grid) after other particles' rows moved leaves S and G empty;
  // the next one equals a fresh assembly. Operators equal (==) fresh ones after each.
  const Grid g1(2, {0, 0, 0}, {1, 1, 1}, {4, 9, 1}), g2(2, {0, 0, 0}, {1, 1, 1}, {9, 4, 1});
  Particles P;
  P.resize(2, 3000); // above the threshold of the parallel loops: rows rewritten on threads
  for (Index p = 0; p < P.size(); ++p) {
    P.X(p, 0) = 1.2 + 1.6 * double(p % 7) / 7;
    P.X(p, 1) = 1.3 + 1.4 * double(p % 11) / 11;
  }
  P.half_length.setConstant(0.25);
  P.mass.setOnes();
  Eigen::VectorXi field(P.size());
  for (Index p = 0; p < P.size(); ++p)
    field[p] = int(p % 2);
  for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::CPDI}) {
    CAPTURE(to_string(shape));
    Operators ops;
    assemble(g1, P, shape, ops, 2, &field);
    assemble(g2, P, shape, ops, 2, &field);
    Operators fresh;
    assemble(g2, P, shape, fresh, 2, &field);
    check_same_operators(ops, fresh, 2);
    Eigen::VectorXi swapped = 1 - field.array();
    assemble(g2, P, shape, ops, 2, &swapped);
    Operators fresh_swapped;
    assemble(g2, P, shape, fresh_swapped, 2, &swapped);
    check_same_operators(ops, fresh_swapped, 2);

    Particles Q = P;
    for (Index p = 0; p < Q.size(); p += 3)
      Q.X(p, 0) += 1.0; // boxes move one cell
    Q.X(Q.size() - 1, 0) = 50;
    CHECK_THROWS_WITH(assemble(g2, Q, shape, ops, 2, &field), Catch::Contains("particle 2999"));
    CHECK(ops.S.nonZeros() == 0);
    CHECK(ops.support.empty());
    Q.X(Q.size() - 1, 0) = 2.5;
    assemble(g2, Q, shape, ops, 2, &field);
    Operators fresh_q;
    assemble(g2, Q, shape, fresh_q, 2, &field);
    check_same_operators(ops, fresh_q, 2);
  }
}

TEST_CASE("a particle whose support leaves the grid is reported by index", "[shape]") {
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  Particles P;
  P.resize(2, 2);
  P.X.row(0) << 2.0, 2.0;
  P.X.row(1) << 3.9, 0.6; // B-spline support reaches node x = 5 > 4
  P.half_length.setConstant(0.25);
  P.mass.setOnes();
  CHECK_NOTHROW(assemble(g, P, Shape::Linear));
  CHECK_THROWS_WITH(assemble(g, P, Shape::BSpline2),
                    Catch::Contains("particle 1") && Catch::Contains("left the grid"));
}

TEST_CASE("domains reaching the grid's edge need no node of zero weight", "[shape]") {
  // A uGIMP / CPDI block filling the whole grid [0, 10]: the last domains end exactly on the
  // last node, so their support is inside the grid; S 1 = 1 to round-off.
  const Grid g(1, {0, 0, 0}, {1, 1, 1}, {10, 1, 1});
  const Particles P = make_block(g, {0, 0, 0}, {10, 0, 0}, {2, 1, 1}, 1.0, 0);
  for (Shape shape : {Shape::GIMP, Shape::CPDI}) {
    CAPTURE(to_string(shape));
    const Operators ops = assemble(g, P, shape);
    CHECK((ops.S * Eigen::VectorXd::Ones(g.num_nodes()) - Eigen::VectorXd::Ones(P.size()))
              .cwiseAbs()
              .maxCoeff() < 1e-14);
  }
}

TEST_CASE("operators on the particles' window equal those on the whole grid", "[shape][window]") {
  // NodeRange::Particles numbers the nodes of a window of the grid (Grid::window): S, G, m and m̃
  // must be those of the whole grid with the columns renumbered, value for value (the shape
  // functions are computed in the grid's own cell coordinates: the same bits). A cloud in a
  // corner of a 40-cell grid, moved by 0.3 cells (boxes move, the window stays) and then by 9
  // cells (the window moves: a new numbering), in 1D–3D, every shape, one and two fields.
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : kAllShapes)
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const Grid g = smpm::test::test_grid(dim, dim == 3 ? 24 : 40);
        const Grid corner = g.window({0, 0, 0}, {12, dim > 1 ? 12 : 1, dim > 2 ? 12 : 1});
        Particles P = smpm::test::random_cloud(
            Grid(dim, {g.origin(0), g.origin(1), g.origin(2)},
                 {g.cell_size(0), g.cell_size(1), g.cell_size(2)}, {11, 11, 11}),
            dim == 3 ? 60 : 40, 7u + unsigned(dim), 3.0, true);
        Eigen::VectorXi field(P.size());
        for (Index p = 0; p < P.size(); ++p)
          field[p] = int(p % fields);
        const Eigen::VectorXi* f = fields > 1 ? &field : nullptr;
        Operators win;
        win.node_range = NodeRange::Particles;
        ConsistentMass mt_win;
        for (double shift : {0.0, 0.3, 9.0}) {
          CAPTURE(shift);
          for (Index p = 0; p < P.size(); ++p)
            for (int a = 0; a < dim; ++a)
              P.X(p, a) += shift * g.cell_size(a);
          assemble(g, P, shape, win, fields, f);
          Operators whole;
          assemble(g, P, shape, whole, fields, f);
          const Grid& w = win.grid;
          REQUIRE(w.is_window());
          CHECK(win.grid_node_count == w.num_nodes());
          CHECK(win.S.cols() == fields * w.num_nodes());
          for (int a = 0; a < dim; ++a) // the window follows the particles: two blocks at most
            CHECK(w.nodes(a) <= 2 * kWindowBlock);
          if (shift == 0.0)
            CHECK(w.first_node(0) == corner.first_node(0));
          else if (shift == 9.0)
            CHECK(w.first_node(0) == 8); // one block (kWindowBlock nodes) on
          // Column c of field α on the window is column α n_g + whole_node(c) on the grid.
          auto whole_column = [&](Index c) {
            return (c / w.num_nodes()) * g.num_nodes() + w.whole_node(c % w.num_nodes());
          };
          CHECK(win.whole_node(win.S.cols() - 1) == whole_column(win.S.cols() - 1));
          for (int k = 0; k <= dim; ++k) {
            const SparseRowMatrix& A = k == 0 ? win.S : win.G[size_t(k - 1)];
            const SparseRowMatrix& B = k == 0 ? whole.S : whole.G[size_t(k - 1)];
            REQUIRE(A.nonZeros() == B.nonZeros());
            CHECK(
                std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.rows() + 1, B.outerIndexPtr()));
            CHECK(std::equal(A.valuePtr(), A.valuePtr() + A.nonZeros(), B.valuePtr()));
            bool columns = true;
            for (Index e = 0; e < A.nonZeros(); ++e)
              columns = columns && whole_column(A.innerIndexPtr()[e]) == B.innerIndexPtr()[e];
            CHECK(columns);
          }
          bool m_same = true, active_same = true;
          for (Index c = 0; c < win.m.size(); ++c) {
            m_same = m_same && win.m[c] == whole.m[whole_column(c)];
            active_same = active_same && win.active[c] == whole.active[whole_column(c)];
          }
          CHECK(m_same);
          CHECK(active_same);
          CHECK(win.m.sum() == Approx(whole.m.sum()).epsilon(1e-14)); // no mass left outside
          // m̃ in its stencil pattern, entry by entry.
          ConsistentMass mt_whole;
          assemble_consistent_mass(win, mt_win);
          assemble_consistent_mass(whole, mt_whole);
          bool mt_same = true;
          Index entries = 0;
          for (Index r = 0; r < mt_win.matrix.rows(); ++r)
            for (SparseRowMatrix::InnerIterator it(mt_win.matrix, r); it; ++it) {
              mt_same = mt_same && it.value() == mt_whole.matrix.coeff(whole_column(r),
                                                                       whole_column(it.col()));
              entries += it.value() != 0;
            }
          CHECK(mt_same);
          const double* v = mt_whole.matrix.valuePtr();
          CHECK(entries ==
                std::count_if(v, v + mt_whole.matrix.nonZeros(), [](double x) { return x != 0; }));
        }
      }
}

TEST_CASE("m~'s stencil pattern follows a window of another shape", "[shape][window]") {
  // Two windows of 128 nodes, 8 × 16 then 16 × 8, every node touched: the same number of rows
  // and the same touched rows, but another stencil layout. m̃ must equal a fresh assembly and
  // its rows sum to m (FMPM 2026 §2.1), to round-off.
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {32, 32, 1});
  auto cells = [&](int nx, int ny) { // one particle at the centre of each cell x < nx, y < ny
    Particles P;
    P.resize(2, Index(nx) * ny);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Index p = Index(j) * nx + i;
        P.X(p, 0) = i + 0.5;
        P.X(p, 1) = j + 0.5;
        P.mass[p] = 1 + 0.01 * double(p % 7);
      }
    P.volume0.setOnes();
    P.half_length.setConstant(0.25);
    return P;
  };
  Operators ops;
  ops.node_range = NodeRange::Particles;
  ConsistentMass mt;
  for (const auto& [nx, ny] : {std::pair{7, 15}, std::pair{15, 7}}) {
    CAPTURE(nx, ny);
    const Particles P = cells(nx, ny);
    assemble(g, P, Shape::Linear, ops);
    REQUIRE(ops.num_nodes() == 128);
    CHECK(ops.grid_nodes == std::array<int, 3>{nx + 1, ny + 1, 1});
    assemble_consistent_mass(ops, mt);
    Operators fresh_ops;
    fresh_ops.node_range = NodeRange::Particles;
    assemble(g, P, Shape::Linear, fresh_ops);
    ConsistentMass fresh;
    assemble_consistent_mass(fresh_ops, fresh);
    CHECK(Eigen::MatrixXd(mt.matrix) == Eigen::MatrixXd(fresh.matrix));
    const Eigen::VectorXd rows = mt.matrix * Eigen::VectorXd::Ones(128);
    CHECK((rows - ops.m).cwiseAbs().maxCoeff() < 1e-14 * ops.m.maxCoeff());
  }
}
