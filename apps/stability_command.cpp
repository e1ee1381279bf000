// SPDX-License-Identifier: BSD-3-Clause
// smpm stability: the critical Courant numbers of FLIP, FMPM(k) (plain, blended, periodic) and
// the exact inverse, by the spectral method over lattice shifts and frames and by simulation
// (FMPM 2026 §3.3, Fig. 12A).

#include "stability_command.hpp"

#include "notes.hpp"
#include "option_checks.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/output.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>
#include <sstream>
#include <utility>

namespace smpm::app {

namespace {

struct Row {
  StepOptions opt;                        // velocity, order, blending, C_X, α of the row
  double critical_courant = std::nan(""); // C* spectral
  std::string configuration;
  std::string spectral_status;
  double stable_from = std::nan(""); // the lower end of [stable_from, C*] on every configuration
  std::string small_courant;         // what lies below it (small_courant_text)
  double simulation_courant = std::nan(""); // C* simulation
  double energy_change = std::nan("");
  bool simulated = false; // the simulation search ran (NaN then: no C in its bracket held)
  bool fmpm() const { return opt.velocity == VelocityUpdate::FMPM; }
  bool polynomial() const { return fmpm() && opt.fmpm.polynomial != Polynomial::Series; }
  /// C* simulation: "none" when every C of the search failed (unstable, or beyond
  /// --max-energy-change, down to the bracket's lowest C), empty when not searched.
  std::string simulation_cell() const {
    return simulated && std::isnan(simulation_courant) ? "none" : cell(simulation_courant);
  }
};

// The (m, α) pairs of the blended rows: every --blend-every with every --blend-alpha but 1 (the
// unblended rows), or the pairs of the earlier --blend m:alpha when it is given.
std::vector<double> blend_alphas(const StabilityArgs& a) {
  std::vector<double> alphas;
  for (const std::string& text : a.blend_alphas)
    if (!text.empty() && text != "none")
      alphas.push_back(parse_value("--blend-alpha", text, "a number in [0, 1] or none"));
  return alphas;
}

std::vector<std::pair<int, double>> blend_pairs(const StabilityArgs& a) {
  std::vector<std::pair<int, double>> pairs;
  for (const std::string& b : a.blends) {
    if (b.empty() || b == "none")
      continue;
    const size_t colon = b.find(':');
    int m = 0;
    double alpha = 0;
    if (colon == std::string::npos || !parse_all(b.substr(0, colon), m) ||
        !parse_all(b.substr(colon + 1), alpha))
      throw InputError("--blend " + clip(b) + ": expected m:alpha, e.g. 2:0.8");
    pairs.emplace_back(m, alpha);
  }
  if (!a.blends.empty())
    return pairs;
  for (int m : a.blend_every)
    for (const double alpha : blend_alphas(a))
      if (alpha != 1)
        pairs.emplace_back(m, alpha);
  return pairs;
}

std::vector<Polynomial> polynomials(const StabilityArgs& a) {
  std::vector<Polynomial> out;
  for (const std::string& name : a.polynomials) {
    if (name.empty() || name == "none")
      continue;
    Polynomial p = Polynomial::Series;
    try {
      p = polynomial_from_string(name);
    } catch (const InputError&) {
      throw InputError("--polynomial " + clip(name) +
                       ": expected chebyshev | least_squares | chebyshev_squared");
    }
    if (p == Polynomial::Series)
      throw InputError("--polynomial series: the FMPM rows are the series; expected chebyshev | "
                       "least_squares | chebyshev_squared");
    out.push_back(p);
  }
  return out;
}

// λ_lo of the polynomial rows: --interval-low, else the input's, else λ_min(m⁻¹m̃) at t = 0.
double interval_low(const StabilityArgs& a, const RunConfig& cfg) {
  if (!std::isnan(a.interval_low))
    return a.interval_low;
  if (cfg.step.fmpm.interval_low > 0)
    return cfg.step.fmpm.interval_low;
  const Operators ops = assemble(cfg.model.grid, cfg.model.particles, cfg.step.shape);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  return mass_spectrum(ops, mt.matrix).min_eig_minv_mt;
}

std::vector<double> periodic_budgets(const StabilityArgs& a) {
  std::vector<double> out;
  for (const std::string& text : a.periodic_cx) {
    if (text.empty() || text == "none")
      continue;
    const double cx = parse_value("--periodic-cx", text, "a Courant budget C_X or none");
    if (cx < 0)
      throw InputError("--periodic-cx " + clip(text) + ": must be non-negative (0: no rows)");
    if (cx > 0) // C_X = 0: the plain FMPM rows
      out.push_back(cx);
  }
  return out;
}

// The rows: FLIP, FMPM(k) for every --order, blended and periodic FMPM(k > 1), exact. α of
// Eqs. (8)-(9): --position-alpha, else the input's, else each row's default (1 for FLIP, ½ for
// grid-velocity updates).
std::vector<Row> make_rows(const StabilityArgs& a, const RunConfig& cfg) {
  const StepOptions& base = cfg.step;
  std::vector<Row> rows;
  auto row = [&](VelocityUpdate v, int k, double alpha, int every, double cx) {
    Row r;
    r.opt = base;
    r.opt.velocity = v;
    if (a.position_alpha_given)
      r.opt.position_alpha = a.position_alpha;
    r.opt.fmpm.metric = ConvergenceMetric::None;
    r.opt.fmpm.order = k;
    r.opt.fmpm.blend_alpha = alpha;
    r.opt.fmpm.blend_every = every;
    r.opt.periodic_cx = cx;
    r.opt.fmpm.polynomial = Polynomial::Series;
    rows.push_back(std::move(r));
  };
  row(VelocityUpdate::FLIP, base.fmpm.order, 1.0, 1, 0.0);
  for (int k : a.orders)
    row(VelocityUpdate::FMPM, k, 1.0, 1, 0.0);
  for (const auto& [every, alpha] : blend_pairs(a))
    for (int k : a.orders)
      if (k > 1)
        row(VelocityUpdate::FMPM, k, alpha, every, 0.0);
  for (const double cx : periodic_budgets(a))
    for (int k : a.orders)
      if (k > 1)
        row(VelocityUpdate::FMPM, k, 1.0, 1, cx);
  const std::vector<Polynomial> members = polynomials(a);
  const double lo = members.empty() ? 0.0 : interval_low(a, cfg);
  for (const Polynomial p : members)
    for (int k : a.orders)
      if (k > 1) {
        row(VelocityUpdate::FMPM, k, 1.0, 1, 0.0);
        rows.back().opt.fmpm.polynomial = p;
        rows.back().opt.fmpm.interval_low = lo;
      }
  if (!a.no_exact) {
    row(VelocityUpdate::Exact, base.fmpm.order, 1.0, 1, 0.0); // the input's exact_* options
    if (!rows.back().opt.exact_solver)
      rows.back().opt.exact_solver = exact_solver_factory();
  }
  return rows;
}

// The cells of a row: velocity, order, blend_alpha, blend_every, periodic_cx, position_alpha.
std::vector<std::string> option_cells(const Row& r) {
  const FmpmOptions& f = r.opt.fmpm;
  return {std::string(velocity_name(r.opt)),
          r.fmpm() ? std::to_string(f.order) : "",
          r.fmpm() ? cell(f.blend_alpha) : "",
          r.fmpm() ? std::to_string(f.blend_every) : "",
          r.opt.periodic_cx > 0 ? cell(r.opt.periodic_cx) : "",
          cell(position_alpha(r.opt))};
}

void write_table(const std::vector<Row>& rows, const std::string& path,
                 const std::vector<std::string>& inputs) {
  std::ostringstream out;
  out << kStabilityColumns << "\n";
  for (const Row& r : rows) {
    for (const std::string& c : option_cells(r))
      out << c << ",";
    out << cell(r.critical_courant) << "," << r.configuration << "," << r.spectral_status << ","
        << cell(r.stable_from) << "," << r.small_courant << "," << r.simulation_cell() << ","
        << cell(r.energy_change) << "," << (r.polynomial() ? cell(r.opt.fmpm.interval_low) : "")
        << "\n";
  }
  write_table_file(path, out.str(), inputs, "-o");
}

void print_table(const std::vector<Row>& rows) {
  const char* format = "%-17s %5s %11s %11s %11s %14s %11s %-16s %13s %14s  %s\n";
  std::printf(format, "velocity", "order", "blend_alpha", "blend_every", "periodic_cx",
              "position_alpha", "C* spectral", "configuration", "C* simulation", "energy change",
              "below C* spectral");
  for (const Row& r : rows) {
    const std::vector<std::string> c = option_cells(r);
    std::printf(format, c[0].c_str(), c[1].c_str(), c[2].c_str(), c[3].c_str(), c[4].c_str(),
                c[5].c_str(), cell(r.critical_courant).c_str(), r.configuration.c_str(),
                r.simulation_cell().c_str(), cell(r.energy_change).c_str(),
                r.small_courant.c_str());
  }
}

// Spectral C* of every row: the minimum over the lattice shifts and the stored frames
// (sweep_configurations). Rows that differ only in k (FMPM with one α, m and C_X) form a series
// searched in the order of --order, each search starting from the C* of the previous k.
void spectral_rows(std::vector<Row>& rows, const Model& model, const StabilityArgs& a,
                   const std::vector<Configuration>& frames, const StabilityEngine& engine) {
  std::vector<Configuration> configs = lattice_configurations(model, a.shifts);
  configs.insert(configs.end(), frames.begin(), frames.end());
  std::vector<CourantSeries> series;
  std::vector<std::pair<size_t, size_t>> where(rows.size()); // row → (series, entry)
  for (size_t i = 0; i < rows.size(); ++i) {
    const StepOptions& o = rows[i].opt;
    auto same = [&](const CourantSeries& s) {
      const StepOptions& q = s.options.front();
      return rows[i].fmpm() && q.velocity == o.velocity && q.fmpm.polynomial == o.fmpm.polynomial &&
             q.fmpm.interval_low == o.fmpm.interval_low &&
             q.fmpm.blend_alpha == o.fmpm.blend_alpha && q.fmpm.blend_every == o.fmpm.blend_every &&
             q.periodic_cx == o.periodic_cx;
    };
    auto it = std::find_if(series.begin(), series.end(), same);
    if (it == series.end())
      it =
          series.insert(series.end(), CourantSeries{.options = {}, .hinted = !(o.periodic_cx > 0)});
    where[i] = {size_t(it - series.begin()), it->options.size()};
    it->options.push_back(o);
  }
  const auto sweeps = engine.search ? sweep_configurations(configs, series, engine.search, 1)
                                    : sweep_configurations(configs, series);
  for (size_t i = 0; i < rows.size(); ++i) {
    const ConfigurationSweep& s = sweeps[where[i].first][where[i].second];
    rows[i].critical_courant = s.minimum.critical_courant;
    rows[i].configuration = s.configuration;
    rows[i].stable_from = s.lowest.stable_from;
    rows[i].small_courant =
        small_courant_cell(s.lowest.small, s.lowest.stable_from, s.lowest.floor,
                           s.lowest_configuration, s.minimum.critical_courant, "C");
    // Non-finite radii count as unstable inside critical_courant; unconverged Arnoldi runs are
    // named so that a reader knows the minimum rests on measured growth rates.
    const int unconverged = s.minimum.not_converged;
    rows[i].spectral_status = unconverged
                                  ? std::to_string(unconverged) + "/" +
                                        std::to_string(s.minimum.evaluations) + " not converged"
                                  : "converged";
  }
}

// Both methods for every row: the spectral C* (spectral_rows), then the simulations, one row
// per task on every core.
void compute_rows(std::vector<Row>& rows, const RunConfig& cfg, const StabilityArgs& a,
                  const std::vector<Configuration>& frames, const StabilityEngine& engine) {
  if (a.method != "simulation")
    spectral_rows(rows, cfg.model, a, frames, engine);
  SimulationCourantOptions sim;
  sim.end = cfg.time.end;
  sim.max_energy_change = a.max_energy_change;
  std::mutex print;
  run_tasks(rows.size(), [&](size_t i) {
    Row& r = rows[i];
    if (a.method != "spectral") {
      const SimulationCourant c = simulation_courant(cfg.model, r.opt, sim);
      r.simulation_courant = c.simulation_courant;
      r.energy_change = c.energy_change;
      r.simulated = true;
    }
    if (!a.quiet && engine.root) {
      const std::vector<std::string> c = option_cells(r);
      std::lock_guard<std::mutex> lock(print);
      std::fprintf(stderr,
                   "  %-5s order=%-3s blend_alpha=%-4s blend_every=%-2s periodic_cx=%-4s  C* "
                   "spectral %-7s simulation %s\n",
                   c[0].c_str(), c[1].empty() ? "-" : c[1].c_str(),
                   c[2].empty() ? "-" : c[2].c_str(), c[3].empty() ? "-" : c[3].c_str(),
                   c[4].empty() ? "-" : c[4].c_str(), cell(r.critical_courant).c_str(),
                   r.simulation_cell().c_str());
    }
  });
}

// The configurations of every --frame-stride-th frame of the run file --frames.
std::vector<Configuration> frame_configurations(const StabilityArgs& a, const Model& model) {
  std::vector<Configuration> frames;
  if (a.frames.empty())
    return frames;
  const std::vector<int> numbers = run_frames(a.frames);
  for (size_t j = 0; j < numbers.size(); j += size_t(std::max(1, a.frame_stride))) {
    Configuration c{model, "frame " + std::to_string(numbers[j])};
    load_frame(a.frames, numbers[j], c.model);
    frames.push_back(std::move(c));
  }
  return frames;
}

} // namespace

// Every option of smpm stability, checked before any work (the input is read afterwards).
void validate(const StabilityArgs& a) {
  if (a.method != "spectral" && a.method != "simulation" && a.method != "both")
    throw InputError("--method " + a.method + ": expected spectral | simulation | both");
  const std::vector<double> alphas = blend_alphas(a);
  check_fmpm_lists(a.orders, alphas.empty() ? std::vector<double>{1.0} : alphas, a.blend_every);
  if (!a.blends.empty())
    check_list("--blend", a.blends);
  for (const auto& [every, alpha] : blend_pairs(a)) {
    const std::string pair = std::to_string(every) + ":" + shown(alpha);
    if (every < 1 || every > kMaxListedOrder)
      throw InputError("--blend " + pair + ": m must lie in [1, " +
                       std::to_string(kMaxListedOrder) + "]");
    check_fmpm_option("--blend", pair, [&](FmpmOptions& f, auto&) {
      f.blend_every = every;
      f.blend_alpha = alpha;
    });
  }
  if (!a.polynomials.empty())
    check_list("--polynomial", a.polynomials);
  polynomials(a);
  if (!std::isnan(a.interval_low) && !(a.interval_low > 0 && a.interval_low < 1))
    throw InputError("--interval-low " + shown(a.interval_low) + ": must lie in (0, 1)");
  check_list("--periodic-cx", a.periodic_cx);
  for (const double cx : periodic_budgets(a))
    check_fmpm_option("--periodic-cx", shown(cx),
                      [cx](auto&, StepOptions& o) { o.periodic_cx = cx; });
  check_int("--shifts", a.shifts, 1, kMaxLatticeShifts);
  check_int("--frame-stride", a.frame_stride, 1, 1000000);
  if (a.position_alpha_given)
    check_fraction("--position-alpha", a.position_alpha);
  if (!(a.max_energy_change > 0))
    throw InputError("--max-energy-change " + shown(a.max_energy_change) + ": must be positive");
  check_table_output(a.output, {a.input, a.frames}, "-o");
  check_regular_file(a.input, kMaxInputBytes, "input file");
  if (!a.frames.empty())
    check_regular_file(a.frames, kMaxRunFileBytes, "run file");
}

int stability_command(const StabilityArgs& a, const StabilityEngine& engine) {
  validate(a);
  RunConfig cfg = read_input_file(a.input, a.sets);
  if (engine.root)
    print_notes(cfg);
  std::vector<Row> rows = make_rows(a, cfg);
  const std::vector<Configuration> frames = frame_configurations(a, cfg.model);
  const auto start = std::chrono::steady_clock::now();
  compute_rows(rows, cfg, a, frames, engine);
  if (!engine.root)
    return 0;
  write_table(rows, a.output, {a.input, a.frames});
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_table(rows);
  std::printf("%zu rows in %.1f s; table in %s\n", rows.size(), wall, a.output.c_str());
  return 0;
}

} // namespace smpm::app
