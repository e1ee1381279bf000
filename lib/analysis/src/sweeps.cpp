// SPDX-License-Identifier: BSD-3-Clause
// The spectral C* over configurations (lattice shifts, frames of a run) for families of step
// options, on every core (FMPM 2026 §3.3, Fig. 12A: the minimum over configurations).

#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/threads.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>

namespace smpm {

Model shifted(const Model& model, const std::array<double, 3>& shift) {
  Model m = model;
  for (int a = 0; a < m.grid.dim(); ++a)
    m.particles.X.col(a).array() += shift[size_t(a)] * m.grid.cell_size(a);
  Operators ops; // throws if a particle left the grid
  ops.node_range = NodeRange::Particles;
  assemble(m.grid, m.particles, Shape::Linear, ops);
  return m;
}

std::vector<LatticeShift> lattice_shifts(const Model& model, int shifts) {
  if (shifts < 1 || shifts > kMaxLatticeShifts)
    throw InputError("the number of lattice shifts must be 1 to " +
                     std::to_string(kMaxLatticeShifts) + ", got " + std::to_string(shifts));
  // The lattice repeats itself after one particle spacing 2 r⁰: shifts j/shifts of it (in cells
  // along each axis) reach every distinct position of the lattice relative to the grid.
  std::array<double, 3> period{0, 0, 0};
  for (int a = 0; a < model.grid.dim(); ++a)
    period[size_t(a)] = model.particles.size()
                            ? 2 * model.particles.half_length(0, a) / model.grid.cell_size(a)
                            : 1.0;
  std::vector<LatticeShift> out;
  for (int j = 0; j < shifts; ++j) {
    const double f = double(j) / shifts;
    LatticeShift s;
    s.cells = {f * period[0], f * period[1], f * period[2]};
    std::ostringstream name;
    name << "shift " << s.cells[0];
    s.name = name.str();
    out.push_back(s);
  }
  return out;
}

std::vector<Configuration> lattice_configurations(const Model& model, int shifts) {
  std::vector<Configuration> out;
  for (const LatticeShift& s : lattice_shifts(model, shifts))
    out.push_back({shifted(model, s.cells), s.name});
  return out;
}

void run_tasks(size_t count, const std::function<void(size_t)>& task, int workers) {
  const size_t n = std::min(count, size_t(workers > 0 ? workers : threads()));
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex guard;
  std::exception_ptr failure;
  auto worker = [&] {
    set_threads(1);
    for (size_t i; !stop && (i = next++) < count;) {
      try {
        task(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(guard);
        if (!failure)
          failure = std::current_exception();
        stop = true;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t w = 0; w < n; ++w)
    pool.emplace_back(worker);
  for (std::thread& t : pool)
    t.join();
  if (failure)
    std::rethrow_exception(failure);
}

std::vector<std::vector<ConfigurationSweep>>
sweep_configurations(const std::vector<Configuration>& configurations,
                     const std::vector<CourantSeries>& series, const CriticalSearch& search,
                     int workers) {
  const size_t nc = configurations.size();
  // c[s][i][f]: option i of series s at configuration f.
  std::vector<std::vector<std::vector<CriticalCourant>>> c(series.size());
  for (size_t s = 0; s < series.size(); ++s)
    c[s].assign(series[s].options.size(), std::vector<CriticalCourant>(nc));
  auto task = [&](size_t t) {
    const size_t s = t / nc, f = t % nc;
    double hint = 0;
    for (size_t i = 0; i < series[s].options.size(); ++i) {
      c[s][i][f] = search(configurations[f].model, series[s].options[i], hint);
      hint = series[s].hinted ? c[s][i][f].critical_courant : 0.0;
    }
  };
  if (workers == 1) // in order, on this thread
    for (size_t t = 0; t < series.size() * nc; ++t)
      task(t);
  else
    run_tasks(series.size() * nc, task, workers);
  std::vector<std::vector<ConfigurationSweep>> out(series.size());
  for (size_t s = 0; s < series.size(); ++s)
    for (const std::vector<CriticalCourant>& at : c[s]) {
      ConfigurationSweep sweep;
      sweep.minimum.critical_courant = std::numeric_limits<double>::infinity();
      for (size_t f = 0; f < nc; ++f) {
        sweep.all.emplace_back(configurations[f].name, at[f].critical_courant);
        if (at[f].critical_courant < sweep.minimum.critical_courant) {
          sweep.minimum = at[f];
          sweep.configuration = configurations[f].name;
        }
        if (f == 0 || worse_small(at[f].small, at[f].stable_from, sweep.lowest.small,
                                  sweep.lowest.stable_from)) {
          sweep.lowest = at[f];
          sweep.lowest_configuration = configurations[f].name;
        }
      }
      out[s].push_back(std::move(sweep));
    }
  return out;
}

std::vector<std::vector<ConfigurationSweep>>
sweep_configurations(const std::vector<Configuration>& configurations,
                     const std::vector<CourantSeries>& series, double tol, double resolution,
                     int workers, const std::atomic<int>* interrupt) {
  return sweep_configurations(
      configurations, series,
      [&](const Model& model, const StepOptions& options, double hint) {
        return critical_courant(model, options, tol, 2.0, resolution, hint, interrupt);
      },
      workers);
}

ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol, double resolution, int workers,
                                const std::atomic<int>* interrupt) {
  return sweep_configurations(lattice_configurations(model, shifts), {{.options = {options}}}, tol,
                              resolution, workers, interrupt)[0][0];
}

} // namespace smpm
