// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file advance.hpp
/// The run loop and its criteria: the failure test and advance(), which steps a Model to an end
/// time with the time step of the Courant relation (diagnostics.hpp). `smpm run`, the simulation
/// C* of the stability study, the examples and the tests all run through advance().

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/step.hpp"

#include <functional>
#include <optional>

namespace smpm {

/// When a run has failed, besides the NumericalError the stages throw (NaN, det F ≤ 0, a
/// particle leaving the grid).
struct FailureTest {
  /// Fail when the total energy exceeds energy_growth × its start (≤ 0: never). Not applied
  /// under body forces or driven velocity BCs (values or moving walls), which do work on the
  /// particles.
  double energy_growth = 10;
  /// Fail when the Courant time step falls below this fraction of the first step's (≤ 0:
  /// never): the signal speed has grown a thousandfold, as when a Mie–Grüneisen particle nears
  /// its limit of compression 1 − J = 1/S₁, and the run would creep on without end.
  double min_time_step_fraction = 1e-3;
};

/// Throws NumericalError naming the step, time and fastest particle when the total energy `e`
/// is not finite or exceeds test.energy_growth × e0.
void check_energy(const Model& model, double e, double e0, const FailureTest& test);

/// How advance() runs: the end time, the Courant number of every step, the stops (output
/// frames) and the failure test.
struct AdvanceOptions {
  double end = 0;       ///< simulated end time
  double courant = 0.5; ///< C of stable_time_step, evaluated before every step
  /// With heat transport (the stepper's options), no step is longer than F Δx_min² / D_max, the
  /// Fourier number F of conduction (diffusion_time); 0: default_fourier(d).
  double fourier = 0;
  /// The most steps a run may take: a run from step 0 whose first time step implies more (to
  /// `end`, with a step more per stop it lands on) throws InputError naming the limit that sets
  /// it (check_step_count). A time step that collapses later is FailureTest's.
  long max_steps = 10'000'000;
  /// > 0: report a stop at every multiple of this time (output frames); the observer is told
  /// which steps reach one.
  double stop_every = 0;
  /// Shorten the step before each stop and the last step so that they end exactly on it.
  /// false: every step has the Courant time step (a stability run: stops do not change the
  /// dynamics), a stop is reported at the first step that reaches it, and the run ends at the
  /// first step at or past `end`.
  bool land_on_stops = true;
  FailureTest failure{}; ///< when the run has failed
  /// The total energy the failure test compares with; unset: that of the model on entry (a
  /// restart passes the energy at t = 0).
  std::optional<double> energy_start{};
  /// The Courant time step failure.min_time_step_fraction compares with; unset: that of the
  /// first step of this call (a restart passes the first step's of t = 0).
  std::optional<double> time_step_start{};
  /// The observer may change the model (Python's callback gets it mutable): the signal speed of
  /// the next step is then taken from the model after the observer, not from the step's energies.
  bool observer_changes_model = false;
  /// Set asynchronously to a signal's number (SIGINT, SIGTERM): the run stops after the step in
  /// progress (and its observer) with Interrupted.
  const std::atomic<int>* interrupt = nullptr;
};

/// Called after every step with the model, its total energy and whether the step reached a stop.
using StepObserver = std::function<void(const Model&, const Energies&, bool at_stop)>;

/// What advance() did.
struct AdvanceReport {
  long steps = 0;          ///< steps taken
  double energy_start = 0; ///< total energy the failure test compared with
  double energy_end = 0;   ///< total energy at the end
  double wall_seconds = 0; ///< wall time of the loop
  PhaseTimes times;        ///< where the loop's wall time went (Stepper::times in the loop)
};

/// Throws InputError when the first time step of advance() from `model` at step 0 (the Courant
/// limit and, with `transport`, the conduction limit of `options`) implies more than
/// options.max_steps steps to options.end, naming the limit that sets it and the Δt.
void check_step_count(const Model& model, const AdvanceOptions& options, bool transport);

/// Steps `model` with `stepper` until options.end (see AdvanceOptions), testing the energy
/// after every step. Throws InputError for bad options and NumericalError on failure (the model
/// is left at the failing step).
AdvanceReport advance(Model& model, Stepper& stepper, const AdvanceOptions& options,
                      const StepObserver& observer = {});

} // namespace smpm
