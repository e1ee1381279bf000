#pragma once
// Internal helpers of the shape-function assembly (shape.cpp, shape_points.cpp): the 1D grid
// functions and the fast path of the point-based families.

#include "sparsempm/shape.hpp"

#include <cmath>
#include <string_view>
#include <vector>

namespace smpm::detail {

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

// First node of the box of a point at ξ (cell units) and the box width for a point.
inline int first_node(double xi, bool bspline) {
  return bspline ? int(std::floor(xi + 0.5)) - 1 : int(std::floor(xi));
}
inline int point_count(bool bspline) {
  return bspline ? 3 : 2;
}

/// Throws NumericalError naming particle p, its position and `why`.
[[noreturn]] void throw_outside(Index p, const Particles& P, std::string_view why);

/// Node boxes of the point-based families (linear hat, quadratic B-spline when `bspline`) into
/// `support` (sized N); adds the entries to nnz and returns whether any box changed.
bool point_supports(const Grid& g, const Particles& P, bool bspline,
                    std::vector<ShapeSupport>& support, Index& nnz);
/// Values of S and ∂S/∂x_a of the point-based families written straight into the CSR arrays.
void point_values(const Grid& g, const Particles& P, bool bspline,
                  const std::vector<ShapeSupport>& support, const int* outer, double* sv,
                  double* const* gv);

} // namespace smpm::detail
