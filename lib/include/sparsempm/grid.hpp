// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file grid.hpp
/// Structured background grid in 1, 2 or 3 dimensions (dimension chosen at run time).

#include "sparsempm/types.hpp"

#include <array>

namespace smpm {

/// A structured grid of `cells[a]` cells of size `cell_size[a]` along each axis a < dim,
/// starting at `origin`. Nodes are numbered i + nx (j + ny k) (Buzzi et al., Eq. 21), so
/// the node index grows fastest along x.
///
/// A window of a grid (window()) is the box of its nodes (i, j, k) with first ≤ (i, j, k) <
/// first + count, numbered in the same way from its first node: the operators of a step live on
/// the window of the nodes its particles reach (NodeRange::Particles, operators.hpp), so that
/// their size follows the particles, not the grid. A window keeps the grid's origin, cells and
/// (i, j, k): positions and shape functions are computed exactly as on the whole grid (the same
/// bits); only the numbering of its nodes differs.
class Grid {
public:
  /// A 1D grid of one unit cell at the origin (a placeholder to be assigned over).
  Grid() : Grid(1, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}) {}
  /// Most cells along an axis (2³⁰).
  static constexpr int kMaxCells = 1 << 30;
  /// Most nodes of a grid (2⁵⁰).
  static constexpr Index kMaxNodes = Index(1) << 50;
  /// A grid of `cells[a]` cells of size `cell_size[a]` from `origin` along each axis a < dim
  /// (the entries of unused axes are ignored). Throws InputError unless 1 ≤ dim ≤ 3, every
  /// cell size is positive and finite, every origin is finite, every cell count is 1 to
  /// kMaxCells and the grid has at most kMaxNodes nodes (so that no count of nodes or node
  /// index overflows).
  Grid(int dim, const std::array<double, 3>& origin, const std::array<double, 3>& cell_size,
       const std::array<int, 3>& cells);

  /// The dimension d: 1, 2 or 3.
  int dim() const { return dim_; }
  /// Coordinate along an axis of node (0, 0, 0) of the whole grid (0 for unused axes).
  double origin(int axis) const { return origin_[axis]; }
  /// Cell size h_a along an axis (1 for unused axes).
  double cell_size(int axis) const { return h_[axis]; }
  /// Cells of the whole grid along an axis (0 for unused axes).
  int cells(int axis) const { return axis < dim_ ? cells_[axis] : 0; }
  /// Number of nodes along an axis: cells + 1 for a < dim (the window's count for a window), 1
  /// for unused axes.
  int nodes(int axis) const { return count_[axis]; }
  /// Total number of nodes n (of the window for a window).
  Index num_nodes() const { return Index(count_[0]) * count_[1] * count_[2]; }
  /// The window of the nodes first[a] ≤ i_a < first[a] + count[a] of this grid (of the whole
  /// grid when this is a window). Throws InputError unless it lies inside the grid and is not
  /// empty.
  Grid window(const std::array<int, 3>& first, const std::array<int, 3>& count) const;
  /// (i, j, k) of the window's first node in the whole grid (0 for a whole grid).
  int first_node(int axis) const { return first_[axis]; }
  /// Whether this is a window smaller than the whole grid.
  bool is_window() const;
  /// Number of nodes of the whole grid.
  Index whole_num_nodes() const {
    Index n = 1;
    for (int a = 0; a < dim_; ++a)
      n *= cells_[a] + 1;
    return n;
  }
  /// Whether `other` is the same whole grid (dimension, origin, cell sizes and cells).
  bool same_whole_grid(const Grid& other) const;
  /// The same whole grid and the same window of it.
  bool operator==(const Grid&) const = default;
  /// Index in the whole grid of this grid's node `node`.
  Index whole_node(Index node) const {
    const auto ijk = node_ijk(node);
    Index w = 0;
    for (int a = dim_ - 1; a >= 0; --a)
      w = w * (cells_[a] + 1) + ijk[a];
    return w;
  }
  /// This grid's node at the whole grid's node `whole`, −1 when the window does not hold it.
  Index node_of_whole(Index whole) const;
  /// Smallest cell size over the used axes (Δx_min of FMPM 2026 §3.3).
  double min_cell_size() const;

  /// Node index of (i, j, k), the node's position in the whole grid; unused axes take 0.
  Index node_index(int i, int j = 0, int k = 0) const {
    return (i - first_[0]) +
           Index(count_[0]) * ((j - first_[1]) + Index(count_[1]) * (k - first_[2]));
  }
  /// (i, j, k) of a node index, in the whole grid.
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
  /// True when x (first d entries used) lies inside the box [origin, origin + cells h] of the
  /// whole grid.
  bool contains(const std::array<double, 3>& x) const;

private:
  int dim_;
  std::array<double, 3> origin_;
  std::array<double, 3> h_;
  std::array<int, 3> cells_;
  std::array<int, 3> first_{0, 0, 0}; ///< the window's first node (i, j, k)
  std::array<int, 3> count_{1, 1, 1}; ///< nodes per axis of the window (all: cells + 1)
};

} // namespace smpm
