// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file particles.hpp
/// Material points as a structure of arrays (one row per particle).

#include "sparsempm/grid.hpp"

#include <Eigen/Core>
#include <array>
#include <map>
#include <string>

namespace smpm {

/// N material points in dimension d. Tensors are stored one particle per row, the d × d
/// tensor flattened row-major: column a d + b holds component (a, b).
struct Particles {
  int dim = 1;              ///< d: the columns of X and V (d² of F and stress)
  Field X;                  ///< N × d positions
  Field V;                  ///< N × d velocities
  Field F;                  ///< N × d² deformation gradients
  Field stress;             ///< N × d² Cauchy stresses
  Eigen::VectorXd mass;     ///< N masses M_p
  Eigen::VectorXd volume0;  ///< N initial volumes V_p^(0)
  Eigen::VectorXi material; ///< N material ids (index into the material list)
  Field half_length;        ///< N × d initial half-lengths r⁰ of the particle domain
  /// N internal energies per unit mass U: the work of pressure and artificial viscosity of
  /// Mie–Grüneisen particles (material.hpp), 0 for other materials. Empty: all 0.
  Eigen::VectorXd energy;
  /// N absolute temperatures T_p (heat transport, transport.hpp); empty: no temperature.
  Eigen::VectorXd temperature;
  /// N heat sources r_p, power per unit mass (heat transport); empty: none.
  Eigen::VectorXd heat_source;
  /// N × d² affine velocities L_p (row-major), carried by the affine transfers
  /// (StepOptions::transfer): the velocity gradient G v, or APIC's C_p = B_p D_p⁻¹; empty: none
  /// (zero).
  Field gradient;
  /// N × 9: b̄ᵉ = J^{−2/3} Fᵉ Fᵉᵀ, the isochoric elastic left Cauchy–Green tensor (row-major 3 × 3)
  /// of J2 plasticity (plasticity.hpp); empty: no plastic material (or none yet: b̄ᵉ of F).
  Field elastic_cauchy_green;
  /// N equivalent plastic strains ε̄ᵖ (plasticity.hpp); empty with elastic_cauchy_green.
  Eigen::VectorXd plastic_strain;
  /// The columns of the parts a program adds to the step (register_step_part, step_part.hpp),
  /// by name: N × width each (particle_columns.hpp). The library's own parts keep theirs in the
  /// members above.
  std::map<std::string, Field, std::less<>> columns;

  /// N, the number of particles (rows of X).
  Index size() const { return X.rows(); }
  /// Resizes to N particles of dimension d with F = I and every other field zero (temperature,
  /// heat_source and gradient empty).
  void resize(int d, Index N);
  /// Current volumes V_p = det(F_p) V_p^(0), one entry per particle.
  Eigen::VectorXd volume() const;
  /// det F_p for every particle.
  Eigen::VectorXd jacobian() const;
  /// det F_p of one particle.
  double det_F(Index p) const;
  /// det F_p for every particle, written into J (resized to N).
  void jacobian(Eigen::VectorXd& J) const;
  /// Appends the particles of `other` (same dimension) after the existing ones; an empty energy
  /// or heat-source column counts as zeros. Throws UsageError when one set has temperatures and
  /// the other none.
  void append(const Particles& other);
};

/// Particles on a regular lattice filling the box [lo, hi]: `ppc[a]` particles per cell
/// along axis a, each owning an axis-aligned cell fraction (half-length h_a / (2 ppc_a)),
/// mass = density × volume, F = I, V = 0, stress 0. Throws InputError if the box is
/// empty, not inside the grid, or ppc < 1.
Particles make_block(const Grid& grid, const std::array<double, 3>& lo,
                     const std::array<double, 3>& hi, const std::array<int, 3>& ppc, double density,
                     int material_id);

} // namespace smpm
