// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file model.hpp
/// A simulation's state: grid, particles, materials, boundary conditions, clock.

#include "sparsempm/boundary.hpp"
#include "sparsempm/contact.hpp"
#include "sparsempm/grid.hpp"
#include "sparsempm/loads.hpp"
#include "sparsempm/material.hpp"
#include "sparsempm/particles.hpp"
#include "sparsempm/rigid.hpp"

#include <array>
#include <vector>

namespace smpm {

/// A simulation's state: what an input file describes and a Stepper advances.
struct Model {
  Grid grid;                       ///< the whole background grid
  Particles particles;             ///< the material points
  std::vector<Material> materials; ///< indexed by Particles::material
  BoundaryConditions bcs;          ///< velocity conditions and moving walls
  /// Temperature conditions (Dirichlet, heat transport): each a condition on a node field of
  /// one column (direction x̂) whose value v_b(t, x) is the prescribed temperature.
  BoundaryConditions temperature_bcs;
  Contact contact; ///< velocity fields of the materials and their contact laws (contact.hpp)
  /// The uniform body acceleration B of every particle ([loads] gravity), d entries used: the
  /// body force per unit mass of FMPM 2026 task 2, f += Sᵀ M B.
  std::array<double, 3> gravity{0, 0, 0};
  /// Body forces and tractions on sets of particles (loads.hpp): f += Sᵀ F^ext.
  std::vector<ParticleLoad> loads;
  /// The prescribed motions of the rigid materials (rigid.hpp), one per material of model rigid.
  std::vector<RigidMotion> rigid;
  double time = 0; ///< simulated time t
  long step = 0;   ///< number of steps taken

  Model() = default;
  /// A model on `grid` with no particles and no constraints.
  explicit Model(const Grid& g) : grid(g), bcs(BoundaryConditions::none(g)) {}
};

} // namespace smpm
