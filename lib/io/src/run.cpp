#include "sparsempm/run.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/output.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

namespace smpm {

RunConfig stored_config(const std::string& path) {
  const StoredRun stored = read_stored_run(path);
  return read_input(stored.input, path + " (stored input)", stored.overrides);
}

namespace {
void check_energy(const Energies& e, double e0, const Model& model) {
  if (!std::isfinite(e.total))
    throw at_step(NumericalError("total energy is not finite"), model.step, model.time);
  // Kinetic + strain energy is conserved only without body forces (gravity does work), so the
  // blow-up test applies to runs without them.
  const bool loaded =
      model.body_force[0] != 0 || model.body_force[1] != 0 || model.body_force[2] != 0;
  if (!loaded && e0 > 0 && e.total > 10 * e0) {
    const Particles& P = model.particles;
    Index fastest = 0;
    P.V.rowwise().squaredNorm().maxCoeff(&fastest);
    std::ostringstream os;
    os << "total energy " << e.total << " exceeds 10 times its start " << e0
       << " (unstable; fastest particle " << fastest << " at (";
    for (int a = 0; a < P.dim; ++a)
      os << (a ? ", " : "") << P.X(fastest, a);
    os << ") with speed " << P.V.row(fastest).norm() << ")";
    throw at_step(NumericalError(os.str()), model.step, model.time);
  }
}
} // namespace

RunReport run(RunConfig& cfg, const RunOptions& options, const ProgressFn& progress) {
  const std::string path = options.output.empty() ? cfg.output.file : options.output;
  Model& model = cfg.model;
  int next_frame = 0;
  double e0 = 0;
  OutputFile out = [&] {
    if (options.restart) {
      const StoredRun stored = read_stored_run(path);
      e0 = stored.series.empty() ? energies(model).total : stored.series.front().e.total;
      return OutputFile::reopen(path, cfg, next_frame);
    }
    return OutputFile(path, cfg);
  }();
  if (!options.restart) {
    const Energies e = energies(model);
    e0 = e.total;
    out.add_series({model.step, model.time, e});
    out.write_frame(next_frame++, model, cfg.step.shape, cfg.output.matrices);
  }
  Stepper stepper(cfg.step);
  const double end = cfg.time.end, every = cfg.output.every;
  const double eps = 1e-12 * std::max(end, every);
  RunReport report;
  report.energy_start = e0;
  report.output = path;
  const auto start = std::chrono::steady_clock::now();
  try {
    while (model.time < end - eps) {
      const double t_frame = std::min(next_frame * every, end);
      const double dt = std::min(stable_time_step(model, cfg.time.courant), t_frame - model.time);
      stepper.step(model, dt);
      ++report.steps;
      const Energies e = energies(model);
      out.add_series({model.step, model.time, e});
      check_energy(e, e0, model);
      if (model.time >= t_frame - eps)
        out.write_frame(next_frame++, model, cfg.step.shape, cfg.output.matrices);
      if (progress)
        progress(model, end);
    }
  } catch (const std::exception& e) {
    out.set_status(std::string("failed: ") + e.what());
    throw;
  }
  out.set_status("completed");
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.energy_end = energies(model).total;
  report.frames = next_frame;
  return report;
}

} // namespace smpm
