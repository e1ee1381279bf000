// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file petsc_run.hpp
/// Simulations across MPI ranks (the component sparsempm::petsc): each rank's share of a model,
/// the serial Stepper on it with the node sums over the ranks (WindowSums, petsc.hpp), the
/// particles' migration by PETSc's DMSwarm and the whole particle set gathered in global id
/// order.

#include "sparsempm/petsc.hpp"

#include <vector>

namespace smpm::petsc {

/// This rank's share of a model simulated across ranks: the whole model's grid, materials and
/// conditions, the particles whose cell this rank owns (DistributedGrid::owns_cell) and the
/// global id of each (its row in the whole particle set), ascending. The model's loads name this
/// rank's particles (each load's particles that this rank holds, by their index here, with their
/// areas); `loads` keeps them as the whole model names them, and every migration names them
/// again.
struct RankModel {
  Model model;                     ///< this rank's particles on the whole grid
  std::vector<Index> ids;          ///< the global id of each of model.particles, ascending
  Index total = 0;                 ///< particles over every rank
  std::vector<ParticleLoad> loads; ///< the whole model's loads (global ids)
};

/// Each rank's share of `whole` (the same model on every rank). Collective.
RankModel distribute(const DistributedGrid& grid, const Model& whole);

/// Moves every particle whose cell another rank owns to that rank, with every column it
/// carries (X, V, F, σ, mass, volume0, material, half-lengths, the parts' columns: energies,
/// temperatures, heat sources, velocity gradients, the plastic state) and its global id, by
/// PETSc's DMSwarm (type basic: each leaving particle is one point whose DMSwarm_rank is the
/// owner of its cell, sent by DMSwarmMigrate to any rank, not only a neighbour); the particles
/// then stand in ascending global id. `sums` makes the reductions (NodeSums::sum), so that a
/// failure on another rank is met here. Returns the particles that moved over every rank; adds
/// the bytes of the particles this rank sent and received to `bytes` when given. Collective.
Index migrate(const DistributedGrid& grid, const NodeSums& sums, RankModel& local,
              double* bytes = nullptr);

/// The whole particle set on rank 0, in global id order (the serial run's), every column any
/// rank's particles carry; empty on the other ranks. By a PETSc Vec of the particles' values
/// in global id order and VecScatterCreateToZero. Collective.
Particles gather_particles(const DistributedGrid& grid, const RankModel& local);

/// The serial Stepper on each rank's share of a model across ranks (the Stepper's constructor
/// with NodeSums: the same step, its node sums completed by WindowSums over `grid`), followed by
/// the migration of the particles that left their rank's cells. FLIP, PIC, FMPM(k) (plain,
/// blended, periodic, dynamic) and the exact update with USL, USF, USL+ and USAVG(+), in single
/// material mode, with
/// the parts that declare themselves distributable (StepPart::not_distributed).
class DistributedStepper {
public:
  /// The step of `options` on `grid` (which must outlive this); the exact update solves with
  /// `exact` (step_mass_solver_factory, in place of options.exact_solver). Collective.
  DistributedStepper(const DistributedGrid& grid, const StepOptions& options,
                     ExactMethod exact = ExactMethod::CgBlockJacobiIcc);
  /// One step of length dt of every rank's particles, then migrate(); returns the particles that
  /// moved to another rank. Throws the Stepper's NumericalError on the rank whose step failed,
  /// each "particle <p>" of its message naming the particle's global id as the serial run
  /// would, and FailedElsewhere on the others. Collective.
  Index step(RankModel& local, double dt);
  /// Δt = C Δx_min / max(c_wave, max_p |V_p|) over every rank (stable_time_step). Collective.
  double stable_time_step(const RankModel& local, double courant) const;
  /// The energies of the whole particle set: sums over the ranks, the largest speed over them.
  /// Collective.
  Energies energies(const RankModel& local) const;
  /// The run's tallies (Stepper::state): the work of friction, artificial viscosity and plastic
  /// flow summed over the ranks. Collective.
  StepperState state() const;
  /// The reactions of the last step, totals over the ranks (Stepper::reactions).
  const std::vector<double>& reactions() const { return stepper_.reactions(); }
  /// This rank's Stepper.
  const Stepper& stepper() const { return stepper_; }
  /// The bytes this rank sent and received so far: the node sums' scatters
  /// (WindowSums::communicated_bytes) and the particles it sent and received in migrations.
  double communicated_bytes() const { return sums_.communicated_bytes() + migrated_bytes_; }
  /// The node sums of the steps.
  const WindowSums& sums() const { return sums_; }

private:
  const DistributedGrid& grid_;
  WindowSums sums_;
  Stepper stepper_;
  double migrated_bytes_ = 0;
  Index moved_ = 0; // the particles the last step's migration moved
};

} // namespace smpm::petsc
