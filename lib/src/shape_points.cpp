// SPDX-License-Identifier: BSD-3-Clause
// The fast paths of the tensor-product shape families (linear hat, quadratic B-spline, uGIMP):
// dimension and family known at compile time, values written straight into the CSR arrays.

#include "kernels.hpp"
#include "parallel.hpp"
#include "shape_functions.hpp"

#include "sparsempm/errors.hpp"

#include <array>
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

// A row of S and G from the 1D weights w[a][k] and slopes dw[a][k] along each axis: their
// tensor product over the box of count[0] × count[1] × count[2] nodes, x fastest, written at
// position q of sv and of each gv[a] (the axes beyond D are not read).
// Box sizes C0, C1, C2 are compile-time constants when nonzero.
template <int D, int W, int C0 = 0, int C1 = 0, int C2 = 0>
inline void tensor_row(const std::array<int, 3>& count, const double (&w)[3][W],
                       const double (&dw)[3][W], double* sv, double* const* gv, int q) {
  const int c0 = C0 ? C0 : count[0], c1 = D > 1 ? (C1 ? C1 : count[1]) : 1,
            c2 = D > 2 ? (C2 ? C2 : count[2]) : 1;
  for (int k2 = 0; k2 < c2; ++k2)
    for (int k1 = 0; k1 < c1; ++k1)
      for (int k0 = 0; k0 < c0; ++k0, ++q) {
        const double w0 = w[0][k0];
        if constexpr (D == 1) {
          sv[q] = w0;
          gv[0][q] = dw[0][k0];
        } else if constexpr (D == 2) {
          const double w1 = w[1][k1];
          sv[q] = w0 * w1;
          gv[0][q] = dw[0][k0] * w1;
          gv[1][q] = w0 * dw[1][k1];
        } else {
          const double w1 = w[1][k1], w2 = w[2][k2];
          sv[q] = w0 * w1 * w2;
          gv[0][q] = dw[0][k0] * w1 * w2;
          gv[1][q] = w0 * dw[1][k1] * w2;
          gv[2][q] = w0 * w1 * dw[2][k2];
        }
      }
}

template <int D, bool BS>
void point_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                    BoxChanges& changes) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  parallel_for(P.size(), [&](Index p) {
    ShapeSupport s;
    for (int a = 0; a < D; ++a) {
      const double xi = xi_of(p, a);
      if (!std::isfinite(xi))
        throw_outside(p, P, "has a non-finite position or domain");
      const int first = xi > -kFarCells && xi < kFarCells ? first_node(xi, BS) : -1;
      if (first < 0 || first + width - 1 > g.cells(a))
        throw_outside(p, P,
                      "has left the grid (its shape-function support needs nodes outside it)");
      s.first[a] = first;
      s.count[a] = width;
    }
    changes.record(p, support[size_t(p)], s);
  });
}

template <int D, bool BS>
void point_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                  const int* outer, double* sv, double* const* gv) {
  constexpr int width = BS ? 3 : 2;
  const CellCoordinates<D> xi_of(g, P);
  parallel_for(P.size(), [&](Index p) {
    const ShapeSupport& s = support[size_t(p)];
    double w[3][width], dw[3][width];
    for (int a = 0; a < D; ++a) {
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
    tensor_row<D, width>({width, width, width}, w, dw, sv, gv, outer[p]);
  });
}

// uGIMP: the box of [ξ − l, ξ + l] under the hat along each axis, l = r⁰/h.
template <int D>
void gimp_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                   BoxChanges& changes) {
  parallel_segments(P.size(), [&](Index p0, Index n) {
    const CellCoordinates<D> xi_of(g, P); // in the range's locals
    const double* L = P.half_length.data();
    ShapeSupport* boxes = support.data();
    for (Index p = p0; p < p0 + n; ++p) {
      ShapeSupport s;
      for (int a = 0; a < D; ++a) {
        const double xi = xi_of(p, a), l = L[p * D + a] * xi_of.inv_h[a];
        if (!(l > 0)) // the average over the domain divides by its length
          throw_outside(p, P, "has a uGIMP domain without length (half-length <= 0)");
        interval_box(g, P, p, a, xi - l, xi + l, 1.0, s.first[size_t(a)], s.count[size_t(a)]);
      }
      changes.record(p, boxes[p], s);
    }
  });
}

// uGIMP weights along one axis: the average of the hat over the particle's domain,
// S_i = (H(r + l) − H(r − l))/(2l) with H = ∫ hat and r = ξ − i, and its slope
// (hat(r + l) − hat(r − l))/(2lh) (Buzzi Eqs. 17–18), for the `count` nodes of the box from its
// first node; r0 = ξ − first, l = r⁰/h (cell units). A hat is linear within a cell, so its average
// over the part of the domain in one cell is its value at that part's centre:
// - two nodes, the domain within one cell: the hats at the centre, w = (1 − r0, r0), and the
//   slopes (−1, 1)/h (linear interpolation);
// - three nodes, the domain across node 1 with a = 1 − (r0 − l) of it to the left and
//   b = r0 + l − 1 to the right: w0 = a²/(4l), w2 = b²/(4l), w1 = 1 − w0 − w2 (the hats sum to
//   1), slopes (−a, a − b, b)/(2lh);
// - any other box, the integrals node by node.
// The closed forms agree with the integrals to round-off (tests/lib/test_shape.cpp); the box's
// 10⁻¹² cell tolerance (interval_box) leaves out a part of the domain shorter than that.
inline void gimp_axis(int count, double r0, double l, double inv_h, double* w, double* dw) {
  const double inv_2l = 0.5 / l, slope = inv_2l * inv_h;
  if (count == 2) {
    w[0] = 1 - r0;
    w[1] = r0;
    dw[0] = -inv_h;
    dw[1] = inv_h;
  } else if (count == 3) {
    const double a = 1 - (r0 - l), b = (r0 + l) - 1;
    w[0] = 0.5 * a * a * inv_2l;
    w[2] = 0.5 * b * b * inv_2l;
    w[1] = 1 - w[0] - w[2];
    dw[0] = -a * slope;
    dw[1] = (a - b) * slope;
    dw[2] = b * slope;
  } else {
    for (int k = 0; k < count; ++k) {
      const double r = r0 - k;
      w[k] = (hat_integral(r + l) - hat_integral(r - l)) * inv_2l;
      dw[k] = (hat(r + l) - hat(r - l)) * slope;
    }
  }
}

template <int D>
void gimp_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                 const int* outer, double* sv, double* const* gv) {
  parallel_segments(P.size(), [&](Index p0, Index n) {
    const CellCoordinates<D> xi_of(g, P); // in the range's locals
    const double* L = P.half_length.data();
    const ShapeSupport* boxes = support.data();
    double* const g_v[3] = {gv[0], D > 1 ? gv[1] : nullptr, D > 2 ? gv[2] : nullptr};
    for (Index p = p0; p < p0 + n; ++p) {
      const ShapeSupport& s = boxes[p];
      double w[3][kMaxBox], dw[3][kMaxBox];
      for (int a = 0; a < D; ++a)
        gimp_axis(s.count[size_t(a)], xi_of(p, a) - s.first[size_t(a)],
                  L[p * D + a] * xi_of.inv_h[a], xi_of.inv_h[a], w[a], dw[a]);
      dispatch_box(s.count, [&]<int C0, int C1, int C2>() {
        tensor_row<D, kMaxBox, C0, C1, C2>(s.count, w, dw, sv, g_v, outer[p]);
      });
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

void point_supports(const Grid& g, const Particles& P, bool bspline,
                    std::vector<ShapeSupport>& support, BoxChanges& changes) {
  auto f = [&]<int D, bool BS>() { point_supports<D, BS>(g, P, support, changes); };
  if (bspline)
    dispatch_point<true>(P.dim, f);
  else
    dispatch_point<false>(P.dim, f);
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

void gimp_supports(const Grid& g, const Particles& P, std::vector<ShapeSupport>& support,
                   BoxChanges& changes) {
  by_dim(P.dim, [&]<int D>() { gimp_supports<D>(g, P, support, changes); });
}

void gimp_values(const Grid& g, const Particles& P, const std::vector<ShapeSupport>& support,
                 const int* outer, double* sv, double* const* gv) {
  by_dim(P.dim, [&]<int D>() { gimp_values<D>(g, P, support, outer, sv, gv); });
}

} // namespace smpm::detail
