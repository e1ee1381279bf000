#include "sparsempm/boundary.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <string>

namespace smpm {

BoundaryConditions BoundaryConditions::none(const Grid& grid) {
  BoundaryConditions bc;
  bc.free.setOnes(grid.num_nodes(), grid.dim());
  return bc;
}

namespace {
template <class Select>
Index fix_where(const Grid& grid, const std::array<bool, 3>& dirs, BoundaryConditions& bc,
                Select&& selected) {
  if (bc.free.rows() != grid.num_nodes() || bc.free.cols() != grid.dim())
    bc = BoundaryConditions::none(grid);
  Index count = 0;
  for (Index i = 0; i < grid.num_nodes(); ++i) {
    if (!selected(i))
      continue;
    ++count;
    for (int a = 0; a < grid.dim(); ++a)
      if (dirs[a])
        bc.free(i, a) = 0.0;
  }
  return count;
}
} // namespace

Index fix_plane(const Grid& grid, int axis, double at, const std::array<bool, 3>& dirs,
                BoundaryConditions& bc) {
  if (axis < 0 || axis >= grid.dim())
    throw InputError("boundary plane axis " + std::to_string(axis) + " is not an axis of a " +
                     std::to_string(grid.dim()) + "D grid");
  const double tol = 1e-9 * grid.cell_size(axis);
  const Index count = fix_where(
      grid, dirs, bc, [&](Index i) { return std::abs(grid.node_coordinate(i, axis) - at) <= tol; });
  if (count == 0)
    throw InputError("boundary plane at " + std::to_string(at) + " on axis " +
                     std::to_string(axis) + " contains no grid node");
  return count;
}

Index fix_box(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
              const std::array<bool, 3>& dirs, BoundaryConditions& bc) {
  const Index count = fix_where(grid, dirs, bc, [&](Index i) {
    for (int a = 0; a < grid.dim(); ++a) {
      const double x = grid.node_coordinate(i, a), tol = 1e-9 * grid.cell_size(a);
      if (x < lo[a] - tol || x > hi[a] + tol)
        return false;
    }
    return true;
  });
  if (count == 0)
    throw InputError("boundary box contains no grid node");
  return count;
}

} // namespace smpm
