// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal helpers of the shape-function assembly (shape.cpp, shape_points.cpp): the 1D grid
// functions and the fast path of the point-based families.

#include "kernels.hpp"

#include "sparsempm/shape.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string_view>
#include <vector>

namespace smpm::detail {

// 1D grid functions of r = (x − x_i)/h, in cell units.
// Both branch-free: uGIMP evaluates them at the edges of particle domains, where the branch a
// value takes is as good as random.
inline double hat(double r) {
  return std::max(0.0, 1 - std::abs(r));
}
// ∫_{−∞}^{r} hat: the antiderivative used by uGIMP, 0 below −1, ½(1 + r)² up to 0,
// 1 − ½(1 − r)² up to 1, then 1.
inline double hat_integral(double r) {
  const double a = 1 + std::max(r, -1.0), b = 1 - std::min(r, 1.0);
  return r <= 0 ? 0.5 * a * a : 1 - 0.5 * b * b;
}
// Quadratic B-spline on nodes (support ±1.5 cells) and its derivative.
inline double bspline2(double r) {
  const double q = std::abs(r);
  if (q < 0.5)
    return 0.75 - q * q;
  if (q < 1.5)
    return 0.5 * (1.5 - q) * (1.5 - q);
  return 0;
}
inline double bspline2_slope(double r) {
  const double q = std::abs(r);
  if (q < 0.5)
    return -2 * r;
  if (q < 1.5)
    return (r > 0 ? -1.0 : 1.0) * (1.5 - q);
  return 0;
}

// ξ = (X_p − origin)/h along each axis, in cell units (the reciprocal of h computed once).
template <int D>
struct CellCoordinates {
  double o[3], inv_h[3];
  const double* X;
  CellCoordinates(const Grid& g, const Particles& P) : X(P.X.data()) {
    for (int a = 0; a < D; ++a) {
      o[a] = g.origin(a);
      inv_h[a] = 1.0 / g.cell_size(a);
    }
  }
  double operator()(Index p, int a) const { return (X[p * D + a] - o[a]) * inv_h[a]; }
};

// ⌊x⌋ and ⌈x⌉ of a value in cell units known to lie within ±kFarCells (checked by interval_box
// before any other use): a truncation and its correction, the same integers as std::floor and
// std::ceil, which without SSE4.1 are a sequence of about 20 instructions that also handles
// values beyond int's range.
inline constexpr double kFarCells = 1e9;
inline int floor_int(double x) {
  const int t = int(x); // toward zero
  return t - int(x < double(t));
}
inline int ceil_int(double x) {
  const int t = int(x);
  return t + int(x > double(t));
}

// Nodes a particle may touch along an axis.
inline constexpr int kMaxBox = 12;

/// Throws NumericalError naming particle p, its position and `why`.
[[noreturn]] void throw_outside(Index p, const Particles& P, std::string_view why);

// The box of nodes with non-zero weight along axis a of a function of radius R (1 for the hat,
// 1.5 for the B-spline) spread over [lo, hi] (cell units): |ξ − i| < R for some ξ there, with a
// 10⁻¹² cell tolerance so that round-off does not reach a node of zero weight. Throws naming
// particle p when the box needs nodes outside the grid or more than kMaxBox nodes.
inline void interval_box(const Grid& g, const Particles& P, Index p, int a, double lo, double hi,
                         double R, int& first, int& count) {
  // Bounds in cell units far inside int's range (and not NaN), for floor_int and ceil_int.
  if (!(lo > -kFarCells && lo < kFarCells && hi > -kFarCells && hi < kFarCells)) {
    if (!std::isfinite(lo) || !std::isfinite(hi))
      throw_outside(p, P, "has a non-finite position or domain");
    throw_outside(p, P, "has left the grid (its shape-function support needs nodes outside it)");
  }
  constexpr double eps = 1e-12;
  first = floor_int(lo - R + eps) + 1;
  const int last = ceil_int(hi + R - eps) - 1;
  if (first < 0 || last > g.cells(a))
    throw_outside(p, P, "has left the grid (its shape-function support needs nodes outside it)");
  count = last - first + 1;
  if (count > kMaxBox)
    throw_outside(p, P, "has a domain spanning more than 11 cells");
}

/// How the node boxes changed since the previous assembly: none, some moved with every box
/// keeping its size, or some box changed size (S's rows change length: a new pattern).
enum class BoxChange { None, Moved, Resized };

/// Writes row p's column indices into each of the `Arrays` arrays `row` (S's and the G_a's, which
/// share its pattern): the nodes of box s, x fastest, from node `first` (its first node's
/// column). The box's sizes are read once (a write through an int* could alias them) and each
/// index is stored to every array in the same pass, not copied afterwards (a copy of a row this
/// short is a call to memmove); the number of arrays is a compile-time constant, so that the
/// stores of one index are straight-line code.
template <int Arrays>
inline void write_box_row(const Grid& g, const ShapeSupport& s, Index first, int* const* row) {
  const Index nx = g.nodes(0), nxy = nx * g.nodes(1);
  int* r[Arrays];
  for (int a = 0; a < Arrays; ++a)
    r[a] = row[a];
  // The common boxes' sizes at compile time (kernels.hpp): the row's stores are then unrolled.
  dispatch_box(s.count, [&]<int C0, int C1, int C2>() {
    const int c0 = C0 ? C0 : s.count[0], c1 = C1 ? C1 : s.count[1], c2 = C2 ? C2 : s.count[2];
    int q = 0;
    for (int k2 = 0; k2 < c2; ++k2)
      for (int k1 = 0; k1 < c1; ++k1) {
        const int line = int(first + k1 * nx + k2 * nxy);
        for (int k0 = 0; k0 < c0; ++k0, ++q)
          for (int a = 0; a < Arrays; ++a)
            r[a][q] = line + k0;
      }
  });
}

/// write_box_row for S and the G_a of a d-dimensional problem (d + 1 arrays).
inline void write_box_row(const Grid& g, const ShapeSupport& s, Index first, int* const* row,
                          int arrays) {
  switch (arrays) {
  case 2:
    return write_box_row<2>(g, s, first, row);
  case 3:
    return write_box_row<3>(g, s, first, row);
  default:
    return write_box_row<4>(g, s, first, row);
  }
}

/// Records the boxes of a support pass from any number of threads. With the pattern of the
/// previous assembly attached (`rows`), a box that moves and keeps its size has its row
/// rewritten in S and G at once: when no box changed size, the pattern is then up to date
/// without a pass over every row.
struct BoxChanges {
  struct Rows {
    const Grid* grid = nullptr;
    const int* outer = nullptr;
    std::array<int*, 4> inner{}; ///< S's and G's column indices
    int arrays = 0;
    Index nodes_per_field = 0;
    const int* field = nullptr; ///< particle fields (blocks of columns) or null
    Index first_column(Index p, const ShapeSupport& s) const {
      const Index block = field ? Index(field[p]) * nodes_per_field : 0;
      return block + grid->node_index(s.first[0], s.first[1], s.first[2]);
    }
  };
  std::atomic<bool> moved{false}, resized{false};
  const Rows* rows = nullptr;
  /// Stores particle p's new box s over its previous box.
  void record(Index p, ShapeSupport& old, const ShapeSupport& s) {
    // Compared entry by entry: ShapeSupport's == compares memory (memcmp), which keeps the new
    // box on the stack and loads it back wider than it was stored, a store-forwarding stall
    // per particle.
    bool same_count = true, same_first = true;
    for (size_t a = 0; a < 3; ++a) {
      same_count &= s.count[a] == old.count[a];
      same_first &= s.first[a] == old.first[a];
    }
    if (same_count && same_first)
      return; // written only when changed: the pattern is usually kept
    moved.store(true, std::memory_order_relaxed);
    if (!same_count) {
      resized.store(true, std::memory_order_relaxed);
    } else if (rows) {
      const int begin = rows->outer[p];
      int* row[4];
      for (int a = 0; a < rows->arrays; ++a)
        row[a] = rows->inner[size_t(a)] + begin;
      write_box_row(*rows->grid, s, rows->first_column(p, s), row, rows->arrays);
    }
    old = s;
  }
  BoxChange result() const {
    return resized.load() ? BoxChange::Resized : moved.load() ? BoxChange::Moved : BoxChange::None;
  }
};

// First node of the box of a point at ξ (cell units, within ±kFarCells) and the box width for a
// point.
inline int first_node(double xi, bool bspline) {
  return bspline ? floor_int(xi + 0.5) - 1 : floor_int(xi);
}
inline int point_count(bool bspline) {
  return bspline ? 3 : 2;
}

/// Node boxes of the point-based families (linear hat, quadratic B-spline when `bspline`) into
/// `support` (sized N); their boxes never change size.
void point_supports(const Grid& g, const Particles& P, bool bspline,
                    std::vector<ShapeSupport>& support, BoxChanges& changes);
/// Values of S and ∂S/∂x_a of the point-based families written straight into the CSR arrays.
void point_values(const Grid& g, const Particles& P, bool bspline,
                  const std::vector<ShapeSupport>& support, const int* outer, double* sv,
                  double* const* gv);
/// uGIMP (Buzzi Eqs. 17–18): the node boxes of the particle domains [X_p − r⁰_p, X_p + r⁰_p]
/// into `support`.
void gimp_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                   BoxChanges& changes);
/// Values of uGIMP's S and ∂S/∂x_a written straight into the CSR arrays.
void gimp_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                 const int* outer, double* sv, double* const* gv);

} // namespace smpm::detail
