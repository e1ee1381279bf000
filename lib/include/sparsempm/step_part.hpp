// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file step_part.hpp
/// The parts of a step: what one capability (heat transport, shock physics, plasticity, loads,
/// rigid bodies, the velocity-gradient transfer, contact) adds to the one step, scheme_step.
/// A Stepper holds a list of parts, built once from its options (step_parts); each step it
///   1. lets every part start the particle columns it carries that the model lacks (start),
///   2. prepares the step (prepare_step) and lets every part add its share (prepare),
///   3. lets every part add what it brings to the stages: its operators, its state in the
///      strain update, its stage hooks (begin),
///   4. runs scheme_step, the stages in the order of FMPM 2026 Fig. 1, which calls the parts'
///      hooks at the stage boundaries (StageHooks, scheme.hpp),
///   5. lets every part finish: the motions it imposes, its tallies (end).
/// The linearised step (LinearizedStep, stability.hpp) holds the same list and lets every part
/// add what is linear in the step's state (begin_linearised); the rest is frozen.
/// A part is called once per step on whole fields, never per particle.

#include "sparsempm/particle_columns.hpp"
#include "sparsempm/scheme.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/step_preparation.hpp"

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace smpm {

/// What a part reads and sets before the stages of a step (StepPart::begin).
struct StepStart {
  Model& model;               ///< the model at the step's start, t = model.time
  const StepOptions& options; ///< the Stepper's options
  StepPreparation& prep;      ///< the step's operators, conditions and contact nodes
  StepContext& context;       ///< what the stages read; a part sets its own entries
  ParticleFields& fields;     ///< the particle fields the stages update
  StrainCouplings& strain;    ///< the strain update's states; a part sets its own
  StepBuffers& buffers;       ///< the step's scratch, whose grid fields a part may use
  /// The parts whose hooks the step calls, at the stage boundaries (StepContext::hooks) and in
  /// its strain updates (MaterialStrainUpdate): a part with hooks adds itself (heat, shocks and
  /// plasticity for their strain updates). The linearised step's strain update (its tangents)
  /// calls no strain hook.
  std::vector<StageHooks*>& hooks;
  /// The linearised step's state columns besides V and σ (N × c each): a part whose particles
  /// carry state the step maps adds it in begin_linearised; null in the Stepper.
  std::vector<Field*>* linear_state = nullptr;
};

/// What a part reads and sets after the stages of a step (StepPart::end).
struct StepEnd {
  Model& model;                ///< the model after the stages, its clock still at t
  double dt;                   ///< Δt, the length of the step
  const StepPreparation& prep; ///< the step's preparation
  /// The reaction of each velocity condition of prep.bcs along its direction in the step (the
  /// model's conditions, then the rigid materials' axes: reaction_labels).
  const std::vector<double>& reactions;
  /// The mass Σ m_i on each condition's nodes (every field's block, or its own field's).
  const std::vector<double>& condition_mass;
  /// W(F_p) the strain update stored for the energies; a part that changes what it was
  /// evaluated at empties it (energies are then evaluated anew).
  Eigen::VectorXd& density;
  StepperState& state; ///< the run's tallies, to which a part adds its step's work
};

/// A part of the step (this file's comment). The default hooks do nothing.
class StepPart : public StageHooks {
public:
  /// Before the step is prepared: gives the model's particles the columns this part carries
  /// when they have none yet (their start values).
  virtual void start(Model& /*model*/) {}
  /// After the step's preparation (prepare_step): the part's share of it, the operators and
  /// conditions its capability adds (heat transport's). Called when the configuration is
  /// prepared, by Stepper::step and Stepper::prepare.
  virtual void prepare(const Model& /*model*/, StepPreparation& /*prep*/) {}
  /// Before the stages: the part's operators and fields in the step's context, and its hooks.
  virtual void begin(StepStart& /*step*/) {}
  /// Before the linearised step's stages at its frozen configuration (step.model): what the part
  /// adds that is linear in the step's state, as begin (its operators, hooks and state columns,
  /// StepStart::linear_state). By default nothing: the part's effect is frozen there or drops
  /// out of T (not_linearised).
  virtual void begin_linearised(StepStart& /*step*/) {}
  /// After the stages: the part's own motions and its tallies.
  virtual void end(StepEnd& /*step*/) {}

  /// Why the linearised step (LinearizedStep, stability.hpp) cannot take this part at the frozen
  /// configuration `model`: a sentence for the user; empty when it can. The linearised step maps
  /// (V, σ) (and L_p with the gradient transfer) at that configuration: what a part adds besides
  /// is frozen there (temperatures, internal energies, plastic states: their tangents, tangents)
  /// or, being independent of (V, σ), drops out of T (loads, gravity, the rigid bodies'
  /// prescribed motions, which act through homogeneous conditions). A part refuses only what
  /// switches with the state (contact).
  virtual std::string not_linearised(const Model& /*model*/) const { return {}; }
  /// Why a step across processes (a NodeSums: the Stepper's and the linearised step's) cannot
  /// take this part on `model` (its name, as "<name> yet" ends the message); empty when it can.
  virtual std::string not_distributed(const Model& /*model*/) const { return {}; }
  /// The material tangents 𝕂 = ∂σ/∂L of the linearised step, N × d⁴ in stress_tangent's layout,
  /// which start as those of σ(F) of each particle's material (cauchy_stress): a part whose
  /// particles' stress is another function of their state sets their rows.
  virtual void tangents(const Model& /*model*/, Field& /*K*/) const {}
};

/// One series a part adds to a run file: `/series/NAME`, one value per step (row 0: t = 0),
/// after the run's own series.
struct PartSeries {
  std::string_view name = {};    ///< dataset name in /series
  std::string_view meaning = {}; ///< what it holds, one line (the layout)
  std::string_view needs = {};   ///< the input that brings it (the layout; empty: every run)
};

/// What a part's series are evaluated from: the model after a step, its energies and the run's
/// tallies (the work the parts dissipated since t = 0).
struct SeriesInput {
  const Model& model;        ///< the model after the step
  const Energies& energies;  ///< its energies (Stepper::energies)
  const StepperState& state; ///< the run's tallies after the step (Stepper::state)
};

/// A part as the list of parts knows it: its maker, which returns the part for a Stepper with
/// these options or null when the options leave its capability off, the particle columns it
/// carries (particle_columns.hpp), and its series with the function that gives their values.
struct StepPartEntry {
  std::unique_ptr<StepPart> (*make)(const StepOptions& options) = nullptr; ///< the maker
  std::span<const ParticleColumn> columns = {}; ///< its columns, in their order in frames
  std::span<const PartSeries> series = {};      ///< its series, in their order in run files
  /// The values of `series` after a step, one per series in their order (out.size() ==
  /// series.size()); called once per row, on whole fields.
  void (*series_values)(const SeriesInput& in, std::span<double> out) = nullptr;
};

/// Every part's entry: the library's, then those a program added (register_step_part). The
/// series of a part are known without a Stepper: a run lays out its series before it steps.
std::vector<const StepPartEntry*> step_part_entries();
/// The entries with series of the parts a Stepper with these options holds, in the parts' order.
std::vector<const StepPartEntry*> series_parts(const StepOptions& options);

/// Adds a part to the list of every Stepper made after the call, after the library's own (a
/// program's own capability: its columns in frames, restarts, appends and the Python views,
/// its series in run files and their layout, its answer to the linearised step). Its columns
/// are not members of Particles (ParticleColumn::vector and field null: they live in
/// Particles::columns); their names are new and none of Particles' own (X, V, F, stress, mass,
/// volume0, volume, half_length, material, J, xyz, dim, jacobian), and its series' names are
/// new (UsageError otherwise; a series named like one of the run's own is refused when a run
/// lays out its series). The arrays the entry's spans point to, and their strings, must live as
/// long as the program (constexpr arrays of literals). Call it before the list is first read
/// (by a Stepper, a run, a layout, a particle set, the Python module's import: UsageError
/// after), from one thread.
void register_step_part(const StepPartEntry& entry);

/// The parts a Stepper with these options holds, in the order their hooks run: shocks, heat
/// transport, the gradient transfer, plasticity, loads, rigid bodies, contact (a part whose
/// capability the options leave off is not in the list; a part whose capability the model
/// lacks, e.g. shocks without Mie–Grüneisen materials, does nothing in its step).
std::vector<std::unique_ptr<StepPart>> step_parts(const StepOptions& options);
/// The one rule of a step across processes: throws InputError "<step> across processes does not
/// take <what> yet" naming the first of `parts` that cannot be distributed on `model`
/// (StepPart::not_distributed).
void check_distributed(const std::vector<std::unique_ptr<StepPart>>& parts, const Model& model,
                       std::string_view step);

} // namespace smpm
