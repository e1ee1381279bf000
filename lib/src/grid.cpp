// SPDX-License-Identifier: BSD-3-Clause
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
    if (cells[a] < 1 || cells[a] > kMaxCells)
      throw InputError("grid cells[" + std::to_string(a) + "] must be 1 to " +
                       std::to_string(kMaxCells) + ", got " + std::to_string(cells[a]));
    if (!std::isfinite(origin[a]))
      throw InputError("grid origin[" + std::to_string(a) + "] is not finite");
    origin_[a] = origin[a];
    h_[a] = cell_size[a];
    cells_[a] = cells[a];
    count_[a] = cells[a] + 1;
  }
  // Counted in double, where the product of three counts up to 2^30 + 1 cannot overflow.
  if (double(count_[0]) * count_[1] * count_[2] > double(kMaxNodes))
    throw InputError("grid of " + std::to_string(count_[0]) + " x " + std::to_string(count_[1]) +
                     " x " + std::to_string(count_[2]) + " nodes: more than the " +
                     std::to_string(kMaxNodes) + " a grid can number");
}

Grid Grid::window(const std::array<int, 3>& first, const std::array<int, 3>& count) const {
  Grid w = *this;
  for (int a = 0; a < dim_; ++a) {
    if (first[a] < 0 || count[a] < 1 || first[a] + count[a] > cells_[a] + 1)
      throw InputError("grid window: nodes " + std::to_string(first[a]) + " to " +
                       std::to_string(first[a] + count[a] - 1) + " along axis " +
                       std::to_string(a) + " are not inside the grid's 0 to " +
                       std::to_string(cells_[a]));
    w.first_[a] = first[a];
    w.count_[a] = count[a];
  }
  return w;
}

bool Grid::same_whole_grid(const Grid& g) const {
  return dim_ == g.dim_ && origin_ == g.origin_ && h_ == g.h_ && cells_ == g.cells_;
}

bool Grid::is_window() const {
  for (int a = 0; a < dim_; ++a)
    if (first_[a] != 0 || count_[a] != cells_[a] + 1)
      return true;
  return false;
}

Index Grid::node_of_whole(Index whole) const {
  Index node = 0, stride = 1;
  for (int a = 0; a < dim_; ++a) {
    const Index n = cells_[a] + 1;
    const Index i = whole % n - first_[a];
    whole /= n;
    if (i < 0 || i >= count_[a])
      return -1;
    node += i * stride;
    stride *= count_[a];
  }
  return whole == 0 ? node : -1;
}

double Grid::min_cell_size() const {
  double h = h_[0];
  for (int a = 1; a < dim_; ++a)
    h = std::min(h, h_[a]);
  return h;
}

std::array<int, 3> Grid::node_ijk(Index node) const {
  const Index nx = count_[0], ny = count_[1];
  return {int(node % nx) + first_[0], int((node / nx) % ny) + first_[1],
          int(node / (nx * ny)) + first_[2]};
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
