// SPDX-License-Identifier: BSD-3-Clause
// The geometry of one contact node (contact_geometry.hpp, NodeGeometry): the normal from side A to
// side B (specified, AG, LR, a rigid body's outward normal) and their separation (CP, DF, LR);
// contact 2020 §3.1–3.3.

#include "contact_geometry.hpp"

#include "contact_detail.hpp"
#include "contact_lr.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace smpm::detail {

double cell_width_along(const Grid& grid, const Eigen::Vector3d& n) {
  double h2 = 0;
  for (int a = 0; a < grid.dim(); ++a)
    h2 += n[a] * n[a] * grid.cell_size(a) * grid.cell_size(a);
  return std::sqrt(h2);
}

Eigen::Vector3d NodeGeometry::side_b(const Field& x, int a, int b) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < ops.fields; ++f)
    if (in_b(f, a, b))
      sum += row3(x, f * ops.grid_node_count + node);
  return sum;
}

double NodeGeometry::mass_b(int a, int b) const {
  double m = 0;
  for (int f = 0; f < ops.fields; ++f)
    if (in_b(f, a, b))
      m += ops.m[f * ops.grid_node_count + node];
  return m;
}

double NodeGeometry::cls(Index k, int a, int b) const {
  const int f = cn.cloud[size_t(k)].second;
  return f == a ? -1.0 : (in_b(f, a, b) ? 1.0 : 0.0);
}

Eigen::Vector3d NodeGeometry::relative(Index k) const {
  const int p = cn.cloud[size_t(k)].first;
  Eigen::Vector3d x = -grid.node_position(node);
  for (int c = 0; c < ops.dim; ++c)
    x[c] += P.X(p, c);
  return x;
}

Eigen::Vector3d NodeGeometry::rigid_outward(int r) const {
  const Index ng = ops.grid_node_count;
  const std::array<int, 3> ijk = grid.node_ijk(node);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const int span[3] = {1, grid.dim() > 1 ? 1 : 0, grid.dim() > 2 ? 1 : 0};
  for (int dk = -span[2]; dk <= span[2]; ++dk)
    for (int dj = -span[1]; dj <= span[1]; ++dj)
      for (int di = -span[0]; di <= span[0]; ++di) {
        const int q[3] = {ijk[0] + di, ijk[1] + dj, ijk[2] + dk};
        bool inside = true;
        for (int a = 0; a < grid.dim(); ++a)
          inside =
              inside && q[a] >= grid.first_node(a) && q[a] < grid.first_node(a) + grid.nodes(a);
        if (!inside)
          continue;
        const Index j = grid.node_index(q[0], q[1], q[2]), row = r * ng + j;
        const int k = cn.fixed.empty() ? -1 : cn.fixed[size_t(j)];
        sum += ops.m[row] * (k < 0 ? row3(cn.gradient, row)
                                   : Eigen::Vector3d(cn.free[size_t(k)] * row3(cn.gradient, row)));
      }
  return unit_or_zero(sum);
}

Eigen::Vector3d NodeGeometry::normal(const ContactPair& pair, int a, int b) const {
  const Index ng = ops.grid_node_count;
  if (pair.normal != ContactNormal::Specified && b >= 0 && rigid(a) != rigid(b))
    return rigid(a) ? rigid_outward(a) : Eigen::Vector3d(-rigid_outward(b));
  switch (pair.normal) {
  case ContactNormal::Specified:
    return pair.first == a ? pair.direction : Eigen::Vector3d(-pair.direction);
  case ContactNormal::AverageGradient:
    return unit_or_zero(row3(cn.gradient, a * ng + node) - side_b(cn.gradient, a, b));
  case ContactNormal::LogisticRegression: {
    const Index first = cn.cloud_offset[size_t(cloud)];
    const Index count = cn.cloud_offset[size_t(cloud) + 1] - first;
    return detail::logistic_fit(
               ops.dim, count, [&](Index k) { return relative(first + k); },
               [&](Index k) { return cls(first + k, a, b); }, grid.min_cell_size())
        .normal;
  }
  }
  return Eigen::Vector3d::Zero();
}

double NodeGeometry::separation(const ContactPair& pair, int a, int b,
                                const Eigen::Vector3d& n) const {
  const Index ng = ops.grid_node_count;
  if (pair.detection == ContactDetection::Position ||
      pair.detection == ContactDetection::DistanceFunction) {
    const Eigen::Vector3d xa = row3(cn.position, a * ng + node) / ops.m[a * ng + node];
    const Eigen::Vector3d xb = side_b(cn.position, a, b) / mass_b(a, b);
    const double h = cell_width_along(grid, n);
    if (pair.detection == ContactDetection::Position)
      return (xb - xa).dot(n) - pair.critical_separation * h;
    if (!(h > 0))
      return 1; // no normal: no separation along it
    const Eigen::Vector3d xi = grid.node_position(node);
    const double sa = (xa - xi).dot(n) / h, sb = (xb - xi).dot(n) / h;
    return -h * (distance_function_edge(-sb, pair.df_exponent, pair.df_reach) +
                 distance_function_edge(sa, pair.df_exponent, pair.df_reach));
  }
  if (pair.detection != ContactDetection::LogisticRegression)
    return -1;
  double max_a = -std::numeric_limits<double>::infinity();
  double min_b = std::numeric_limits<double>::infinity();
  const int d = ops.dim;
  for (Index k = cn.cloud_offset[size_t(cloud)]; k < cn.cloud_offset[size_t(cloud) + 1]; ++k) {
    const double c = cls(k, a, b);
    if (c == 0)
      continue;
    const int p = cn.cloud[size_t(k)].first;
    const double s = relative(k).dot(n);
    const double r =
        particle_radius_along(d, P.F.data() + p * P.F.outerStride(),
                              P.half_length.data() + p * P.half_length.outerStride(), n);
    if (c < 0)
      max_a = std::max(max_a, s + r);
    else
      min_b = std::min(min_b, s - r);
  }
  return min_b - max_a; // +inf if a side has no particle here: not touching
}

} // namespace smpm::detail
