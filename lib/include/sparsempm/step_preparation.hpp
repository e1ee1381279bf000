// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file step_preparation.hpp
/// What a step needs from the particle configuration at its start, prepared by one function,
/// prepare_step, for everyone who needs it: the Stepper, the linearised step of the stability
/// analysis, the frame writer of a run and Python's assemble. It holds
///   - S, G, M, m and the active nodes (assemble, operators.hpp), with the materials' velocity
///     fields as blocks of columns of S in multimaterial mode (contact.hpp);
///   - the velocity BCs of the step: the model's conditions with the walls' nodes at the
///     model's time (FMPM 2026 §3.1), apart from the model's, which stay as they were given;
///   - the contact nodes with their normals, separations and areas (contact 2020 §2.3, §3.1);
///   - m̃ = Sᵀ M S, assembled on first use (only the steps that use it pay for it);
///   - with heat transport, the transport operators (capacities, conductances, c on the grid's
///     nodes), the temperature conditions of the step and c̃, assembled on first use.

#include "sparsempm/boundary.hpp"
#include "sparsempm/contact.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/transport.hpp"

namespace smpm {

/// The preparation of one step (this file's list), made by prepare_step and reused, storage
/// and all, by the next preparation.
struct StepPreparation {
  /// S, G, M, m and the active nodes of the configuration; set ops.node_range (the particles'
  /// window of the grid or the whole grid) before the first prepare_step.
  Operators ops;
  /// The model's velocity conditions with the walls' nodes selected at the model's time among
  /// the nodes with mass (BoundaryConditions::step_conditions): their values call the model's,
  /// so they are valid while the model's conditions are unchanged.
  BoundaryConditions bcs;
  Eigen::VectorXi field;  ///< velocity field of each particle (multimaterial; empty otherwise)
  Eigen::VectorXd volume; ///< current particle volumes J Ω⁽⁰⁾ (multimaterial: AG normals)
  ContactNodes contact;   ///< the contact nodes of the configuration (multimaterial)

  /// Whether the configuration has several velocity fields, and so contact nodes.
  bool has_contact() const { return ops.fields > 1; }
  /// m̃ = Sᵀ diag(M) S of `ops` in its stencil storage (assemble_consistent_mass), assembled on
  /// the first call after each prepare_step.
  const SparseRowMatrix& consistent_mass();
  /// The storage of m̃ as the last assembly left it (its pattern, whether it was reused).
  const ConsistentMass& consistent_mass_storage() const { return mt_; }
  /// m̃_L of the velocity-gradient transfer at the positions X of the preparation's particles
  /// (assemble_transfer_mass), in its own stencil storage, assembled on the first call after
  /// each prepare_step.
  const SparseRowMatrix& transfer_mass(const ConstFieldRef& X);

  /// Heat transport: the transport operators of the configuration (when prepared with
  /// transport) ...
  TransportOperators transport;
  /// ... and the model's temperature conditions on the transport nodes with capacity, their
  /// values those of the model's conditions (as `bcs`).
  BoundaryConditions temperature_bcs;
  /// Whether the transport operators were prepared.
  bool has_transport() const { return transport_; }
  /// c̃ = Sᵀ diag(𝗖) S on the transport nodes (assemble_consistent_capacity), assembled on the
  /// first call after each prepare_step with transport.
  const SparseRowMatrix& consistent_capacity();

private:
  friend void prepare_step(const Model& model, Shape shape, StepPreparation& prep,
                           TransportUpdate transport);
  ConsistentMass mt_;
  bool mt_current_ = false;
  ConsistentMass mtL_;
  bool mtL_current_ = false;
  ConsistentMass ct_;
  bool ct_current_ = false;
  bool transport_ = false;
};

/// Prepares `prep` for a step from the model's configuration with the shape functions `shape`:
/// assembly (reusing the pattern and storage of the previous preparation where the particles'
/// node boxes allow), the walls' nodes, the contact nodes and, with heat transport, the
/// transport operators (prepare_transport: every node with capacity active, kMassTolerance for
/// the exact solve) and the temperature conditions. Throws NumericalError naming the
/// particle when a particle's support leaves the grid, and InputError when conditions meet at
/// an angle on a node (FMPM 2026 Table 2) or a material cannot carry heat.
void prepare_step(const Model& model, Shape shape, StepPreparation& prep,
                  TransportUpdate transport = TransportUpdate::Off);

} // namespace smpm
