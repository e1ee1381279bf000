#include "stability_command.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/output.hpp>
#include <sparsempm/run.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>

namespace smpm::app {

namespace {

struct Row {
  std::string scheme; // FLIP | FMPM
  int k = 0;          // 0: not applicable
  double alpha = 1;
  int every = 1;
  double cx = 0;
  StepOptions opt;
  double c_spectral = std::nan("");
  std::string config;
  double c_simulation = std::nan("");
  double energy_change = std::nan("");
};

std::vector<Row> make_rows(const StabilityArgs& a, const StepOptions& base) {
  std::vector<Row> rows;
  Row flip;
  flip.scheme = "FLIP";
  flip.opt = base;
  flip.opt.velocity = VelocityUpdate::FLIP;
  flip.opt.position_alpha = 1.0;
  rows.push_back(flip);
  auto fmpm = [&](int k, double alpha, int every, double cx) {
    Row r;
    r.scheme = "FMPM";
    r.k = k;
    r.alpha = alpha;
    r.every = every;
    r.cx = cx;
    r.opt = base;
    r.opt.velocity = VelocityUpdate::FMPM;
    r.opt.position_alpha = 1.0; // as the paper's Fig. 12 bar (FLIP-like positions)
    r.opt.fmpm.order = k;
    r.opt.fmpm.blend_alpha = alpha;
    r.opt.fmpm.blend_every = every;
    r.opt.fmpm.metric = ConvergenceMetric::None;
    r.opt.periodic_cx = cx;
    return r;
  };
  for (int k : a.orders)
    rows.push_back(fmpm(k, 1.0, 1, 0.0));
  for (const std::string& b : a.blends) {
    if (b.empty() || b == "none")
      continue;
    const size_t colon = b.find(':');
    if (colon == std::string::npos)
      throw InputError("--blend " + b + ": expected m:alpha, e.g. 2:0.8");
    int every = 0;
    double alpha = 0;
    try {
      every = std::stoi(b.substr(0, colon));
      alpha = std::stod(b.substr(colon + 1));
    } catch (const std::exception&) {
      throw InputError("--blend " + b + ": expected m:alpha, e.g. 2:0.8");
    }
    if (every < 1 || !(alpha >= 0 && alpha <= 1))
      throw InputError("--blend " + b + ": m must be >= 1 and alpha in [0, 1]");
    for (int k : a.orders)
      if (k > 1)
        rows.push_back(fmpm(k, alpha, every, 0.0));
  }
  for (const std::string& text : a.periodic) {
    if (text.empty() || text == "none")
      continue;
    double cx = 0;
    try {
      cx = std::stod(text);
    } catch (const std::exception&) {
      throw InputError("--periodic " + text + ": expected a Courant budget C_X");
    }
    if (!(cx > 0))
      throw InputError("--periodic " + text + ": C_X must be positive");
    for (int k : a.orders)
      if (k > 1)
        rows.push_back(fmpm(k, 1.0, 1, cx));
  }
  return rows;
}

// Spectral C*: the minimum over lattice shifts and (optionally) stored frames.
void spectral(Row& r, const Model& model, const StabilityArgs& a, const std::vector<Model>& frames,
              const std::vector<std::string>& frame_names) {
  const ConfigurationSweep s = sweep_shifts(model, r.opt, a.shifts, 1e-6, 1e-3);
  r.c_spectral = s.minimum.courant;
  r.config = s.configuration;
  for (size_t f = 0; f < frames.size(); ++f) {
    const double c = critical_courant(frames[f], r.opt, 1e-6, 2.0, 1e-3).courant;
    if (c < r.c_spectral) {
      r.c_spectral = c;
      r.config = frame_names[f];
    }
  }
}

// Relative change of total energy of a full run at Courant number C, NaN when it fails
// (NaN, det F <= 0, a particle leaving the grid, or total energy above 10x its start).
double run_energy(const Model& start, const StepOptions& opt, double C, double end) {
  Model model = start;
  Stepper stepper(opt);
  const double e0 = energies(model).total;
  try {
    while (model.time < end - 1e-12 * end) {
      stepper.step(model, std::min(stable_time_step(model, C), end - model.time));
      const double e = energies(model).total;
      if (!std::isfinite(e) || (e0 > 0 && e > 10 * e0))
        return std::nan("");
    }
  } catch (const NumericalError&) {
    return std::nan("");
  }
  return e0 != 0 ? (energies(model).total - e0) / e0 : 0.0;
}

// The paper's way: bisection on C over full runs, to ±0.005.
void simulation(Row& r, const Model& model, double end) {
  double lo = 0.02, hi = 1.5;
  double e_lo = run_energy(model, r.opt, lo, end);
  if (std::isnan(e_lo))
    return; // unstable even at C = 0.02
  if (!std::isnan(run_energy(model, r.opt, hi, end))) {
    r.c_simulation = hi;
    return;
  }
  while (hi - lo > 0.005) {
    const double mid = 0.5 * (lo + hi);
    const double e = run_energy(model, r.opt, mid, end);
    if (std::isnan(e))
      hi = mid;
    else {
      lo = mid;
      e_lo = e;
    }
  }
  r.c_simulation = lo;
  r.energy_change = e_lo;
}

std::string cell(double v, int precision = 4) {
  if (std::isnan(v))
    return "";
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

} // namespace

int stability_command(const StabilityArgs& a) {
  if (a.method != "spectral" && a.method != "simulation" && a.method != "both")
    throw InputError("--method " + a.method + ": expected spectral | simulation | both");
  RunConfig cfg = read_input_file(a.input, a.sets);
  std::vector<Row> rows = make_rows(a, cfg.step);
  std::vector<Model> frames;
  std::vector<std::string> frame_names;
  if (!a.frames.empty()) {
    const std::vector<int> numbers = run_frames(a.frames);
    for (size_t j = 0; j < numbers.size(); j += size_t(std::max(1, a.frame_stride))) {
      Model m = cfg.model;
      load_frame(a.frames, numbers[j], m);
      frames.push_back(std::move(m));
      frame_names.push_back("frame " + std::to_string(numbers[j]));
    }
  }
  const auto start = std::chrono::steady_clock::now();
  std::atomic<size_t> next{0};
  std::mutex print;
  std::exception_ptr failure;
  auto worker = [&] {
    for (size_t i; (i = next++) < rows.size();) {
      try {
        Row& r = rows[i];
        if (a.method != "simulation")
          spectral(r, cfg.model, a, frames, frame_names);
        if (a.method != "spectral")
          simulation(r, cfg.model, cfg.time.end);
        if (!a.quiet) {
          std::lock_guard<std::mutex> lock(print);
          std::fprintf(
              stderr, "  %-5s k=%-3s alpha=%-4s m=%s C_X=%-4s  C* spectral %-7s simulation %s\n",
              r.scheme.c_str(), r.k ? std::to_string(r.k).c_str() : "-", cell(r.alpha).c_str(),
              std::to_string(r.every).c_str(), r.cx > 0 ? cell(r.cx).c_str() : "-",
              cell(r.c_spectral).c_str(), cell(r.c_simulation).c_str());
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(print);
        failure = std::current_exception();
        return;
      }
    }
  };
  std::thread t1(worker), t2(worker); // independent rows use both cores
  t1.join();
  t2.join();
  if (failure)
    std::rethrow_exception(failure);
  // CSV: written to a temporary name first so that no partial table is left behind.
  const std::string tmp = a.output + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out)
      throw InputError("-o " + a.output + ": cannot write the table");
    out << "scheme,k,alpha,blend_every,periodic_cx,c_spectral,config_spectral,c_simulation,"
           "energy_change\n";
    for (const Row& r : rows)
      out << r.scheme << "," << (r.k ? std::to_string(r.k) : "") << ","
          << (r.scheme == "FLIP" ? "" : cell(r.alpha)) << ","
          << (r.scheme == "FLIP" ? "" : std::to_string(r.every)) << ","
          << (r.cx > 0 ? cell(r.cx) : "") << "," << cell(r.c_spectral) << "," << r.config << ","
          << cell(r.c_simulation) << "," << cell(r.energy_change) << "\n";
  }
  std::rename(tmp.c_str(), a.output.c_str());
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%-6s %4s %6s %6s %6s %10s %-16s %12s %14s\n", "scheme", "k", "alpha", "every", "C_X",
              "C*(spec)", "configuration", "C*(sim)", "energy change");
  for (const Row& r : rows)
    std::printf("%-6s %4s %6s %6s %6s %10s %-16s %12s %14s\n", r.scheme.c_str(),
                r.k ? std::to_string(r.k).c_str() : "",
                r.scheme == "FLIP" ? "" : cell(r.alpha).c_str(),
                r.scheme == "FLIP" ? "" : std::to_string(r.every).c_str(),
                r.cx > 0 ? cell(r.cx).c_str() : "", cell(r.c_spectral).c_str(), r.config.c_str(),
                cell(r.c_simulation).c_str(), cell(r.energy_change).c_str());
  std::printf("%zu schemes in %.1f s; table in %s\n", rows.size(), wall, a.output.c_str());
  return 0;
}

int spectrum_command(const SpectrumArgs& a) {
  RunConfig cfg = read_input_file(a.input, a.sets);
  const Model& model = cfg.model;
  const Operators ops = assemble(model.grid, model.particles, cfg.step.shape);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  const MassSpectrum ms = mass_spectrum(ops, mt.matrix);
  Field p, exact;
  StageWorkspace w;
  map_momentum(ops, model.particles, p, w);
  CholmodSolver solver;
  solver.solve(ops, mt.matrix, {}, p, exact);
  std::printf("active nodes %ld: rho(A) = %.8f, min eig(m^-1 m~) = %.3e, cond(m~) = %.4g\n",
              long(ms.active), ms.rho_A, ms.min_eig_minv_mt, ms.cond_mt);
  const std::string tmp = a.output + ".tmp";
  std::ofstream out(tmp);
  if (!out)
    throw InputError("-o " + a.output + ": cannot write the table");
  out.precision(10);
  out << "# rho_A = " << ms.rho_A << "\n# min_eig_minv_mt = " << ms.min_eig_minv_mt
      << "\n# cond_mt = " << ms.cond_mt << "\n# active_nodes = " << ms.active << "\n";
  out << "k,alpha,blend_every,truncation_error,courant,rho_T\n";
  std::printf("%4s %6s %6s %16s %10s\n", "k", "alpha", "every", "truncation", "rho(T)");
  for (int m : a.every)
    for (double alpha : a.alphas)
      for (int k : a.orders) {
        if (m > 1 && alpha == 1.0)
          continue; // no blending: the m = 1 rows already hold it
        const FmpmOptions f{.order = k, .blend_alpha = alpha, .blend_every = m};
        const double err = truncation_error(ops, mt.matrix, f, p, exact);
        double rho = std::nan("");
        if (a.courant > 0) {
          StepOptions opt = cfg.step;
          opt.velocity = VelocityUpdate::FMPM;
          opt.fmpm = f;
          opt.periodic_cx = 0;
          const LinearizedStep T(model, opt, a.courant / courant_of(model, 1.0));
          rho = spectral_radius(T);
        }
        out << k << "," << alpha << "," << m << "," << err << ","
            << (a.courant > 0 ? std::to_string(a.courant) : "") << "," << cell(rho, 10) << "\n";
        std::printf("%4d %6.3g %6d %16.6e %10s\n", k, alpha, m, err, cell(rho, 8).c_str());
      }
  out.close();
  std::rename(tmp.c_str(), a.output.c_str());
  std::printf("table in %s\n", a.output.c_str());
  return 0;
}

} // namespace smpm::app
