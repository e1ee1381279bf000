// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file step_preparation.hpp
/// What a step needs from the particle configuration at its start, prepared by prepare_step for
/// everyone who needs it (the Stepper, the linearised step of the stability analysis, the frame
/// writer of a run and Python's assemble) and by the parts of the step for what they add
/// (StepPart::prepare; prepare_heat_transport for heat transport). It holds
///   - S, G, M, m and the active nodes (assemble, operators.hpp), with the materials' velocity
///     fields as blocks of columns of S in multimaterial mode (contact.hpp);
///   - the velocity BCs of the step: the model's conditions with the walls' nodes at the
///     model's time (FMPM 2026 §3.1), apart from the model's, which stay as they were given;
///   - the contact nodes with their normals, separations and areas (contact 2020 §2.3, §3.1);
///   - m̃ = Sᵀ M S, assembled on first use (only the steps that use it pay for it);
///   - with heat transport (prepare_heat_transport), the transport operators (capacities,
///     conductances, c on the grid's nodes), the temperature conditions of the step and c̃,
///     assembled on first use.

#include "sparsempm/boundary.hpp"
#include "sparsempm/contact.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/transport.hpp"

#include <chrono>

namespace smpm {

class NodeSums; // fmpm.hpp

/// Wall seconds spent in each part of a run, summed over its steps: where a whole run's time
/// goes (`smpm run --timings`). prepare_step and the parts' preparations (the transport and its
/// conditions: prepare_heat_transport) fill the first four, Stepper::step the next
/// three, and advance and run the run driver's parts. The clock is read a few times per step.
struct PhaseTimes {
  double assemble = 0;    ///< S, G, their patterns, m, the column index, the particles' fields
  double conditions = 0;  ///< the step's velocity (and temperature) conditions and rigid nodes
  double contact = 0;     ///< the contact nodes: clouds, normals, LR fits, separations, areas
  double transport = 0;   ///< the transport operators (heat transport)
  double mass_matrix = 0; ///< m̃ (or m̃_L) of the steps that use it
  double update = 0;      ///< the step's stages (scheme_step): grid velocities, stresses, particles
  double reactions = 0;   ///< the conditions' reactions and the rigid materials' motion
  double energies = 0;    ///< the energies, failure tests and Courant time step after each step
  double series = 0;      ///< the series row of each step (material sums, velocity change)
  double frames = 0;      ///< the frames written (with the preparation of their step)
  /// The sum of the parts.
  double total() const {
    return assemble + conditions + contact + transport + mass_matrix + update + reactions +
           energies + series + frames;
  }
  /// The seconds of each part since `start` (this minus start, part by part).
  PhaseTimes since(const PhaseTimes& start) const {
    return {assemble - start.assemble,   conditions - start.conditions,   contact - start.contact,
            transport - start.transport, mass_matrix - start.mass_matrix, update - start.update,
            reactions - start.reactions, energies - start.energies,       series - start.series,
            frames - start.frames};
  }
};

/// Adds the wall time between its construction (or the last lap) and each lap to a part of
/// PhaseTimes.
class PhaseClock {
public:
  PhaseClock() : last_(std::chrono::steady_clock::now()) {}
  /// Adds the seconds since the last lap to `part` and starts the next.
  void lap(double& part) {
    const auto now = std::chrono::steady_clock::now();
    part += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

private:
  std::chrono::steady_clock::time_point last_;
};

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
  PhaseTimes times;       ///< the seconds of each preparation's parts, summed (and the step's)

  /// Whether the configuration has several velocity fields, and so contact nodes.
  bool has_contact() const { return ops.fields > 1; }
  /// m̃ = Sᵀ diag(M) S of `ops` in its stencil storage (assemble_consistent_mass), assembled on
  /// the first call after each prepare_step.
  const SparseRowMatrix& consistent_mass();
  /// The storage of m̃ as the last assembly left it (its pattern, whether it was reused).
  const ConsistentMass& consistent_mass_storage() const { return mt_; }
  /// The mass operator of an affine transfer at the positions X of the preparation's particles,
  /// in its own stencil storage, assembled on the first call after each prepare_step: m̃_L of the
  /// velocity-gradient transfer (assemble_transfer_mass), or with `weights` (APIC's Ĝ over S's
  /// entries, one array per axis) assemble_affine_mass's m̃_A: whichever the first call after a
  /// prepare_step asks for (a run has one transfer).
  const SparseRowMatrix& transfer_mass(const ConstFieldRef& X,
                                       const std::array<const double*, 3>* weights = nullptr);

  /// Heat transport: the transport operators of the configuration (when prepared with
  /// transport) ...
  TransportOperators transport;
  /// ... and the model's temperature conditions on the transport nodes with capacity, their
  /// values those of the model's conditions (as `bcs`).
  BoundaryConditions temperature_bcs;
  /// Whether the transport operators were prepared.
  bool has_transport() const { return transport_; }
  /// c̃ = Sᵀ diag(𝗖) S on the transport nodes (assemble_consistent_capacity), assembled on the
  /// first call after each prepare_heat_transport.
  const SparseRowMatrix& consistent_capacity();

private:
  friend void prepare_step(const Model& model, Shape shape, StepPreparation& prep, NodeSums* sums);
  friend void prepare_heat_transport(const Model& model, StepPreparation& prep,
                                     TransportUpdate update);
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
/// node boxes allow), the walls' nodes and the contact nodes. What a part of the step adds to
/// the preparation (the transport operators of heat transport) is the part's
/// (StepPart::prepare). Throws NumericalError naming the particle when a particle's support
/// leaves the grid, and InputError when conditions meet at an angle on a node (FMPM 2026
/// Table 2). Across processes (`sums`, fmpm.hpp; prep.ops.node_range Particles): the model holds
/// this process's particles, `sums` is bound to their window and m, the active nodes and m⁻¹
/// are those of the totals over the processes (complete_masses), before the conditions are
/// selected on the active nodes. Collective then.
void prepare_step(const Model& model, Shape shape, StepPreparation& prep, NodeSums* sums = nullptr);

/// Across processes: binds `sums` to the window of `ops` (this process's particles) and makes
/// m the total nodal masses over the processes, the active set and m⁻¹ those of the totals by
/// the serial rule (m^α_i > kMassTolerance max_j Σ_α m^α_j over every node). Collective.
void complete_masses(NodeSums& sums, Operators& ops);

/// Heat transport's share of a step's preparation (the heat part's, parts/heat.cpp), after
/// prepare_step, for the Stepper and for those who read the transport operators without one:
/// the transport operators of the configuration (prepare_transport: every node with capacity
/// active, kMassTolerance for the exact `update`) and the model's temperature conditions on
/// them. Throws InputError when a material cannot carry heat.
void prepare_heat_transport(const Model& model, StepPreparation& prep, TransportUpdate update);

} // namespace smpm
