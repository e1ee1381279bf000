// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file rigid.hpp
/// Rigid materials: pistons, platens, impact walls and free rigid bodies made of particles, as
/// NairnMPM's rigid materials. The particles of a material of model `rigid` move with the
/// velocity v(t) of its RigidMotion; on the grid, every node a rigid particle's shape functions
/// reach (S_pi > 0) takes that velocity in every axis, by one velocity condition per axis (FMPM
/// 2026 §3.1), whose reaction is the force the drive applies to hold the body to v(t): the
/// force that the grid's other forces on the body (contact, gravity) leave to it.
///
/// In single material mode the conditions act on every field of those nodes: the body is
/// bonded to what it touches. In multimaterial mode they act on the rigid material's own field
/// alone, and the rigid field is a contact partner of infinite mass with every law, normal and
/// separation (contact.hpp, ContactNodes::rigid): contact moves the other side to the rigid
/// velocity along n̂ (and along t̂ as the law allows), and the contact force on the body appears
/// in its reaction.
///
/// A free rigid body (RigidMotion::free) has no drive: its velocity is its particles' common
/// velocity, and a step changes it by −Δt R / M, R the reactions of its conditions (the force
/// the drive would have applied) and M its mass: M dv/dt is the sum of the grid forces on its
/// field. It translates; it does not rotate. It needs multimaterial mode (a field of its own)
/// and FLIP or PIC (check_rigid_motions).

#include "sparsempm/boundary.hpp"
#include "sparsempm/particles.hpp"
#include "sparsempm/step_options.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace smpm {

class NodeSums; // fmpm.hpp

struct Operators; // operators.hpp

/// The prescribed motion of the particles of one rigid material (MaterialModel::Rigid).
struct RigidMotion {
  int material = -1; ///< the material's index (Model::materials)
  /// v_a(t), the velocity along each axis a < d (an empty function is 0).
  std::array<std::function<double(double t)>, 3> velocity;
  std::string label; ///< for messages and the reactions ("material.piston")
  /// A free rigid body: `velocity` gives its velocity at t = 0, and the grid's forces its
  /// velocity after (rigid_velocity, move_rigid_particles).
  bool free = false;
  /// v(t); throws NumericalError naming the label, t and the axis when a component is not
  /// finite.
  Eigen::Vector3d at(double t) const;
};

/// The velocity of a motion at time t: v(t) if prescribed; for a free body, the mass-weighted
/// mean velocity of its particles (they share one), over every process with `sums` (each holding
/// some of the particles; collective then).
Eigen::Vector3d rigid_velocity(const RigidMotion& motion, const Particles& particles, double t,
                               const NodeSums* sums = nullptr);

/// Per velocity field: 1 for the field of a rigid material (ContactNodes::rigid), written into
/// `rigid` (resized to `fields`); `material_field` is Contact::material_field.
void rigid_fields(const std::vector<RigidMotion>& motions, const std::vector<int>& material_field,
                  int fields, std::vector<char>& rigid);

/// Appends to `step` (the step's conditions) one condition per axis a < d for each motion: on
/// the nodes of `ops` (field blocks folded onto their grid node, named by their node of the
/// whole grid as every condition is) with S_pi > 0 for a particle of the motion's material, the
/// value rigid_velocity(t)_a in the direction ê_a, labelled "<label>.x" (.y, .z). With several
/// fields (ops.fields > 1) the condition acts on the material's field alone
/// (`material_field`, Contact::material_field), otherwise on every field. A node that an
/// earlier condition on the same fields (of the model, or of an earlier rigid material) sets
/// along the same axis is left to it: parallel conditions would add their values. Checks the
/// superposition of the conditions (FMPM 2026 §3.1). Across processes (`sums`, bound to the
/// window of `ops`; collective then) a node is the motion's when the particles of any process
/// reach it, so every process whose window holds the node constrains it.
void add_rigid_conditions(const std::vector<RigidMotion>& motions, const Particles& particles,
                          const std::vector<int>& material_field, const Operators& ops, double t,
                          BoundaryConditions& step, const NodeSums* sums = nullptr);

/// Throws InputError naming the material when the rigid motions cannot run with these fields
/// and options: in multimaterial mode (`material_field` not empty) a rigid material sharing its
/// velocity field with another material (its conditions would hold that material too); a free
/// body in single material mode (it needs a field of its own), with a velocity update other
/// than FLIP or PIC (the contact corrections of FMPM(k), XPIC(m) and the exact update come
/// after its reactions), or with Buzzi's improper BC ordering (no reactions).
void check_rigid_motions(const std::vector<RigidMotion>& motions,
                         const std::vector<int>& material_field, const StepOptions& options);

/// Before a step at t: the particles of each prescribed motion take V = v(t), so that the
/// extrapolated momenta of a rigid field hold its velocity before its conditions act; each
/// motion's velocity at t (rigid_velocity, over the processes with `sums`) is written to
/// `velocity` (resized).
void start_rigid_motion(const std::vector<RigidMotion>& motions, double t, Particles& particles,
                        std::vector<Eigen::Vector3d>& velocity, const NodeSums* sums = nullptr);

/// After a step from t to t + Δt: the particles of each rigid material, from their positions
/// X_start at t (N × d), to X_start + Δt v_mid with V = v_end, F = I and no stress. Prescribed:
/// v_mid = v(t + Δt/2), v_end = v(t + Δt) (the midpoint rule: exact for a velocity linear in t).
/// Free: v_end,a = v_a − Δt R_a / M_a, v_mid = (v + v_end)/2, with v = velocity[k] (the
/// velocity at t that start_rigid_motion gave),
/// R_a = reactions[k d + a] the reaction of motion k's condition along axis a in the step and
/// M_a = masses[k d + a] the mass on that condition's nodes (in the order add_rigid_conditions
/// appended the conditions): the body's mass, which its field's nodal masses sum to.
void move_rigid_particles(const std::vector<RigidMotion>& motions, const Field& X_start, double t,
                          double dt, const std::vector<Eigen::Vector3d>& velocity,
                          const double* reactions, const double* masses, Particles& particles);

} // namespace smpm
