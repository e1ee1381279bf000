// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file step.hpp
/// The Stepper, which advances a Model by explicit MPM time steps with the options of
/// step_options.hpp. The stages of the step are written once, in scheme.hpp (scheme_step); the
/// Stepper assembles the operators of the current configuration and calls it.

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/step_options.hpp"
#include "sparsempm/step_preparation.hpp"

#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace smpm {

struct GridState;      // scheme.hpp
struct TransportState; // scheme.hpp
struct StepContext;    // scheme.hpp

/// What a Stepper accumulates over a run besides the model: the state a restart sets back
/// (Stepper::restore) to continue bit for bit.
struct StepperState {
  /// Periodic FMPM: the Courant number accumulated since the last grid-velocity step (§3.3).
  double courant_budget = 0;
  /// Work dissipated since the start of the run by Coulomb friction at contact nodes
  /// (contact_friction_work, the momentum-update correction) ...
  double friction_work = 0;
  /// ... and by the artificial viscosity of Mie–Grüneisen materials (part of their internal
  /// energy U).
  double viscous_work = 0;
  /// ... and by plastic flow (J2 plasticity, plasticity.hpp): Σ Ω_p ‖s‖ Δγ.
  double plastic_work = 0;
};

/// The conditions of Stepper::reactions(), in its order: the labels of Model::bcs, then
/// "<label>.x" (.y, .z) of each rigid material's motion (rigid.hpp).
std::vector<std::string> reaction_labels(const Model& model);

/// Advances a Model by one time step; owns the operators, m̃ and the grid fields and reuses
/// their storage from step to step. A Stepper belongs to one thread at a time: step(), prepare()
/// and advance() throw UsageError when another thread is inside one of them with the same
/// Stepper (a nested call from the same thread, such as advance's observer may make, is allowed).
class Stepper {
public:
  /// Holds the Stepper for the calling thread while it lives (step, prepare and advance take one);
  /// throws UsageError when another thread holds it.
  class Exclusive {
  public:
    /// Takes `stepper` for the calling thread (a nested hold by the thread that holds it takes
    /// nothing); throws UsageError when another thread holds it.
    explicit Exclusive(const Stepper& stepper);
    ~Exclusive();
    Exclusive(const Exclusive&) = delete;
    Exclusive& operator=(const Exclusive&) = delete;

  private:
    const Stepper* held_ = nullptr; // the Stepper to release; null for a nested hold
  };

  /// Validates the options (validate) and makes the exact solver when one is needed.
  explicit Stepper(const StepOptions& options);
  /// The same step across processes (NodeSums, fmpm.hpp; `sums` must outlive the Stepper): the
  /// model of each step holds this process's particles (possibly none), its loads naming them
  /// by their index there (sparsempm::petsc's RankModel does), and the whole grid; the
  /// operators are assembled on the particles' window, every node field the step needs is
  /// completed by `sums` (m and the active nodes, p, f, each m̃ product of the FMPM loop), the
  /// periodic FMPM budget takes the largest Courant number over the processes and reactions()
  /// are the totals over them (each node counted by its owner). The parts that cannot run
  /// across processes are refused (StepPart::not_distributed), as is XPIC; the exact update's
  /// options.exact_solver must solve across the processes. A failure on one process stops every
  /// process at the same step: the others throw FailedElsewhere (errors.hpp). Every call that
  /// steps or prepares is collective.
  Stepper(const StepOptions& options, NodeSums& sums);
  ~Stepper();
  /// Takes over the options, solver, preparation and buffers of a Stepper, which may then only
  /// be destroyed or assigned to.
  Stepper(Stepper&&) noexcept;
  /// Move assignment, as the move constructor.
  Stepper& operator=(Stepper&&) noexcept;

  /// One step of length dt: prepares the step at the current configuration (prepare_step:
  /// S, G, m, the walls' nodes, the contact nodes; then the parts' shares, StepPart::prepare)
  /// unless prepare() did, and runs scheme_step. Throws NumericalError naming the step, time and
  /// particle when the state becomes invalid (a particle leaves the grid, NaN, det F ≤ 0).
  void step(Model& model, double dt);

  /// Prepares the next step from the model's configuration now and returns the preparation (a
  /// frame writer reads the operators and contact nodes of the frame there): the next step() of
  /// this model, at this step and time, uses it instead of preparing again. The particles'
  /// positions, deformation, domains and materials must not change in between. A failure (a
  /// particle's support off the grid) is a NumericalError of the next step.
  const StepPreparation& prepare(const Model& model);

  /// energies(model) after a step, with the strain energy densities W(F_p) its stress update
  /// stored: the same bits without evaluating W again. The particles must be as the last step
  /// left them; when no step has run (or the strain update stored nothing) this is
  /// energies(model).
  Energies energies(const Model& model) const;

  /// The options of every step (validated).
  const StepOptions& options() const { return opt_; }
  /// The operators assembled for the last step (configuration at its start), or for the next one
  /// after prepare(). Their nodes are those of the particles' window of the model's grid,
  /// operators().grid (NodeRange::Particles): node i is node operators().grid.whole_node(i).
  const Operators& operators() const { return prep_.ops; }
  /// The preparation of the last step (or of the next one, after prepare()).
  const StepPreparation& preparation() const { return prep_; }
  /// The wall seconds of each part of the preparations and steps so far (PhaseTimes); a run
  /// driver (advance, run) adds its own parts here.
  PhaseTimes& times() { return prep_.times; }
  /// The wall seconds of each part so far (as the other overload).
  const PhaseTimes& times() const { return prep_.times; }
  /// The grid fields of the last step, on the nodes of its operators (those of operators() until
  /// prepare() prepares the next step); v_plus is the velocity used by the particle update.
  const GridState& grid_state() const;
  /// The transport fields of the last step (heat transport; empty otherwise): τ, the nodal
  /// temperatures, the heat flow q, θ⁺ on the transport nodes of operators().grid.
  const TransportState& transport_state() const;
  /// m̃ of the last step (assembled only when the step used it).
  const ConsistentMass& consistent_mass_storage() const { return prep_.consistent_mass_storage(); }
  /// Whether the last step updated particles from grid velocities (PIC, FMPM, XPIC, exact)
  /// rather than FLIP (false on the FLIP steps of periodic FMPM).
  bool last_step_was_fmpm() const { return grid_update_; }
  /// How the last FMPM loop ended (order reached, metric).
  const FmpmReport& last_fmpm() const;
  /// The convergence metric of each pass ℓ = 2, 3, ... of the last step's last FMPM loop
  /// (dynamic FMPM, FMPM 2026 §3.4 and Fig. 13A; empty without a metric or a loop, as on the
  /// FLIP steps of periodic FMPM). With USL+ and USAVG+ the last loop is that of the
  /// re-extrapolated velocities (task 4.c). With dynamic_limit = 0 the loop runs to the order k
  /// and this is the whole curve.
  const std::vector<double>& last_fmpm_metrics() const;
  /// The state accumulated since the start of the run (or the last restore).
  const StepperState& state() const { return state_; }
  /// Sets the accumulated state back to `state` (a restart, from the frame's RunState).
  void restore(const StepperState& state) { state_ = state; }
  /// Work of Coulomb friction since the start of the run (StepperState::friction_work).
  double friction_work() const { return state_.friction_work; }
  /// Work of the artificial viscosity since the start of the run (StepperState::viscous_work).
  double viscous_work() const { return state_.viscous_work; }
  /// Gives the model's particles the columns the Stepper's parts carry where they have none
  /// yet, with their start values (StepPart::start; every step begins with it): a run calls it
  /// before its first series row and frame.
  void start(Model& model);
  /// Plastic work since the start of the run (StepperState::plastic_work).
  double plastic_work() const { return state_.plastic_work; }
  /// The reaction force of each velocity condition of the model (Model::bcs, in its order, then
  /// the axes of each rigid material: reaction_labels) in the last step: Σ_i n̂ · f^(BC)_i over
  /// the nodes it constrains (every field's block), the force the condition applies along its
  /// direction n̂ (for a rigid body, the force it applies to the material). A node shared by
  /// conditions along the same direction counts in each. Empty before the first step.
  const std::vector<double>& reactions() const { return reactions_; }

private:
  // Whether this step updates the particles from grid velocities (periodic FMPM: the steps
  // that cross the budget C_X); advances the budget.
  bool grid_velocity_step(const Model& model, double dt);
  // prepare_step on the model's configuration, then every part's share (StepPart::prepare).
  void prepare_configuration(const Model& model);
  // Across processes, before a failure leaves a step or a preparation: the others' pending
  // collective call throws FailedElsewhere (nothing to do when the failure came from there).
  void release_others(const std::exception_ptr& failure) const;
  // What the stages of a step of length dt from the model read, before the parts add theirs.
  StepContext stage_context(const Model& model, double dt) const;
  struct Buffers;
  StepOptions opt_;
  std::unique_ptr<MassSolver> solver_;
  NodeSums* sums_ = nullptr; // across processes: the node sums (null: one process)
  StepPreparation prep_;
  // What prepare() prepared: the model, its clock and its particle storage.
  struct Prepared {
    const Model* model = nullptr;
    long step = -1;
    double time = 0;
    Index particles = 0;
    const double* X = nullptr;
    const double* F = nullptr;
    bool operator==(const Prepared&) const = default;
  };
  static Prepared prepared_of(const Model& model);
  Prepared prepared_;
  std::unique_ptr<Buffers> buf_;
  StepperState state_;
  std::vector<double> reactions_; // reactions(): one per velocity condition
  bool grid_update_ = false;
};

} // namespace smpm
