#pragma once
/// \file grid.hpp
/// Structured background grid in 1, 2 or 3 dimensions (dimension chosen at run time).

#include "sparsempm/types.hpp"

#include <array>

namespace smpm {

/// A structured grid of `cells[a]` cells of size `cell_size[a]` along each axis a < dim,
/// starting at `origin`. Nodes are numbered i + nx (j + ny k) (Buzzi et al., Eq. 21), so
/// the node index grows fastest along x.
class Grid {
public:
  /// A 1D grid of one unit cell at the origin (a placeholder to be assigned over).
  Grid() : Grid(1, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}) {}
  /// Throws InputError unless 1 ≤ dim ≤ 3, every cell size is positive and finite and
  /// every cell count is at least 1.
  Grid(int dim, const std::array<double, 3>& origin, const std::array<double, 3>& cell_size,
       const std::array<int, 3>& cells);

  int dim() const { return dim_; }
  double origin(int axis) const { return origin_[axis]; }
  double cell_size(int axis) const { return h_[axis]; }
  int cells(int axis) const { return axis < dim_ ? cells_[axis] : 0; }
  /// Number of nodes along an axis: cells + 1 for a < dim, 1 for unused axes.
  int nodes(int axis) const { return axis < dim_ ? cells_[axis] + 1 : 1; }
  /// Total number of nodes n.
  Index num_nodes() const { return Index(nodes(0)) * nodes(1) * nodes(2); }
  /// Smallest cell size over the used axes (Δx_min of FMPM 2026 §3.3).
  double min_cell_size() const;

  /// Node index of (i, j, k); unused axes take 0.
  Index node_index(int i, int j = 0, int k = 0) const {
    return i + Index(nodes(0)) * (j + Index(nodes(1)) * k);
  }
  /// (i, j, k) of a node index.
  std::array<int, 3> node_ijk(Index node) const;
  /// Coordinate of a node along an axis.
  double node_coordinate(Index node, int axis) const {
    return origin_[axis] + h_[axis] * node_ijk(node)[axis];
  }
  /// Position of a node (unused axes 0).
  Eigen::Vector3d node_position(Index node) const {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int a = 0; a < dim_; ++a)
      x[a] = node_coordinate(node, a);
    return x;
  }
  /// n × d matrix of node positions, one row per node.
  Field node_positions() const;
  /// True when x (first d entries used) lies inside the box [origin, origin + cells h].
  bool contains(const std::array<double, 3>& x) const;

private:
  int dim_;
  std::array<double, 3> origin_;
  std::array<double, 3> h_;
  std::array<int, 3> cells_;
};

} // namespace smpm
