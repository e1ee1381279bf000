// The fast path of the point-based shape families (linear hat, quadratic B-spline): dimension
// and family known at compile time, values written straight into the CSR arrays.

#include "parallel.hpp"
#include "shape_functions.hpp"

#include "sparsempm/errors.hpp"

#include <atomic>
#include <sstream>

namespace smpm::detail {

void throw_outside(Index p, const Particles& P, std::string_view why) {
  std::ostringstream os;
  os << "particle " << p << " at (";
  for (int a = 0; a < P.dim; ++a)
    os << (a ? ", " : "") << P.X(p, a);
  os << ") " << why;
  throw NumericalError(os.str());
}

namespace {

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

template <int D, bool BS>
void point_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                    bool& changed, Index& nnz) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  std::atomic<bool> moved{false};
  parallel_for(P.size(), [&](Index p) {
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
      moved.store(true, std::memory_order_relaxed);
      support[size_t(p)] = s;
    }
  });
  changed = moved.load() || changed;
  nnz += P.size() * (BS ? (D == 1 ? 3 : D == 2 ? 9 : 27) : (1 << D));
}

template <int D, bool BS>
void point_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                  const int* outer, double* sv, double* const* gv) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  parallel_for(P.size(), [&](Index p) {
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
  });
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

} // namespace

bool point_supports(const Grid& g, const Particles& P, bool bspline,
                    std::vector<ShapeSupport>& support, Index& nnz) {
  bool changed = false;
  auto f = [&]<int D, bool BS>() { point_supports<D, BS>(g, P, support, changed, nnz); };
  if (bspline)
    dispatch_point<true>(P.dim, f);
  else
    dispatch_point<false>(P.dim, f);
  return changed;
}

void point_values(const Grid& g, const Particles& P, bool bspline,
                  const std::vector<ShapeSupport>& support, const int* outer, double* sv,
                  double* const* gv) {
  auto f = [&]<int D, bool BS>() { point_values<D, BS>(g, P, support, outer, sv, gv); };
  if (bspline)
    dispatch_point<true>(P.dim, f);
  else
    dispatch_point<false>(P.dim, f);
}

} // namespace smpm::detail
