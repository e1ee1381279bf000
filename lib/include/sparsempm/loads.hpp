// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file loads.hpp
/// External loads on particles besides the uniform gravity of Model::gravity: body forces and
/// surface tractions, the f^ext of FMPM 2026 task 2 (f = f^int + Sᵀ F^ext).
///
/// A load acts on a set of particles; at the start of each step (time t, positions x_p) it
/// gives each of them a force F_p = w_p b(t, x_p):
/// - a body force: b is an acceleration (force per unit mass) and w_p = M_p;
/// - a traction: b is a force per unit reference area on one face of the particle's domain and
///   w_p = A_p, that face's initial area (face_area; a dead load: the area does not follow
///   the deformation).
/// A body force reaches the grid through the particle's shape functions, f_i += S_pi F_p. A
/// traction acts on the face itself, as NairnMPM's traction conditions do: its force is split
/// equally among the 2^(d−1) corners x_c of the loaded face of the particle's domain (the
/// trapezoidal rule on the face) and each share goes to the nodes of the particle's row of S
/// with the grid's hat functions at the corner, f_i += Σ_c N_i(x_c) F_p / 2^(d−1). The face is
/// that of the domain of the shape functions: X_p ± r⁰ (classic MPM, GIMP) or X_p + F_p diag(r⁰) ξ
/// (CPDI). A corner's hat weights are renormalised over the nodes of the row (they sum to 1
/// unless a hat node lies outside the particle's support, as with classic MPM's end particles),
/// so that the force is kept whole on nodes with mass.

#include "sparsempm/particles.hpp"

#include <functional>
#include <string>
#include <vector>

namespace smpm {

/// What a ParticleLoad's value b is.
enum class LoadKind {
  BodyForce, ///< b is a force per unit mass (an acceleration): F_p = M_p b
  Traction   ///< b is a force per unit reference area on a face: F_p = A_p b
};

/// One load on a set of particles (see loads.hpp).
struct ParticleLoad {
  LoadKind kind = LoadKind::BodyForce; ///< body force or traction
  std::vector<Index> particles;        ///< the particles it acts on (ids into Model::particles)
  /// Traction: A_p, the initial area of each particle's loaded face (one per entry of
  /// `particles`); unused for a body force (its weight is the particle's mass).
  Eigen::VectorXd area;
  /// b(t, x): given t and the current positions x of `particles` (one row each, d columns),
  /// writes b (the same shape, resized by the caller). Called once per step, never per particle.
  std::function<void(double t, const Field& x, Field& b)> value;
  std::string label; ///< for messages ("traction.0")
  int axis = 0;      ///< traction: the normal axis of the loaded face
  int side = 1;      ///< traction: +1 for the face on the + side of `axis`, −1 for the − side
};

/// A traction's force on one corner of a particle's loaded face (see loads.hpp).
struct PointForce {
  Index particle = 0;                              ///< the loaded particle (its row of S)
  Eigen::Vector3d x = Eigen::Vector3d::Zero();     ///< the corner's position x_c
  Eigen::Vector3d force = Eigen::Vector3d::Zero(); ///< its share F_p / 2^(d−1)
};

/// The loads of one step: body forces at the particles and tractions at their faces' corners.
struct ExternalForces {
  Field particle; ///< N × d: F^ext of the body forces at the particles (zero rows elsewhere)
  std::vector<PointForce> points; ///< the tractions' forces at the corners of the loaded faces
  bool any_body_force = false;    ///< whether `particle` holds a body force
  Field x;                        ///< scratch: the positions of a load's particles
  Field b;                        ///< scratch: its values b(t, x)
};

/// The initial area of particle p's face normal to `axis`: 1 in 1D (a bar of unit
/// cross-section), 2 r_b in 2D (unit thickness) and 4 r_b r_c in 3D, from the half-lengths r⁰
/// of its domain (Particles::half_length).
double face_area(const Particles& P, Index p, int axis);

/// The particles among `candidates` whose face on `side` (+1 or −1) of `axis` is on the
/// boundary of the set: no particle of the set has its centre within a quarter of the particle's
/// size of X_p ± 2 r_p ê_axis, the centre of the next particle of a lattice. In the order of
/// `candidates`.
std::vector<Index> exposed_face(const Particles& P, const std::vector<Index>& candidates, int axis,
                                int side);

/// The loads at time t: the body forces' F_p = M_p b(t, x_p) at the particles and the
/// tractions' F_p = A_p b(t, x_p) at the corners of the loaded faces, of the domains of the
/// shape functions (`deformed`: CPDI's X_p + F_p diag(r⁰) ξ, else X_p ± r⁰). Storage is reused
/// from call to call. Throws NumericalError naming the load, t and the particle when a value is
/// not finite.
void external_forces(const std::vector<ParticleLoad>& loads, const Particles& P, double t,
                     bool deformed, ExternalForces& out);

/// The total force Σ_p F_p of one load at time t (the applied load, to compare with the
/// reaction of a velocity condition).
Eigen::Vector3d total_load(const ParticleLoad& load, const Particles& P, double t);

} // namespace smpm
