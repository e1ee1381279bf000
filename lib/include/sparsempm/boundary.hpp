#pragma once
/// \file boundary.hpp
/// Fixed-velocity (zero-velocity) grid boundary conditions, applied as a diagonal projector
/// Φ on n × d nodal fields: Φx zeroes the constrained directions of the constrained nodes.

#include "sparsempm/grid.hpp"

#include <Eigen/Core>
#include <array>

namespace smpm {

/// n × d mask of free directions: free(i, a) = 0 when direction a of node i is fixed.
struct BoundaryConditions {
  Eigen::Array<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> free;

  /// No constraint on any of the grid's nodes.
  static BoundaryConditions none(const Grid& grid);
  /// Number of constrained (node, direction) pairs.
  Index num_fixed() const { return Index((free == 0.0).count()); }
  /// x ← Φ x: zero the constrained components of an n × d nodal field (Buzzi Eqs. 27–28).
  void apply(Field& x) const { x.array() *= free; }
};

/// Fixes the directions `dirs` (dirs[a] true ⇒ direction a fixed) of every node whose
/// coordinate along `axis` equals `at` (within 10⁻⁹ of a cell). Returns the number of nodes
/// selected; throws InputError if the plane holds no node.
Index fix_plane(const Grid& grid, int axis, double at, const std::array<bool, 3>& dirs,
                BoundaryConditions& bc);
/// Fixes the directions `dirs` of every node inside the box [lo, hi]. Returns the number of
/// nodes selected; throws InputError if the box holds no node.
Index fix_box(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
              const std::array<bool, 3>& dirs, BoundaryConditions& bc);

} // namespace smpm
