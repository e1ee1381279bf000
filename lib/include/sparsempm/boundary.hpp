#pragma once
/// \file boundary.hpp
/// Grid velocity boundary conditions (FMPM 2026 §3.1, Table 2, top block; Buzzi §5.5).
///
/// A condition b sets the velocity of each of its nodes in the unit direction n̂_b to v_b(t, x):
///     v_i ← v_i − (v_i · n̂_b) n̂_b + v_b n̂_b.
/// A fixed direction is the condition v_b = 0 along an axis. Several conditions may act on
/// one node if their directions are parallel or perpendicular (FMPM 2026 §3.1).

#include "sparsempm/grid.hpp"

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

namespace smpm {

struct VelocityCondition {
  std::vector<Index> nodes;                                        ///< constrained nodes
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();            ///< unit n̂ (d entries used)
  std::function<double(double t, const Eigen::Vector3d& x)> value; ///< v_b(t, x); empty ⇒ 0
  std::string label;                                               ///< for messages
  double value_at(double t, const Eigen::Vector3d& x) const { return value ? value(t, x) : 0.0; }
};

struct BoundaryConditions {
  std::vector<VelocityCondition> conditions;

  /// No constraint.
  static BoundaryConditions none(const Grid&) { return {}; }
  /// Number of (node, condition) pairs.
  Index num_constrained() const;
  /// p_i ← p_i − (p_i · n̂) n̂ + m_i v_b(t, x_i) n̂ on every constrained node (lumped-mass BC in
  /// momentum form; with v_b = 0 this is Buzzi's zeroing of the fixed momentum, Eqs. 27–28).
  void constrain_momentum(const Grid& grid, const Eigen::VectorXd& m, double t, Field& p) const;
  /// Constrains the updated momentum p⁺ (as constrain_momentum at time t) and adds the
  /// reaction force f^(BC) = (p⁺_constrained − p⁺)/Δt to f on the constrained nodes
  /// (FMPM 2026 task 2.a), so that f stays consistent with p⁺ = p + f Δt.
  void constrain_update(const Grid& grid, const Eigen::VectorXd& m, double t, double dt,
                        Field& p_plus, Field& f) const;
  /// v_i ← v_i − (v_i · n̂) n̂ + v_b(t, x_i) n̂ on every constrained node (only on the nodes
  /// where `active` is true when a mask is given: nodes without mass keep v = 0).
  void constrain_velocity(const Grid& grid, double t, Field& v,
                          const Eigen::Array<bool, Eigen::Dynamic, 1>* active = nullptr) const;
  /// v_i ← v_i − (v_i · n̂) n̂: zero the constrained directions (FMPM 2026 Table 2, bottom).
  void zero_directions(Field& v) const;
};

/// Nodes whose coordinate along `axis` equals `at` (within 10⁻⁹ of a cell). Throws
/// InputError if the plane holds no node.
std::vector<Index> nodes_on_plane(const Grid& grid, int axis, double at);
/// Nodes inside the box [lo, hi] (within 10⁻⁹ of a cell). Throws InputError if none.
std::vector<Index> nodes_in_box(const Grid& grid, const std::array<double, 3>& lo,
                                const std::array<double, 3>& hi);

/// Adds one zero-velocity condition per fixed axis (dirs[a] true) on the plane
/// x_axis = at. Returns the number of nodes selected.
Index fix_plane(const Grid& grid, int axis, double at, const std::array<bool, 3>& dirs,
                BoundaryConditions& bc);
/// Adds one zero-velocity condition per fixed axis on the nodes inside [lo, hi].
Index fix_box(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
              const std::array<bool, 3>& dirs, BoundaryConditions& bc);

} // namespace smpm
