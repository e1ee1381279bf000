#include "sparsempm/shape.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/LU>
#include <algorithm>
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
  throw InputError("unknown shape function '" + std::string(name) +
                   "' (expected linear | gimp | cpdi | bspline2 | b2cpdi)");
}

namespace {

constexpr int kMaxBox = 12; // nodes per axis a particle may touch

// 1D grid functions of r = (x − x_i)/h, in cell units.
inline double hat(double r) {
  r = std::abs(r);
  return r < 1 ? 1 - r : 0;
}
// ∫_{−∞}^{r} hat: the antiderivative used by uGIMP.
inline double hat_integral(double r) {
  if (r <= -1)
    return 0;
  if (r <= 0)
    return 0.5 * (1 + r) * (1 + r);
  if (r < 1)
    return 1 - 0.5 * (1 - r) * (1 - r);
  return 1;
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

bool uses_bspline(Shape s) {
  return s == Shape::BSpline2 || s == Shape::B2CPDI;
}
bool uses_corners(Shape s) {
  return s == Shape::CPDI || s == Shape::B2CPDI;
}

// First node of the box of a point at ξ (cell units) and the box width for a point.
inline int first_node(double xi, bool bspline) {
  return bspline ? int(std::floor(xi + 0.5)) - 1 : int(std::floor(xi));
}
inline int point_count(bool bspline) {
  return bspline ? 3 : 2;
}

[[noreturn]] void throw_outside(Index p, const Particles& P, std::string_view why) {
  std::ostringstream os;
  os << "particle " << p << " at (";
  for (int a = 0; a < P.dim; ++a)
    os << (a ? ", " : "") << P.X(p, a);
  os << ") " << why;
  throw NumericalError(os.str());
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

// Values of S and ∂S/∂x_a on the box of one particle, written in box order (x fastest).
struct BoxValues {
  double S[kMaxBox * kMaxBox * kMaxBox];
  double G[3][kMaxBox * kMaxBox * kMaxBox];
};

void tensor_values(const Grid& g, const Particles& P, Index p, Shape shape, const ShapeSupport& s,
                   BoxValues& out) {
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
    for (int k = 0; k < s.count[a]; ++k) {
      const double r = xi - (s.first[a] + k);
      switch (shape) {
      case Shape::Linear: // two nodes; r ∈ [0, 1) for the left one, r − 1 for the right one
        s1[a][k] = k == 0 ? 1 - r : 1 + r;
        g1[a][k] = (k == 0 ? -1.0 : 1.0) / h;
        break;
      case Shape::BSpline2:
        s1[a][k] = bspline2(r);
        g1[a][k] = bspline2_slope(r) / h;
        break;
      default: { // GIMP: average of the hat over [ξ − l, ξ + l] (Buzzi Eqs. 17–18)
        const double l = P.half_length(p, a) / h;
        s1[a][k] = (hat_integral(r + l) - hat_integral(r - l)) / (2 * l);
        g1[a][k] = (hat(r + l) - hat(r - l)) / (2 * l * h);
      }
      }
    }
  }
  int q = 0;
  for (int k2 = 0; k2 < s.count[2]; ++k2)
    for (int k1 = 0; k1 < s.count[1]; ++k1)
      for (int k0 = 0; k0 < s.count[0]; ++k0, ++q) {
        const double w0 = s1[0][k0], w1 = s1[1][k1], w2 = s1[2][k2];
        out.S[q] = w0 * w1 * w2;
        out.G[0][q] = g1[0][k0] * w1 * w2;
        out.G[1][q] = w0 * g1[1][k1] * w2;
        out.G[2][q] = w0 * w1 * g1[2][k2];
      }
}

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

// ξ = (X_p − origin)/h along each axis, in cell units.
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

// Fast path for the point-based families (linear hat, quadratic B-spline): dimension and
// family known at compile time, values written straight into the CSR arrays.
template <int D, bool BS>
void point_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                    bool& changed, Index& nnz) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  for (Index p = 0; p < P.size(); ++p) {
    ShapeSupport s;
    for (int a = 0; a < D; ++a) {
      const double xi = xi_of(p, a);
      if (!std::isfinite(xi))
        throw_outside(p, P, "has a non-finite position or domain");
      const int first = first_node(xi, BS);
      if (first < 0 || first + width - 1 > g.cells(a))
        throw_outside(p, P,
                      "has left the grid (its shape-function support needs nodes outside it)");
      s.first[a] = first;
      s.count[a] = width;
    }
    if (!(s == support[size_t(p)])) { // write only what changed: the pattern is usually kept
      changed = true;
      support[size_t(p)] = s;
    }
    nnz += BS ? (D == 1 ? 3 : D == 2 ? 9 : 27) : (1 << D);
  }
}

template <int D, bool BS>
void point_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                  const int* outer, double* sv, double* const* gv) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  for (Index p = 0; p < P.size(); ++p) {
    const ShapeSupport& s = support[size_t(p)];
    double w[3][width], dw[3][width];
    for (int a = 0; a < 3; ++a) {
      if (a >= D) {
        w[a][0] = 1;
        dw[a][0] = 0;
        continue;
      }
      const double r0 = xi_of(p, a) - s.first[a];
      for (int k = 0; k < width; ++k) {
        const double r = r0 - k;
        if constexpr (BS) {
          w[a][k] = bspline2(r);
          dw[a][k] = bspline2_slope(r) * xi_of.inv_h[a];
        } else {
          w[a][k] = k == 0 ? 1 - r : 1 + r;
          dw[a][k] = (k == 0 ? -1.0 : 1.0) * xi_of.inv_h[a];
        }
      }
    }
    int q = outer[p];
    for (int k2 = 0; k2 < (D > 2 ? width : 1); ++k2)
      for (int k1 = 0; k1 < (D > 1 ? width : 1); ++k1)
        for (int k0 = 0; k0 < width; ++k0, ++q) {
          const double w0 = w[0][k0], w1 = w[1][k1], w2 = w[2][k2];
          sv[q] = w0 * w1 * w2;
          gv[0][q] = dw[0][k0] * w1 * w2;
          if constexpr (D > 1)
            gv[1][q] = w0 * dw[1][k1] * w2;
          if constexpr (D > 2)
            gv[2][q] = w0 * w1 * dw[2][k2];
        }
  }
}

template <bool BS>
void dispatch_point(int d, auto&& f) {
  switch (d) {
  case 1:
    f.template operator()<1, BS>();
    break;
  case 2:
    f.template operator()<2, BS>();
    break;
  default:
    f.template operator()<3, BS>();
    break;
  }
}

void set_pattern(SparseRowMatrix& A, Index N, Index n, Index nnz) {
  if (A.rows() != N || A.cols() != n)
    A.resize(N, n);
  A.resizeNonZeros(nnz);
}

} // namespace

bool assemble_shape(const Grid& grid, const Particles& P, Shape shape, SparseRowMatrix& S,
                    std::array<SparseRowMatrix, 3>& G, std::vector<ShapeSupport>& support) {
  const Index N = P.size(), n = grid.num_nodes();
  const int d = grid.dim();
  if (P.dim != d)
    throw InputError("particles are " + std::to_string(P.dim) + "D but the grid is " +
                     std::to_string(d) + "D");
  // Pass 1: the node box of every particle; the pattern is kept if no box changed.
  bool changed = Index(support.size()) != N || S.rows() != N || S.cols() != n;
  support.resize(N);
  Index nnz = 0;
  const bool point = shape == Shape::Linear || shape == Shape::BSpline2;
  if (point) {
    auto f = [&]<int D, bool BS>() { point_supports<D, BS>(grid, P, support, changed, nnz); };
    if (shape == Shape::BSpline2)
      dispatch_point<true>(d, f);
    else
      dispatch_point<false>(d, f);
  } else {
    for (Index p = 0; p < N; ++p) {
      const ShapeSupport s = support_of(grid, P, p, shape);
      changed = changed || !(s == support[p]);
      support[p] = s;
      nnz += Index(s.count[0]) * s.count[1] * s.count[2];
    }
  }
  if (nnz > Index(std::numeric_limits<int>::max()))
    throw NumericalError("S would hold " + std::to_string(nnz) +
                         " nonzeros, more than its 32-bit indices allow");
  if (changed) {
    set_pattern(S, N, n, nnz);
    int* outer = S.outerIndexPtr();
    int* inner = S.innerIndexPtr();
    Index pos = 0;
    for (Index p = 0; p < N; ++p) {
      outer[p] = int(pos);
      const ShapeSupport& s = support[p];
      for (int k2 = 0; k2 < s.count[2]; ++k2)
        for (int k1 = 0; k1 < s.count[1]; ++k1)
          for (int k0 = 0; k0 < s.count[0]; ++k0)
            inner[pos++] = int(grid.node_index(s.first[0] + k0, s.first[1] + k1, s.first[2] + k2));
    }
    outer[N] = int(pos);
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
    auto f = [&]<int D, bool BS>() { point_values<D, BS>(grid, P, support, outer, sv, gv); };
    if (shape == Shape::BSpline2)
      dispatch_point<true>(d, f);
    else
      dispatch_point<false>(d, f);
    return changed;
  }
  BoxValues box;
  for (Index p = 0; p < N; ++p) {
    const ShapeSupport& s = support[p];
    if (uses_corners(shape))
      corner_values(grid, P, p, shape, s, box);
    else
      tensor_values(grid, P, p, shape, s, box);
    const int begin = outer[p], len = outer[p + 1] - begin;
    std::copy(box.S, box.S + len, sv + begin);
    for (int a = 0; a < d; ++a)
      std::copy(box.G[a], box.G[a] + len, gv[a] + begin);
  }
  return changed;
}

} // namespace smpm
