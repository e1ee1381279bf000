#include "sparsempm/grid.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <string>

namespace smpm {

Grid::Grid(int dim, const std::array<double, 3>& origin, const std::array<double, 3>& cell_size,
           const std::array<int, 3>& cells)
    : dim_(dim), origin_{0, 0, 0}, h_{1, 1, 1}, cells_{0, 0, 0} {
  if (dim < 1 || dim > 3)
    throw InputError("grid dimension must be 1, 2 or 3, got " + std::to_string(dim));
  for (int a = 0; a < dim; ++a) {
    if (!(cell_size[a] > 0) || !std::isfinite(cell_size[a]))
      throw InputError("grid cell_size[" + std::to_string(a) + "] must be positive, got " +
                       std::to_string(cell_size[a]));
    if (cells[a] < 1)
      throw InputError("grid cells[" + std::to_string(a) + "] must be at least 1, got " +
                       std::to_string(cells[a]));
    if (!std::isfinite(origin[a]))
      throw InputError("grid origin[" + std::to_string(a) + "] is not finite");
    origin_[a] = origin[a];
    h_[a] = cell_size[a];
    cells_[a] = cells[a];
  }
}

double Grid::min_cell_size() const {
  double h = h_[0];
  for (int a = 1; a < dim_; ++a)
    h = std::min(h, h_[a]);
  return h;
}

std::array<int, 3> Grid::node_ijk(Index node) const {
  const Index nx = nodes(0), ny = nodes(1);
  return {int(node % nx), int((node / nx) % ny), int(node / (nx * ny))};
}

Field Grid::node_positions() const {
  Field x(num_nodes(), dim_);
  for (Index i = 0; i < x.rows(); ++i)
    for (int a = 0; a < dim_; ++a)
      x(i, a) = node_coordinate(i, a);
  return x;
}

bool Grid::contains(const std::array<double, 3>& x) const {
  for (int a = 0; a < dim_; ++a)
    if (!(x[a] >= origin_[a] && x[a] <= origin_[a] + h_[a] * cells_[a]))
      return false;
  return true;
}

} // namespace smpm
