#pragma once
/// \file run.hpp
/// Driving a run from its configuration: the time loop, frames, failure checks, restart.

#include "sparsempm/input.hpp"

#include <functional>
#include <string>

namespace smpm {

struct RunOptions {
  std::string output;   ///< output path; empty: cfg.output.file
  bool restart = false; ///< continue the run stored in `output` from its last frame
};

struct RunReport {
  long steps = 0;          ///< steps taken by this invocation
  double wall_seconds = 0; ///< wall time of the time loop
  double energy_start = 0; ///< total energy at t = 0
  double energy_end = 0;   ///< total energy at the end
  int frames = 0;          ///< frames in the file
  std::string output;      ///< the HDF5 file
};

/// Called after every step with the model and the end time.
using ProgressFn = std::function<void(const Model&, double end)>;

/// Runs `cfg` to cfg.time.end writing frames every cfg.output.every. Δt follows FMPM 2026 §3.3
/// and is shortened to land on frame times. Stops with NumericalError (naming step, time and
/// particle) on NaN, det F ≤ 0, a particle leaving the grid, or total energy above 10× its
/// start (without body forces); frames written so far are kept and the file's status says why
/// it stopped. A restart rebuilds the Stepper: periodic FMPM restarts its Courant budget there.
RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress = {});

/// The configuration stored in a run file (its input text and overrides), for --restart.
RunConfig stored_config(const std::string& path);

} // namespace smpm
