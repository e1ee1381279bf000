// SPDX-License-Identifier: BSD-3-Clause
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
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace smpm {

/// A moving wall's position s_w, velocity v and gradient ∇v at one time (MovingWall::at).
struct WallState {
  /// \var position
  /// s_w, the wall's position along its normal n̂
  /// \var velocity
  /// v, its velocity along n̂
  /// \var gradient
  /// ∇v, the spatial gradient of that velocity along n̂
  double position = 0, velocity = 0, gradient = 0;
  /// FMPM 2026 §3.1: v + ∇v (x · n̂ − s_w).
  double value(const Eigen::Vector3d& normal, const Eigen::Vector3d& x) const {
    return velocity + gradient * (x.dot(normal) - position);
  }
};

/// One velocity condition (FMPM 2026 §3.1): on each of its nodes the velocity component along
/// the unit n̂ is set to v_b(t, x), v_i ← v_i − (v_i · n̂) n̂ + v_b n̂.
struct VelocityCondition {
  std::vector<Index> nodes;                                        ///< constrained nodes
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();            ///< unit n̂ (d entries used)
  std::function<double(double t, const Eigen::Vector3d& x)> value; ///< v_b(t, x); empty ⇒ 0
  std::string label;                                               ///< for messages
  int wall = -1; ///< ≥ 0: the nodes are those BoundaryConditions::walls[wall] selects each step
  /// ≥ 0: the condition acts on this velocity field alone (a rigid material's field in
  /// multimaterial mode, rigid.hpp); −1: on node i of every field.
  int field = -1;
  /// A wall's condition in one step (BoundaryConditions::step_conditions): v_b is the wall's
  /// value with this state (n̂ = direction, the wall's normal) and `value` is empty.
  std::optional<WallState> wall_state;
  /// v_b(t, x): the wall's value with wall_state when set, else value(t, x), 0 without either.
  double value_at(double t, const Eigen::Vector3d& x) const {
    return wall_state ? wall_state->value(direction, x) : value ? value(t, x) : 0.0;
  }
};

/// A wall moving through the grid (FMPM 2026 §3.1, Fig. 2): the plane s = s_w(t) with unit
/// normal n̂ pointing out of the object, s = x · n̂, moving along n̂ with velocity v(t) and
/// spatial gradient ∇v(t). At time t it constrains, in the direction n̂, every node with mass
/// beyond it (s_i > s_w) and every node with mass inside it within the depth d
/// (s_w − d ≤ s_i ≤ s_w), to
///     v_i = v(t) + ∇v(t) (s_i − s_w(t)).
struct MovingWall {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX(); ///< unit n̂, out of the object
  std::function<double(double t)> position;          ///< s_w(t) = x_wall(t) · n̂
  std::function<double(double t)> velocity;          ///< v(t); empty ⇒ 0
  std::function<double(double t)> gradient;          ///< ∇v(t); empty ⇒ 0
  double depth = 0;                                  ///< d (length)
  std::string label;                                 ///< for messages ("bc.N.wall")
  /// s_w(t), v(t) and ∇v(t), each evaluated once. Throws NumericalError naming the function
  /// (label.position, label.velocity or label.gradient), t and the value when one is not
  /// finite: a wall whose position stops being finite would otherwise select no node and stop
  /// acting unnoticed.
  WallState at(double t) const;
  /// v(t) + ∇v(t) (x · n̂ − s_w(t)).
  double value_at(double t, const Eigen::Vector3d& x) const;
  /// Whether a node at x is constrained at time t (it must also have mass).
  bool selects(double t, const Eigen::Vector3d& x, double tolerance) const;
};

/// The velocity conditions of a model (FMPM 2026 §3.1, Table 2): each sets one direction of
/// the velocity on its nodes; a moving wall's condition takes the nodes the wall selects.
struct BoundaryConditions {
  /// Every condition, the walls' included.
  std::vector<VelocityCondition> conditions;
  std::vector<MovingWall> walls; ///< their conditions are in `conditions` (wall ≥ 0)

  /// Adds a moving wall and its velocity condition (nodes selected by select_wall_nodes).
  void add_wall(const MovingWall& wall);
  /// Appends the conditions and walls of `other` (the conditions of its walls renumbered).
  void append(const BoundaryConditions& other);
  /// Selects the nodes of every wall at time t: the active (massive) nodes the wall constrains
  /// (MovingWall). Then checks that the conditions on every node are parallel or perpendicular
  /// (FMPM 2026 §3.1, Table 2); throws InputError naming the node and the conditions otherwise.
  /// The step calls this once per step, with the values of that step's time.
  void select_wall_nodes(const Grid& grid, const Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                         double t);
  /// The conditions of one step, written into `step` (whose storage is reused: no allocation
  /// once its lists have grown): these conditions with every wall's nodes selected at time t as
  /// select_wall_nodes does, then checked for superposition. Each wall's s_w, v and ∇v are
  /// evaluated once, at t (MovingWall::at: NumericalError when one is not finite), into its
  /// condition's wall_state; the other value functions of `step` call those of these
  /// conditions (no copy of their expressions per step), so these must outlive `step` and stay
  /// unchanged while it is used; its conditions have wall = −1.
  void step_conditions(const Grid& grid, const Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                       double t, BoundaryConditions& step) const;
  /// Throws InputError unless the conditions sharing a node are parallel or perpendicular.
  void check_superposition() const;
  /// Throws InputError naming the node and both conditions when a node is in two conditions:
  /// temperature conditions hold a value, they do not superpose.
  void check_one_condition_per_node() const;
  /// Whether any condition prescribes a non-zero velocity (a value function or a wall): the
  /// BCs then do work on the particles.
  bool driven() const;

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
  void zero_directions(const Grid& grid, Field& v) const;
  // Every function taking a node field accepts one of several velocity fields too (n_f · n_g
  // rows, operators.hpp): a condition on node i acts on node i of every field (of its `field`
  // alone when that is set). The nodes of the
  // conditions are those of the whole grid; given a window of it (Grid::window) and fields on
  // its nodes, a function acts on the nodes the window holds.

private:
  mutable std::vector<std::pair<Index, Index>> pairs_; // check_superposition's (node, condition)
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
