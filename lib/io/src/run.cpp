#include "sparsempm/run.hpp"

#include "sparsempm/advance.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/output.hpp"
#include "sparsempm/run_file.hpp"

#include <cmath>
#include <csignal>
#include <filesystem>
#include <optional>
#include <sys/stat.h>

namespace smpm {

namespace {
const char* signal_name(int s) {
  return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal";
}

// The partial file of a fresh run, or a copy of the restart file continued from its last
// complete frame (the restart file itself is never written). Sets next_frame and e0.
OutputFile open_partial(RunConfig& cfg, const RunOptions& options, const std::string& partial,
                        int& next_frame, std::optional<double>& e0) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // In place only when the partial name is the restart file itself, not a link to it (a
  // symbolic or a second hard link to a completed run, which must stay as it is).
  struct stat named {};
  const bool in_place =
      !options.restart_from.empty() && fs::equivalent(options.restart_from, partial, ec) &&
      ::lstat(partial.c_str(), &named) == 0 && S_ISREG(named.st_mode) && named.st_nlink == 1;
  std::optional<StoredRun> stored;
  if (!options.restart_from.empty()) {
    stored = read_stored_run(options.restart_from);
    if (stored->frame_times.empty())
      throw InputError(options.restart_from + ": no complete frame to restart from");
    if (!stored->series.empty())
      e0 = stored->series.front().e.total;
  }
  // A partial file that check_run_output let through (a failed run's) is replaced, never
  // written through: a link at its name leaves the file it points to as it was.
  if (!in_place)
    fs::remove(partial, ec);
  if (!stored)
    return OutputFile(partial, cfg);
  if (!in_place) {
    std::filesystem::copy_file(options.restart_from, partial,
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec)
      throw InputError(partial + ": cannot copy the restart file " + options.restart_from +
                       " there (" + ec.message() + ")");
  }
  return OutputFile::reopen(partial, cfg, next_frame);
}
} // namespace

RunConfig stored_config(const std::string& path) {
  check_regular_file(path, kMaxRunFileBytes, "run file");
  const StoredRun stored = read_stored_run(path);
  return read_input(stored.input, path + " (stored input)", stored.overrides);
}

RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress) {
  const bool restart = !options.restart_from.empty();
  const std::string target = !options.output.empty() ? options.output
                             : restart               ? final_path(options.restart_from)
                                                     : cfg.output.file;
  if (restart)
    check_regular_file(options.restart_from, kMaxRunFileBytes, "run file");
  check_run_output(target, restart ? std::string() : cfg.source, "-o", options.restart_from);
  const OutputLock lock(target); // a second run on this path stops here, before any write
  const std::string partial = partial_path(target);
  Model& model = cfg.model;
  int next_frame = 0;
  std::optional<double> e0;
  OutputFile out = open_partial(cfg, options, partial, next_frame, e0);
  Stepper stepper(cfg.step);
  // The velocity error of FMPM 2026 §3.1 against the velocities at t = 0 (frame 0), with its
  // running sum continued across a restart.
  Field V0 = model.particles.V;
  double change_sum = 0;
  if (restart) {
    stepper.set_courant_budget(stored_courant_budget(partial, next_frame - 1));
    Model first = model;
    load_frame(partial, 0, first);
    V0 = first.particles.V;
    const StoredRun kept = read_stored_run(partial);
    if (!kept.series.empty() && std::isfinite(kept.series.back().velocity_change_sum))
      change_sum = kept.series.back().velocity_change_sum;
    if (!kept.series.empty() && std::isfinite(kept.series.back().friction) &&
        std::isfinite(kept.series.back().viscous))
      stepper.set_dissipation(kept.series.back().friction, kept.series.back().viscous);
  }
  auto row = [&](const Model& m, const Energies& e) {
    SeriesRow r;
    r.step = m.step;
    r.t = m.time;
    r.e = e;
    material_sums(m, r.materials);
    const Index N = m.particles.size();
    r.velocity_change = N && V0.rows() == N
                            ? std::sqrt((m.particles.V - V0).rowwise().squaredNorm().sum() / N)
                            : 0.0;
    if (m.step > 0)
      change_sum += r.velocity_change;
    r.velocity_change_sum = change_sum;
    r.friction = stepper.friction_work();
    r.viscous = stepper.viscous_work();
    r.fmpm_order = m.step > 0 && stepper.last_step_was_fmpm() &&
                           stepper.options().velocity == VelocityUpdate::FMPM
                       ? stepper.last_fmpm().order
                       : 0;
    return r;
  };
  // A frame, with the step it belongs to named when the write fails (a full disk). Its grid
  // fields come from the preparation of the step that starts there (which that step then
  // uses); a failure to prepare it (a particle's support off the grid) is that step's.
  auto frame = [&](const Model& m) {
    const StepPreparation& next = stepper.prepare(m);
    out.set_stepper_state(stepper.courant_budget());
    try {
      out.write_frame(next_frame++, m, cfg.step.shape, cfg.output.matrices, &next);
    } catch (const std::runtime_error& w) {
      throw std::runtime_error(partial + ": writing the frame of step " + std::to_string(m.step) +
                               " (t = " + std::to_string(m.time) + ") failed: " + w.what() +
                               " (is the disk full?)");
    }
  };
  const AdvanceOptions adv{.end = cfg.time.end,
                           .courant = cfg.time.courant,
                           .stop_every = cfg.output.every,
                           .land_on_stops = cfg.time.land_on_frames,
                           .failure = {},
                           .energy_start = e0};
  RunReport report;
  try {
    if (!restart) {
      out.add_series(row(model, energies(model)));
      frame(model);
    }
    const AdvanceReport r =
        advance(model, stepper, adv, [&](const Model& m, const Energies& e, bool at_stop) {
          out.add_series(row(m, e));
          if (at_stop)
            frame(m);
          if (progress)
            progress(m, cfg.time.end);
          if (options.interrupt && options.interrupt->load() != 0) {
            const int s = options.interrupt->load();
            throw Interrupted(s, std::string("interrupted by ") + signal_name(s) + " after step " +
                                     std::to_string(m.step) + " (t = " + std::to_string(m.time) +
                                     "); the frames so far are in " + partial);
          }
        });
    report.steps = r.steps;
    report.wall_seconds = r.wall_seconds;
    report.energy_start = r.energy_start;
    report.energy_end = r.energy_end;
  } catch (const Interrupted& e) {
    out.set_status(std::string("interrupted: ") + e.what());
    throw;
  } catch (const InputError& e) {
    // A condition of the input that fails only at a later step (a moving wall reaching a
    // fixed plane at an angle): the run has started and its frames are kept, so it is a
    // failure of that step, not a refused input.
    const std::string what = "step " + std::to_string(model.step + 1) +
                             " (from t = " + std::to_string(model.time) + "): " + e.what() +
                             "; the frames so far are in " + partial;
    out.set_status("failed: " + what);
    throw std::runtime_error(what);
  } catch (const std::exception& e) {
    out.set_status(std::string("failed: ") + e.what());
    throw;
  }
  try {
    out.finish(target);
  } catch (const std::exception& e) {
    throw std::runtime_error(partial +
                             ": the run completed but its file could not be closed and "
                             "moved to " +
                             target + ": " + e.what());
  }
  report.output = target;
  report.frames = next_frame;
  return report;
}

} // namespace smpm
