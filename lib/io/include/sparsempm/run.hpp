// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file run.hpp
/// Driving a run from its configuration: the time loop (advance), frames, restart, and the
/// file-safety promises of run_file.hpp.

#include "sparsempm/errors.hpp" // Interrupted: a run stopped by a signal (status "interrupted")
#include "sparsempm/input.hpp"
#include "sparsempm/step_preparation.hpp" // PhaseTimes

#include <atomic>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace smpm {

/// How run() runs a configuration: the output path, the run to restart, the interrupt flag.
struct RunOptions {
  /// Output path; empty: cfg.output.file, or for a restart the final path of the restart file.
  std::string output;
  /// Continue the run stored in this file from its last complete frame. A completed run file
  /// is copied to the output's partial run and never modified (nor may it be the output); the
  /// partial run of a stopped run is continued in place (its series rows after that frame are
  /// dropped).
  std::string restart_from;
  /// Replace the partial run of an earlier run of the output path that did not complete (its
  /// frames are lost); without it, such a restart point stops the run before anything is
  /// written (check_run_output).
  bool discard_partial = false;
  /// Set asynchronously to a signal number (SIGINT, SIGTERM): the run stops after the step in
  /// progress with Interrupted.
  const std::atomic<int>* interrupt = nullptr;
};

/// What run() did.
struct RunReport {
  long steps = 0;          ///< steps taken by this invocation
  double wall_seconds = 0; ///< wall time of the time loop
  PhaseTimes times;        ///< where the time loop's wall time went (`smpm run --timings`)
  double energy_start = 0; ///< total energy at t = 0
  double energy_end = 0;   ///< total energy at the end
  int frames = 0;          ///< frames in the file
  std::string output;      ///< the HDF5 file
  /// Heat transport: the lowest and highest particle temperature at the end and the heat
  /// gained, Q(end) − Q(0) (ThermalSums); NaN without transport.
  double temperature_min = std::numeric_limits<double>::quiet_NaN();
  double temperature_max = std::numeric_limits<double>::quiet_NaN(); ///< see temperature_min
  double heat_gained = std::numeric_limits<double>::quiet_NaN();     ///< see temperature_min
};

/// Called after every step with the model and the end time.
using ProgressFn = std::function<void(const Model&, double end)>;

/// Runs `cfg` to cfg.time.end writing frames every cfg.output.every (advance.hpp; Δt from the
/// Courant relation, shortened to land on frames unless time.land_on_frames = false). The
/// output path is checked (check_run_output) and locked before anything is written; frames go
/// to its partial twin, which replaces the output path only when the run completes. Stops with
/// NumericalError (step, time, particle) on NaN, det F ≤ 0, a particle leaving the grid, or
/// total energy above 10× its start (without body forces), with Interrupted on a signal, and
/// with std::runtime_error naming the file and step when a write fails (a full disk): the
/// partial file then keeps every frame completed before and its status says why it stopped.
/// A restart restores the stepper state saved with the frame (periodic FMPM's budget), so it
/// continues bit for bit.
RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress = {});

/// The configuration stored in a run file (its input text and overrides), for --restart.
RunConfig stored_config(const std::string& path);

} // namespace smpm
