// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/shape.hpp"

#include "enum_names.hpp"
#include "kernels.hpp"
#include "parallel.hpp"
#include "shape_functions.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

namespace smpm {

namespace {
constexpr detail::EnumNames<Shape, 5> kShapes{{{Shape::Linear, "linear"},
                                               {Shape::GIMP, "gimp"},
                                               {Shape::BSpline2, "bspline2"},
                                               {Shape::CPDI, "cpdi"},
                                               {Shape::B2CPDI, "b2cpdi"}}};
} // namespace

std::string_view to_string(Shape s) {
  return detail::enum_name(s, kShapes);
}
Shape shape_from_string(std::string_view name) {
  return detail::parse_enum(name, kShapes, "shape function");
}

namespace {

using namespace detail;

bool uses_bspline(Shape s) {
  return s == Shape::BSpline2 || s == Shape::B2CPDI;
}

// Corner positions in cell units, xi_c[c][a], for the 2^D corners of the CPDI domain
// X_p + F_p diag(r⁰_p) ξ, ξ ∈ {−1, 1}^D (corner c has ξ_b = +1 where bit b of c is set).
template <int D>
void corners_of(const CellCoordinates<D>& f, const Particles& P, Index p, double xi_c[8][3]) {
  const double* X = P.X.data() + p * P.X.outerStride();
  const double* F = P.F.data() + p * P.F.outerStride();
  const double* r = P.half_length.data() + p * P.half_length.outerStride();
  double R[D][D]; // F diag(r⁰): (F_ab · (±1)) · r_b is ±(F_ab r_b) exactly
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      R[a][b] = F[a * D + b] * r[b];
  for (int c = 0; c < (1 << D); ++c)
    for (int a = 0; a < D; ++a) {
      double x = X[a];
      for (int b = 0; b < D; ++b)
        x += (c >> b) & 1 ? R[a][b] : -R[a][b];
      xi_c[c][a] = (x - f.o[a]) * f.inv_h[a];
    }
}

// CPDI and B2CPDI: the box of the corners' bounding box under the hat or the B-spline.
template <int D>
ShapeSupport corner_support(const Grid& g, const CellCoordinates<D>& f, const Particles& P, Index p,
                            bool bspline) {
  double xi_c[8][3];
  corners_of<D>(f, P, p, xi_c);
  ShapeSupport s;
  for (int a = 0; a < D; ++a) {
    double lo = xi_c[0][a], hi = xi_c[0][a];
    for (int c = 1; c < (1 << D); ++c) {
      lo = std::min(lo, xi_c[c][a]);
      hi = std::max(hi, xi_c[c][a]);
    }
    interval_box(g, P, p, a, lo, hi, bspline ? 1.5 : 1.0, s.first[size_t(a)], s.count[size_t(a)]);
  }
  return s;
}

// CPDI and B2CPDI (Sadeghirad et al. 2011): S_pi = 2^{-D} Σ_c N_i(x_c) and
// ∇S_pi = Σ_c N_i(x_c) g_c with g_c = 2^{-D} R^{-T} s_c, R = F diag(r⁰), over the 2^D corners x_c,
// written into the particle's row of S and G (box order, x fastest). Each corner adds to the W
// nodes per axis where its N can be nonzero (2 for the hat, 3 for the B-spline), in corner
// order: the sums are those over every corner and box node, without the zero terms. A corner's
// node outside the box (its weight below the box's 10⁻¹² tolerance, interval_box) adds to one
// slot past the row, which is dropped; the sums are made in `local` (len + 1 slots of S and the
// G_a side by side, the G_a as one vector) and then copied, so that the loops have compile-time
// bounds and no test per node.
// The family (hat or B-spline) is a compile-time constant.
template <int D, bool bspline>
void corner_row(const CellCoordinates<D>& f, const Particles& P, Index p, const ShapeSupport& s,
                double* S, double* const G[3], std::vector<double>& local) {
  constexpr int nc = 1 << D, W = bspline ? 3 : 2;
  double xi_c[8][3];
  corners_of<D>(f, P, p, xi_c);
  Eigen::Matrix<double, D, D> Fp;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      Fp(a, b) = P.F(p, a * D + b);
  const Eigen::Matrix<double, D, D> Finv_t = Fp.inverse().transpose();
  const double w = 1.0 / nc;
  const int c0 = s.count[0], c1 = D > 1 ? s.count[1] : 1, c2 = D > 2 ? s.count[2] : 1;
  const int len = c0 * c1 * c2;
  constexpr int stride = D + 1; // slot q: S at q (D + 1), G_a at q (D + 1) + 1 + a
  if (local.size() < size_t(stride * (len + 1)))
    local.resize(size_t(stride * (len + 1))); // kept between particles and steps
  double* sums = local.data();
  std::fill(sums, sums + stride * (len + 1), 0.0);
  double inv_r[D]; // ±1/r as ±(1/r): the same bits, one division per axis
  for (int b = 0; b < D; ++b)
    inv_r[b] = 1.0 / P.half_length(p, b);
  for (int c = 0; c < nc; ++c) {
    Eigen::Matrix<double, D, 1> sr;
    for (int b = 0; b < D; ++b)
      sr[b] = (c >> b) & 1 ? inv_r[b] : -inv_r[b];
    const Eigen::Matrix<double, D, 1> gc = w * Finv_t * sr;
    // The corner's W nodes on each axis (box-relative: pos), N there, and whether in the box.
    int pos[3][W] = {}, in[3][W];
    double n1[3][W];
    for (int a = D; a < 3; ++a)
      for (int k = 0; k < W; ++k) {
        in[a][k] = 1;
        n1[a][k] = 1;
      }
    for (int a = 0; a < D; ++a) {
      const double xi = xi_c[c][a];
      const int first = s.first[size_t(a)], start = first_node(xi, bspline); // ξ checked
      for (int k = 0; k < W; ++k) {
        const int i = start + k - first;
        pos[a][k] = i;
        in[a][k] = unsigned(i) < unsigned(s.count[size_t(a)]);
        const double r = xi - (start + k);
        n1[a][k] = bspline ? bspline2(r) : hat(r);
      }
    }
    for (int k2 = 0; k2 < (D > 2 ? W : 1); ++k2)
      for (int k1 = 0; k1 < (D > 1 ? W : 1); ++k1)
        for (int k0 = 0; k0 < W; ++k0) {
          double Nc = n1[0][k0];
          if constexpr (D > 1)
            Nc *= n1[1][k1];
          if constexpr (D > 2)
            Nc *= n1[2][k2];
          const int q = in[0][k0] & in[1][k1] & in[2][k2]
                            ? pos[0][k0] + c0 * (pos[1][k1] + c1 * pos[2][k2])
                            : len;
          double* slot = sums + q * stride;
          slot[0] += Nc;
          Eigen::Map<Eigen::Matrix<double, D, 1>>(slot + 1) += Nc * gc;
        }
  }
  for (int q = 0; q < len; ++q) {
    S[q] = sums[q * stride] * w;
    for (int a = 0; a < D; ++a)
      G[a][q] = sums[q * stride + 1 + a];
  }
}

// The window of the nodes in some particle's box (assemble_shape): their bounding box widened
// to multiples of kWindowBlock nodes, clipped to the grid.
Grid particle_window(const Grid& grid, const std::vector<ShapeSupport>& support) {
  const int d = grid.dim();
  std::array<int, 3> first{0, 0, 0}, count{1, 1, 1};
  if (support.empty()) // no particle: one node
    return grid.window(first, count);
  double bound[6]; // −(smallest first node), largest last node, per axis
  detail::ordered_reduce_blocks(
      Index(support.size()), 2 * d, -std::numeric_limits<double>::infinity(), bound,
      [&](Index begin, Index end, double* acc) {
        // Integer extremes in registers over the block (through acc, each particle's maxima
        // would wait on the stores of the one before).
        int lo[3] = {INT_MAX, INT_MAX, INT_MAX}, hi[3] = {INT_MIN, INT_MIN, INT_MIN};
        for (Index p = begin; p < end; ++p) {
          const ShapeSupport& s = support[size_t(p)];
          for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], s.first[size_t(a)]);
            hi[a] = std::max(hi[a], s.first[size_t(a)] + s.count[size_t(a)] - 1);
          }
        }
        for (int a = 0; a < d; ++a) {
          acc[2 * a] = std::max(acc[2 * a], -double(lo[a]));
          acc[2 * a + 1] = std::max(acc[2 * a + 1], double(hi[a]));
        }
      },
      [](double a, double b) { return std::max(a, b); });
  for (int a = 0; a < d; ++a) {
    const int lo = int(-bound[2 * a]), hi = int(bound[2 * a + 1]);
    first[size_t(a)] = lo / kWindowBlock * kWindowBlock;
    const int end = std::min(grid.cells(a) + 1, (hi / kWindowBlock + 1) * kWindowBlock);
    count[size_t(a)] = end - first[size_t(a)];
  }
  return grid.window(first, count);
}

// A new pattern of nnz entries: the old entries are not copied when the storage grows (Eigen's
// resize keeps them), and 1/8 slack lets boxes grow again without reallocating.
void set_pattern(SparseRowMatrix& A, Index N, Index n, Index nnz) {
  if (A.rows() != N || A.cols() != n)
    A.resize(N, n);
  if (nnz > A.data().allocatedSize()) {
    A.data().clear();
    A.data().reserve(nnz + nnz / 8);
  }
  A.resizeNonZeros(nnz);
}

} // namespace

namespace {

// Whether S (N × n) and the G_a have the same rows, columns and pattern sizes.
bool matches(const SparseRowMatrix& S, const std::array<SparseRowMatrix, 3>& G, int d, Index N,
             Index n) {
  bool same = S.rows() == N && S.cols() == n;
  for (int a = 0; a < d; ++a)
    same = same && G[size_t(a)].rows() == N && G[size_t(a)].nonZeros() == S.nonZeros();
  return same;
}

// On a failure some boxes are recorded and some rows rewritten: the pattern is emptied so that
// nothing stale is read, and the next call starts afresh.
void discard_pattern(std::vector<ShapeSupport>& support, SparseRowMatrix& S,
                     std::array<SparseRowMatrix, 3>& G) {
  support.clear();
  S.resize(0, 0);
  for (SparseRowMatrix& Ga : G)
    Ga.resize(0, 0);
}

// Pass 1: the node box of every particle, recorded in `support` (changes: which boxes moved or
// changed size, rows rewritten in place for moved boxes of the same size).
void record_boxes(const Grid& grid, const Particles& P, Shape shape,
                  std::vector<ShapeSupport>& support, BoxChanges& changes) {
  if (shape == Shape::Linear || shape == Shape::BSpline2) {
    detail::point_supports(grid, P, shape == Shape::BSpline2, support, changes);
  } else if (shape == Shape::GIMP) {
    detail::gimp_supports(grid, P, support, changes);
  } else {
    const bool bs = uses_bspline(shape);
    by_dim(grid.dim(), [&]<int D>() {
      const CellCoordinates<D> f(grid, P);
      detail::parallel_for(P.size(), [&](Index p) {
        changes.record(p, support[size_t(p)], corner_support<D>(grid, f, P, p, bs));
      });
    });
  }
}

// A new pattern of S and the G_a from the boxes: row offsets (an exclusive prefix sum of the box
// sizes) and the rows, each written to S and every G_a, both in parallel over blocks of
// particles (parallel.hpp). Returns false (with the count in `nnz`) when the nonzeros would
// exceed 32-bit indices.
bool build_pattern(const Grid& numbering, const std::vector<ShapeSupport>& support,
                   const BoxChanges::Rows& rows, Index n, int d, SparseRowMatrix& S,
                   std::array<SparseRowMatrix, 3>& G, Index& nnz) {
  const Index N = Index(support.size());
  auto entries = [&](Index p) {
    const ShapeSupport& s = support[size_t(p)];
    return Index(s.count[0]) * s.count[1] * s.count[2];
  };
  std::vector<Index> starts;
  detail::prefix_block_starts(N, starts, entries);
  nnz = starts.back();
  if (nnz > Index(std::numeric_limits<int>::max()))
    return false;
  set_pattern(S, N, n, nnz);
  std::array<int*, 4> outer{S.outerIndexPtr()}, inner{S.innerIndexPtr()};
  for (int a = 0; a < 3; ++a) {
    if (a >= d) {
      G[a].resize(0, 0);
      continue;
    }
    set_pattern(G[a], N, n, nnz);
    outer[size_t(a + 1)] = G[a].outerIndexPtr();
    inner[size_t(a + 1)] = G[a].innerIndexPtr();
  }
  for (int a = 0; a <= d; ++a)
    outer[size_t(a)][N] = int(nnz);
  by_dim(d, [&]<int D>() { // D + 1 arrays (S and the G_a) known at compile time
    detail::for_prefix_blocks(N, starts, [&](Index begin, Index end, Index start) {
      Index pos = start;
      for (Index p = begin; p < end; ++p) {
        int* row[D + 1];
        for (int a = 0; a <= D; ++a) {
          outer[size_t(a)][p] = int(pos);
          row[a] = inner[size_t(a)] + pos;
        }
        const ShapeSupport& s = support[size_t(p)];
        write_box_row<D + 1>(numbering, s, rows.first_column(p, s), row);
        pos += entries(p);
      }
    });
  });
  return true;
}

// Pass 2: the values of S and the G_a in their pattern.
void write_values(const Grid& grid, const Particles& P, Shape shape,
                  const std::vector<ShapeSupport>& support, SparseRowMatrix& S,
                  std::array<SparseRowMatrix, 3>& G) {
  const int d = grid.dim();
  double* sv = S.valuePtr();
  double* gv[3] = {G[0].valuePtr(), d > 1 ? G[1].valuePtr() : nullptr,
                   d > 2 ? G[2].valuePtr() : nullptr};
  const int* outer = S.outerIndexPtr();
  if (shape == Shape::Linear || shape == Shape::BSpline2)
    return detail::point_values(grid, P, shape == Shape::BSpline2, support, outer, sv, gv);
  if (shape == Shape::GIMP)
    return detail::gimp_values(grid, P, support, outer, sv, gv);
  const bool bs = uses_bspline(shape);
  by_dim(d, [&]<int D>() {
    const CellCoordinates<D> f(grid, P);
    auto rows = [&]<bool BS>() {
      detail::parallel_segments(P.size(), [&](Index p0, Index n) {
        thread_local std::vector<double> local; // corner_row's sums
        for (Index p = p0; p < p0 + n; ++p) {
          const int begin = outer[p];
          double* const g[3] = {gv[0] + begin, D > 1 ? gv[1] + begin : nullptr,
                                D > 2 ? gv[2] + begin : nullptr};
          corner_row<D, BS>(f, P, p, support[size_t(p)], sv + begin, g, local);
        }
      });
    };
    if (bs)
      rows.template operator()<true>();
    else
      rows.template operator()<false>();
  });
}

} // namespace

bool assemble_shape(const Grid& grid, const Particles& P, Shape shape, SparseRowMatrix& S,
                    std::array<SparseRowMatrix, 3>& G, std::vector<ShapeSupport>& support,
                    int fields, const int* field, Grid* window) {
  const Index N = P.size();
  SMPM_VERIFY(fields == 1 || field || N == 0,
              "assemble_shape: several fields need the particle fields");
  const int d = grid.dim();
  SMPM_VERIFY(P.dim == d, "assemble_shape: particles are " + std::to_string(P.dim) +
                              "D but the grid is " + std::to_string(d) + "D");
  // The nodes the columns number: the grid, or the window of the previous call (that of the
  // pattern kept), updated after the boxes are known.
  const bool same_grid = !window || (window->same_whole_grid(grid) && !grid.is_window());
  const Grid& numbering = window ? *window : grid;
  // The pattern is kept when no box changed; a box that moved and kept its size has its row
  // rewritten during pass 1; when a box changed size, the pattern is built anew.
  const bool fresh = !same_grid || Index(support.size()) != N ||
                     !matches(S, G, d, N, numbering.num_nodes() * fields);
  support.resize(N);
  BoxChanges changes;
  BoxChanges::Rows rows;
  rows.grid = &numbering;
  rows.nodes_per_field = numbering.num_nodes();
  rows.field = fields > 1 ? field : nullptr;
  if (!fresh) {
    rows.outer = S.outerIndexPtr();
    rows.inner[0] = S.innerIndexPtr();
    for (int a = 0; a < d; ++a)
      rows.inner[size_t(a + 1)] = G[size_t(a)].innerIndexPtr();
    rows.arrays = d + 1;
    changes.rows = &rows;
  }
  try {
    record_boxes(grid, P, shape, support, changes);
  } catch (...) {
    discard_pattern(support, S, G);
    throw;
  }
  BoxChange change = fresh ? BoxChange::Resized : changes.result();
  if (window && change != BoxChange::None) {
    const Grid next = particle_window(grid, support);
    if (fresh || next != *window) {
      *window = next; // a new numbering: the pattern is built anew
      change = BoxChange::Resized;
    }
  }
  rows.nodes_per_field = numbering.num_nodes();
  Index nnz = 0;
  if (change == BoxChange::Resized &&
      !build_pattern(numbering, support, rows, numbering.num_nodes() * fields, d, S, G, nnz)) {
    discard_pattern(support, S, G);
    throw NumericalError("S would hold " + std::to_string(nnz) +
                         " nonzeros, more than its 32-bit indices allow");
  }
  write_values(grid, P, shape, support, S, G);
  return change != BoxChange::None;
}

} // namespace smpm
