// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/run.hpp"

#include "sparsempm/advance.hpp"
#include "sparsempm/diagnostics.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/output.hpp"
#include "sparsempm/run_file.hpp"
#include "sparsempm/step_part.hpp"
#include "sparsempm/transport.hpp"

#include <cmath>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace smpm {

namespace {
// The partial run of a fresh run, or the restart file's frames continued from its last
// complete frame (the restart file itself is written only when it is the partial run, continued
// in place). Sets next_frame and e0.
OutputFile open_partial(RunConfig& cfg, const RunOptions& options, const std::string& partial,
                        int& next_frame, std::optional<double>& e0) {
  if (options.restart_from.empty())
    return OutputFile(partial, cfg);
  OutputFile out = OutputFile::reopen(partial, options.restart_from, cfg, next_frame);
  const StoredRun stored = read_stored_run(partial);
  if (!stored.series.empty())
    e0 = stored.series.front().e.total;
  return out;
}
} // namespace

RunConfig stored_config(const std::string& path) {
  check_regular_file(path, kMaxRunFileBytes, "run file");
  const StoredRun stored = read_stored_run(path);
  // An image body's file is looked for beside the input the run was given (as its name
  // resolves from here), then beside the run file.
  std::vector<std::string> dirs;
  if (!stored.source.empty())
    dirs.push_back(std::filesystem::path(stored.source).parent_path().string());
  return read_input(stored.input, path + " (stored input)", stored.overrides, dirs);
}

namespace {

// One invocation of `smpm run`: the partial file, the Stepper, the series rows and frames, and
// the restart state they carry.
class Run {
public:
  Run(RunConfig& cfg, const RunOptions& options, std::string partial)
      : cfg_(cfg), options_(options), partial_(std::move(partial)),
        out_(open_partial(cfg, options, partial_, next_frame_, e0_)), stepper_(cfg.step),
        V0_(cfg.model.particles.V) {
    if (restarting()) {
      restore();
      return;
    }
    stepper_.start(cfg.model); // the parts' columns in the first row and frame
    if (heat(cfg.model))
      thermal0_ = thermal_sums(cfg.model, energies(cfg.model).strain);
  }

  // The thermal sums at t = 0 (heat transport), for the heat gained; null without transport.
  const ThermalSums* thermal_start() const { return thermal0_ ? &*thermal0_ : nullptr; }

  bool restarting() const { return !options_.restart_from.empty(); }

  // The time loop (advance) with a series row after every step and a frame at every stop.
  AdvanceReport advance_to_end(const ProgressFn& progress) {
    if (!restarting()) {
      out_.add_series(row(cfg_.model, energies(cfg_.model)));
      frame(cfg_.model);
    }
    const AdvanceOptions adv{.end = cfg_.time.end,
                             .courant = cfg_.time.courant,
                             .fourier = cfg_.time.fourier,
                             .max_steps = cfg_.time.max_steps,
                             .stop_every = cfg_.output.every,
                             .land_on_stops = cfg_.time.land_on_frames,
                             .failure = {},
                             .energy_start = e0_,
                             .time_step_start = dt0_};
    return advance(cfg_.model, stepper_, adv, [&](const Model& m, const Energies& e, bool at_stop) {
      PhaseClock clock;
      out_.add_series(row(m, e));
      clock.lap(stepper_.times().series);
      if (at_stop) {
        const PhaseTimes before = stepper_.times();
        frame(m); // its preparation is the next step's: the frame's own time is the rest
        PhaseTimes& t = stepper_.times();
        clock.lap(t.frames);
        t.frames -= (t.total() - t.frames) - (before.total() - before.frames);
      }
      if (progress)
        progress(m, cfg_.time.end);
      check_interrupt(m);
    });
  }

  OutputFile& out() { return out_; }
  int frames() const { return next_frame_; }

private:
  // The state of the frame restarted from (RunState), and the velocities at t = 0 of frame 0.
  void restore() {
    const RunState state = read_run_state(partial_, next_frame_ - 1);
    stepper_.restore(state.stepper);
    change_sum_ = state.velocity_change_sum;
    Model first = cfg_.model;
    load_frame(partial_, 0, first);
    V0_ = first.particles.V;
    if (heat(first))
      thermal0_ = thermal_sums(first, energies(first).strain);
    // The first step's Courant time step, as the uninterrupted run's advance took it.
    dt0_ = stable_time_step(first, cfg_.time.courant, signal_speed(first));
  }

  // The series row of the model after a step: energies, the velocity error of FMPM 2026 §3.1
  // against the velocities at t = 0 and its running sum, dissipation, the FMPM order reached.
  SeriesRow row(const Model& m, const Energies& e) {
    SeriesRow r;
    r.step = m.step;
    r.t = m.time;
    r.e = e;
    material_sums(m, r.materials);
    const Index N = m.particles.size();
    r.velocity_change = N && V0_.rows() == N ? velocity_change(m.particles, V0_) : 0.0;
    if (m.step > 0)
      change_sum_ += r.velocity_change;
    r.velocity_change_sum = change_sum_;
    for (const StepPartEntry* part : series_) { // the parts' own
      r.parts.resize(r.parts.size() + part->series.size());
      part->series_values({m, e, stepper_.state()}, std::span(r.parts).last(part->series.size()));
    }
    r.reactions.assign(reaction_labels(m).size(), 0.0);
    if (m.step > 0 && stepper_.reactions().size() == r.reactions.size())
      r.reactions = stepper_.reactions();
    r.fmpm_order = m.step > 0 && stepper_.last_step_was_fmpm() &&
                           stepper_.options().velocity == VelocityUpdate::FMPM
                       ? stepper_.last_fmpm().order
                       : 0;
    return r;
  }

  // A frame, with the step it belongs to named when the write fails (a full disk). Its grid
  // fields come from the preparation of the step that starts there (which that step then
  // uses); a failure to prepare it (a particle's support off the grid) is that step's.
  void frame(const Model& m) {
    const StepPreparation& next = stepper_.prepare(m);
    out_.set_run_state({.stepper = stepper_.state(), .velocity_change_sum = change_sum_});
    try {
      out_.write_frame(next_frame_, m, cfg_.step.shape, cfg_.output.matrices, &next);
      ++next_frame_;
    } catch (const std::runtime_error& w) {
      const bool first = next_frame_ == 0; // nothing to keep: no file is left behind
      if (first)
        out_.discard();
      throw std::runtime_error(partial_ + ": writing the frame of step " + std::to_string(m.step) +
                               " (t = " + number_text(m.time) + ") failed: " + w.what() +
                               (first ? " (is the disk full?); no frame was written, so no file "
                                        "is kept"
                                      : " (is the disk full?); the frames before it are kept"));
    }
  }

  void check_interrupt(const Model& m) const {
    smpm::check_interrupt(options_.interrupt, [&] {
      return "after step " + std::to_string(m.step) + " (t = " + number_text(m.time) +
             "); the frames so far are in " + partial_;
    });
  }

  RunConfig& cfg_;
  const RunOptions& options_;
  std::string partial_;
  int next_frame_ = 0;
  std::optional<double> e0_;
  std::optional<ThermalSums> thermal0_;
  bool heat(const Model& m) const {
    return cfg_.step.transport.update != TransportUpdate::Off &&
           m.particles.temperature.size() == m.particles.size();
  }
  std::optional<double> dt0_; // a restart: the first step's Courant time step (t = 0)
  OutputFile out_;
  Stepper stepper_;
  Field V0_;
  double change_sum_ = 0;
  std::vector<const StepPartEntry*> series_ = series_parts(stepper_.options());
};

// The run file a run writes: -o, else a restart's final file, else the input's output.file. A
// restart never writes the run file it continues.
std::string run_target(const RunConfig& cfg, const RunOptions& options) {
  const bool restart = !options.restart_from.empty();
  const std::string target = !options.output.empty() ? options.output
                             : restart               ? final_path(options.restart_from)
                                                     : cfg.output.file;
  if (restart) {
    check_regular_file(options.restart_from, kMaxRunFileBytes, "run file");
    std::error_code ec;
    if (std::filesystem::equivalent(target, options.restart_from, ec))
      throw InputError("-o " + target +
                       ": is the run file the restart continues, which a restart "
                       "never writes; give another -o");
  }
  return target;
}

// A run that would not end (a Δt far too small) is refused before any write.
void check_steps(const RunConfig& cfg) {
  try {
    check_step_count(cfg.model,
                     {.end = cfg.time.end,
                      .courant = cfg.time.courant,
                      .fourier = cfg.time.fourier,
                      .max_steps = cfg.time.max_steps,
                      .stop_every = cfg.output.every,
                      .land_on_stops = cfg.time.land_on_frames},
                     cfg.step.transport.update != TransportUpdate::Off);
  } catch (const InputError& e) {
    throw InputError(cfg.source + ": " + e.what());
  }
}

// Held temperatures the shape functions cannot hold (held_temperature_refusal) are refused
// before any write; the stability analyses, which run no simulation, take them.
void check_held_temperatures(const RunConfig& cfg) {
  const auto& held = cfg.model.temperature_bcs.conditions;
  if (cfg.step.transport.update != TransportUpdate::Off && !held.empty())
    if (const std::string why = held_temperature_refusal(cfg.step.shape); !why.empty())
      throw InputError(cfg.source + ": " + held[0].label + ": " + why);
}

// The time loop of the run to its end, and its report; a loop that stops leaves its reason as
// the run file's status.
RunReport advance_run(Run& r, RunConfig& cfg, const ProgressFn& progress,
                      const std::string& partial) {
  RunReport report;
  try {
    const AdvanceReport a = r.advance_to_end(progress);
    report.steps = a.steps;
    report.wall_seconds = a.wall_seconds;
    report.energy_start = a.energy_start;
    report.energy_end = a.energy_end;
    report.times = a.times;
    if (const ThermalSums* t = r.thermal_start(); t && cfg.model.particles.temperature.size()) {
      const ThermalSums end = thermal_sums(cfg.model, energies(cfg.model).strain);
      report.temperature_min = end.temperature_min;
      report.temperature_max = end.temperature_max;
      report.heat_gained = end.heat - t->heat;
    }
  } catch (const Interrupted& e) {
    r.out().set_status(std::string("interrupted: ") + e.what());
    throw;
  } catch (const InputError& e) {
    // A condition of the input that fails only at a later step (a moving wall reaching a
    // fixed plane at an angle): the run has started and its frames are kept, so it is a
    // failure of that step, not a refused input.
    const std::string what = "step " + std::to_string(cfg.model.step + 1) +
                             " (from t = " + number_text(cfg.model.time) + "): " + e.what() +
                             "; the frames so far are in " + partial;
    r.out().set_status("failed: " + what);
    throw std::runtime_error(what);
  } catch (const std::exception& e) {
    r.out().set_status(std::string("failed: ") + e.what());
    throw;
  }
  return report;
}

} // namespace

RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress) {
  const bool restart = !options.restart_from.empty();
  const std::string target = run_target(cfg, options);
  // The option that named the path: -o, or the input's output.file.
  const std::string option = options.output.empty() && !restart ? "output.file" : "-o";
  check_run_output(target, restart ? std::string() : cfg.source, option, options.restart_from,
                   options.discard_partial);
  if (!restart) {
    check_steps(cfg);
    check_held_temperatures(cfg);
  }
  const OutputLock lock(target); // a second run on this path stops here, before any write
  // Again under the lock: a run of this path that stopped between the check and the lock left
  // a restart point the first check could not see.
  check_run_output(target, restart ? std::string() : cfg.source, option, options.restart_from,
                   options.discard_partial, true);
  const std::string partial = partial_path(target);
  Run r(cfg, options, partial);
  RunReport report = advance_run(r, cfg, progress, partial);
  try {
    r.out().finish(target);
  } catch (const std::exception& e) {
    throw std::runtime_error(partial +
                             ": the run completed but its file could not be closed and "
                             "moved to " +
                             target + ": " + e.what());
  }
  report.output = target;
  report.frames = r.frames();
  return report;
}

} // namespace smpm
