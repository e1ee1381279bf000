// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file rigid.hpp
/// Rigid materials with a prescribed motion: pistons, platens and impact walls made of
/// particles, as NairnMPM's rigid material used for velocity conditions. The particles of a
/// material of model `rigid` move with the velocity v(t) of its RigidMotion; on the grid, every
/// node a rigid particle's shape functions reach (S_pi > 0) takes that velocity in every axis,
/// by one velocity condition per axis (FMPM 2026 §3.1, with the conditions' reactions: the force
/// the body applies). In multimaterial mode the conditions act on every field of those nodes
/// (the body is bonded to what touches it); contact laws against a rigid partner are not
/// implemented.

#include "sparsempm/boundary.hpp"
#include "sparsempm/particles.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace smpm {

struct Operators; // operators.hpp

/// The prescribed motion of the particles of one rigid material (MaterialModel::Rigid).
struct RigidMotion {
  int material = -1; ///< the material's index (Model::materials)
  /// v_a(t), the velocity along each axis a < d (an empty function is 0).
  std::array<std::function<double(double t)>, 3> velocity;
  std::string label; ///< for messages and the reactions ("material.piston")
  /// v(t); throws NumericalError naming the label, t and the axis when a component is not
  /// finite.
  Eigen::Vector3d at(double t) const;
};

/// Appends to `step` (the step's conditions) one condition per axis a < d for each motion: on
/// the nodes of `ops` (field blocks folded onto their grid node, named by their node of the
/// whole grid as every condition is) with S_pi > 0 for a particle
/// of the motion's material, the value v_a(t) in the direction ê_a, labelled
/// "<label>.x" (.y, .z). A node that an earlier condition (of the model, or of an earlier rigid
/// material) sets along the same axis is left to it: parallel conditions would add their values.
/// Checks the superposition of the conditions (FMPM 2026 §3.1).
void add_rigid_conditions(const std::vector<RigidMotion>& motions,
                          const Eigen::Ref<const Eigen::VectorXi>& material, const Operators& ops,
                          double t, BoundaryConditions& step);

/// After a step from t to t + Δt: the particles of each rigid material, from their positions
/// X_start at t (N × d), to X_start + Δt v(t + Δt/2) with V = v(t + Δt), F = I and no stress
/// (the midpoint rule: exact for a velocity linear in t).
void move_rigid_particles(const std::vector<RigidMotion>& motions, const Field& X_start, double t,
                          double dt, Particles& particles);

} // namespace smpm
