#include "sparsempm/shape.hpp"

#include "parallel.hpp"
#include "shape_functions.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

namespace smpm {

std::string_view to_string(Shape s) {
  switch (s) {
  case Shape::Linear:
    return "linear";
  case Shape::GIMP:
    return "gimp";
  case Shape::BSpline2:
    return "bspline2";
  case Shape::CPDI:
    return "cpdi";
  case Shape::B2CPDI:
    return "b2cpdi";
  }
  return "?";
}

Shape shape_from_string(std::string_view name) {
  for (Shape s : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI})
    if (to_string(s) == name)
      return s;
  throw InputError("unknown shape function \'" + clip(name) +
                   "' (expected linear | gimp | cpdi | bspline2 | b2cpdi)");
}

namespace {

using namespace detail;

constexpr int kMaxBox = 12; // nodes per axis a particle may touch

bool uses_bspline(Shape s) {
  return s == Shape::BSpline2 || s == Shape::B2CPDI;
}
bool uses_corners(Shape s) {
  return s == Shape::CPDI || s == Shape::B2CPDI;
}

// Corner positions in cell units, xi_c[c][a], for the 2^d corners of the CPDI domain.
void corners(const Grid& g, const Particles& P, Index p, double xi_c[8][3]) {
  const int d = P.dim;
  for (int c = 0; c < (1 << d); ++c)
    for (int a = 0; a < d; ++a) {
      double x = P.X(p, a);
      for (int b = 0; b < d; ++b) {
        const double s = (c >> b) & 1 ? 1.0 : -1.0;
        x += P.F(p, a * d + b) * s * P.half_length(p, b);
      }
      xi_c[c][a] = (x - g.origin(a)) / g.cell_size(a);
    }
}

ShapeSupport support_of(const Grid& g, const Particles& P, Index p, Shape shape) {
  const int d = P.dim;
  const bool bs = uses_bspline(shape);
  ShapeSupport s;
  double lo[3], hi[3];
  if (uses_corners(shape)) {
    double xi_c[8][3];
    corners(g, P, p, xi_c);
    for (int a = 0; a < d; ++a) {
      lo[a] = hi[a] = xi_c[0][a];
      for (int c = 1; c < (1 << d); ++c) {
        lo[a] = std::min(lo[a], xi_c[c][a]);
        hi[a] = std::max(hi[a], xi_c[c][a]);
      }
    }
  } else {
    for (int a = 0; a < d; ++a) {
      const double xi = (P.X(p, a) - g.origin(a)) / g.cell_size(a);
      const double l = shape == Shape::GIMP ? P.half_length(p, a) / g.cell_size(a) : 0.0;
      lo[a] = xi - l;
      hi[a] = xi + l;
    }
  }
  for (int a = 0; a < d; ++a) {
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
      throw_outside(p, P, "has a non-finite position or domain");
    // Only nodes with non-zero weight: |ξ − i| < R over [lo, hi] (R = 1 hat, 1.5 B-spline),
    // with a 10⁻¹² cell tolerance so that round-off does not reach a node of zero weight.
    const double R = bs ? 1.5 : 1.0, eps = 1e-12;
    const int first = int(std::floor(lo[a] - R + eps)) + 1;
    const int last = int(std::ceil(hi[a] + R - eps)) - 1;
    if (first < 0 || last > g.cells(a))
      throw_outside(p, P, "has left the grid (its shape-function support needs nodes outside it)");
    if (last - first + 1 > kMaxBox)
      throw_outside(p, P, "has a domain spanning more than 11 cells");
    s.first[a] = first;
    s.count[a] = last - first + 1;
  }
  return s;
}

// uGIMP (the tensor-product shape without a fast point path): the 1D weights and slopes of each
// axis, their products written straight into the particle's row of S and G (box order, x
// fastest).
void tensor_row(const Grid& g, const Particles& P, Index p, const ShapeSupport& s, double* S,
                double* const G[3]) {
  const int d = P.dim;
  double s1[3][kMaxBox], g1[3][kMaxBox];
  for (int a = 0; a < 3; ++a) {
    if (a >= d) {
      s1[a][0] = 1;
      g1[a][0] = 0;
      continue;
    }
    const double h = g.cell_size(a);
    const double xi = (P.X(p, a) - g.origin(a)) / h;
    const double l = P.half_length(p, a) / h;
    for (int k = 0; k < s.count[a]; ++k) {
      // The average of the hat over [ξ − l, ξ + l] (Buzzi Eqs. 17–18).
      const double r = xi - (s.first[a] + k);
      s1[a][k] = (hat_integral(r + l) - hat_integral(r - l)) / (2 * l);
      g1[a][k] = (hat(r + l) - hat(r - l)) / (2 * l * h);
    }
  }
  int q = 0;
  for (int k2 = 0; k2 < s.count[2]; ++k2)
    for (int k1 = 0; k1 < s.count[1]; ++k1)
      for (int k0 = 0; k0 < s.count[0]; ++k0, ++q) {
        const double w0 = s1[0][k0], w1 = s1[1][k1], w2 = s1[2][k2];
        S[q] = w0 * w1 * w2;
        G[0][q] = g1[0][k0] * w1 * w2;
        if (d > 1)
          G[1][q] = w0 * g1[1][k1] * w2;
        if (d > 2)
          G[2][q] = w0 * w1 * g1[2][k2];
      }
}

// Values of S and ∂S/∂x_a on the box of one particle, written in box order (x fastest).
struct BoxValues {
  double S[kMaxBox * kMaxBox * kMaxBox];
  double G[3][kMaxBox * kMaxBox * kMaxBox];
};

void corner_values(const Grid& g, const Particles& P, Index p, Shape shape, const ShapeSupport& s,
                   BoxValues& out) {
  const int d = P.dim, nc = 1 << d;
  const bool bs = uses_bspline(shape);
  double xi_c[8][3];
  corners(g, P, p, xi_c);
  // n1[c][a][k] = N(ξ_c,a − node) on each axis of the box.
  double n1[8][3][kMaxBox];
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < s.count[a]; ++k) {
        if (a >= d) {
          n1[c][a][k] = 1;
          continue;
        }
        const double r = xi_c[c][a] - (s.first[a] + k);
        n1[c][a][k] = bs ? bspline2(r) : hat(r);
      }
  // gc[c] = 2^{-d} R^{-T} s_c with R = F diag(r⁰): the volume average of ∇Q_c.
  Eigen::Matrix3d Fp = Eigen::Matrix3d::Identity();
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b)
      Fp(a, b) = P.F(p, a * d + b);
  const Eigen::Matrix3d Finv_t = Fp.inverse().transpose();
  const double w = 1.0 / nc;
  double gc[8][3];
  for (int c = 0; c < nc; ++c) {
    Eigen::Vector3d sr = Eigen::Vector3d::Zero();
    for (int b = 0; b < d; ++b)
      sr[b] = ((c >> b) & 1 ? 1.0 : -1.0) / P.half_length(p, b);
    const Eigen::Vector3d gv = w * Finv_t * sr;
    for (int a = 0; a < 3; ++a)
      gc[c][a] = gv[a];
  }
  int q = 0;
  for (int k2 = 0; k2 < s.count[2]; ++k2)
    for (int k1 = 0; k1 < s.count[1]; ++k1)
      for (int k0 = 0; k0 < s.count[0]; ++k0, ++q) {
        double Sv = 0, G0 = 0, G1 = 0, G2 = 0;
        for (int c = 0; c < nc; ++c) {
          const double Nc = n1[c][0][k0] * n1[c][1][k1] * n1[c][2][k2];
          Sv += Nc;
          G0 += Nc * gc[c][0];
          G1 += Nc * gc[c][1];
          G2 += Nc * gc[c][2];
        }
        out.S[q] = w * Sv;
        out.G[0][q] = G0;
        out.G[1][q] = G1;
        out.G[2][q] = G2;
      }
}

void set_pattern(SparseRowMatrix& A, Index N, Index n, Index nnz) {
  if (A.rows() != N || A.cols() != n)
    A.resize(N, n);
  A.resizeNonZeros(nnz);
}

} // namespace

bool assemble_shape(const Grid& grid, const Particles& P, Shape shape, SparseRowMatrix& S,
                    std::array<SparseRowMatrix, 3>& G, std::vector<ShapeSupport>& support,
                    int fields, const int* field) {
  const Index N = P.size(), ng = grid.num_nodes(), n = ng * fields;
  SMPM_VERIFY(fields == 1 || field, "assemble_shape: several fields need the particle fields");
  const int d = grid.dim();
  SMPM_VERIFY(P.dim == d, "assemble_shape: particles are " + std::to_string(P.dim) +
                              "D but the grid is " + std::to_string(d) + "D");
  // Pass 1: the node box of every particle; the pattern is kept if no box changed.
  bool changed = Index(support.size()) != N || S.rows() != N || S.cols() != n;
  support.resize(N);
  Index nnz = 0;
  const bool point = shape == Shape::Linear || shape == Shape::BSpline2;
  if (point) {
    changed = detail::point_supports(grid, P, shape == Shape::BSpline2, support, nnz) || changed;
  } else {
    std::atomic<bool> moved{false};
    detail::parallel_for(N, [&](Index p) {
      const ShapeSupport s = support_of(grid, P, p, shape);
      if (!(s == support[size_t(p)])) {
        support[size_t(p)] = s;
        moved.store(true, std::memory_order_relaxed);
      }
    });
    changed = moved.load() || changed;
    for (const ShapeSupport& s : support)
      nnz += Index(s.count[0]) * s.count[1] * s.count[2];
  }
  if (nnz > Index(std::numeric_limits<int>::max()))
    throw NumericalError("S would hold " + std::to_string(nnz) +
                         " nonzeros, more than its 32-bit indices allow");
  if (changed) {
    set_pattern(S, N, n, nnz);
    // Row offsets (an exclusive prefix sum of the box sizes), then the rows in parallel.
    int* outer = S.outerIndexPtr();
    int* inner = S.innerIndexPtr();
    Index pos = 0;
    for (Index p = 0; p < N; ++p) {
      outer[p] = int(pos);
      const ShapeSupport& s = support[size_t(p)];
      pos += Index(s.count[0]) * s.count[1] * s.count[2];
    }
    outer[N] = int(pos);
    detail::parallel_for(N, [&](Index p) {
      const ShapeSupport& s = support[size_t(p)];
      const Index block = fields > 1 ? Index(field[p]) * ng : 0; // node i of field α: α n_g + i
      int* row = inner + outer[p];
      for (int k2 = 0; k2 < s.count[2]; ++k2)
        for (int k1 = 0; k1 < s.count[1]; ++k1)
          for (int k0 = 0; k0 < s.count[0]; ++k0)
            *row++ =
                int(block + grid.node_index(s.first[0] + k0, s.first[1] + k1, s.first[2] + k2));
    });
    for (int a = 0; a < 3; ++a) {
      if (a >= d) {
        G[a].resize(0, 0);
        continue;
      }
      set_pattern(G[a], N, n, nnz);
      std::copy(outer, outer + N + 1, G[a].outerIndexPtr());
      std::copy(inner, inner + nnz, G[a].innerIndexPtr());
    }
  }
  // Pass 2: values.
  double* sv = S.valuePtr();
  double* gv[3] = {G[0].valuePtr(), d > 1 ? G[1].valuePtr() : nullptr,
                   d > 2 ? G[2].valuePtr() : nullptr};
  const int* outer = S.outerIndexPtr();
  if (point) {
    detail::point_values(grid, P, shape == Shape::BSpline2, support, outer, sv, gv);
    return changed;
  }
  if (!uses_corners(shape)) { // uGIMP
    detail::parallel_for(N, [&](Index p) {
      const int begin = outer[p];
      double* const g[3] = {gv[0] + begin, d > 1 ? gv[1] + begin : nullptr,
                            d > 2 ? gv[2] + begin : nullptr};
      tensor_row(grid, P, p, support[size_t(p)], sv + begin, g);
    });
    return changed;
  }
  detail::parallel_for(N, [&](Index p) {
    BoxValues box; // on the stack of the thread
    corner_values(grid, P, p, shape, support[size_t(p)], box);
    const int begin = outer[p], len = outer[p + 1] - begin;
    for (int j = 0; j < len; ++j) {
      sv[begin + j] = box.S[j];
      for (int a = 0; a < d; ++a)
        gv[a][begin + j] = box.G[a][j];
    }
  });
  return changed;
}

} // namespace smpm
