#include "sparsempm/run.hpp"

#include "sparsempm/advance.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/output.hpp"

#include <optional>

namespace smpm {

RunConfig stored_config(const std::string& path) {
  const StoredRun stored = read_stored_run(path);
  return read_input(stored.input, path + " (stored input)", stored.overrides);
}

RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress) {
  const std::string path = options.output.empty() ? cfg.output.file : options.output;
  Model& model = cfg.model;
  int next_frame = 0;
  std::optional<double> e0;
  OutputFile out = [&] {
    if (options.restart) {
      const StoredRun stored = read_stored_run(path);
      if (!stored.series.empty())
        e0 = stored.series.front().e.total;
      return OutputFile::reopen(path, cfg, next_frame);
    }
    return OutputFile(path, cfg);
  }();
  if (!options.restart) {
    out.add_series({model.step, model.time, energies(model)});
    out.write_frame(next_frame++, model, cfg.step.shape, cfg.output.matrices);
  }
  Stepper stepper(cfg.step);
  AdvanceOptions adv{.end = cfg.time.end,
                     .courant = cfg.time.courant,
                     .stop_every = cfg.output.every,
                     .land_on_stops = cfg.time.land_on_frames,
                     .failure = {},
                     .energy_start = e0};
  RunReport report;
  report.output = path;
  try {
    const AdvanceReport r =
        advance(model, stepper, adv, [&](const Model& m, const Energies& e, bool at_stop) {
          out.add_series({m.step, m.time, e});
          if (at_stop)
            out.write_frame(next_frame++, m, cfg.step.shape, cfg.output.matrices);
          if (progress)
            progress(m, cfg.time.end);
        });
    report.steps = r.steps;
    report.wall_seconds = r.wall_seconds;
    report.energy_start = r.energy_start;
    report.energy_end = r.energy_end;
  } catch (const std::exception& e) {
    out.set_status(std::string("failed: ") + e.what());
    throw;
  }
  out.set_status("completed");
  report.frames = next_frame;
  return report;
}

} // namespace smpm
