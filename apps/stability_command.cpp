#include "stability_command.hpp"

#include "notes.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/output.hpp>
#include <sparsempm/run.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>
#include <sparsempm/threads.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace smpm::app {

namespace {

struct Row {
  std::string scheme; // FLIP | FMPM | exact
  int k = 0;          // 0: not applicable
  double alpha = 1;
  int every = 1;
  double cx = 0;
  StepOptions opt;
  double c_spectral = std::nan("");
  std::string config;
  std::string spectral_status;
  double c_simulation = std::nan("");
  double energy_change = std::nan("");
};

// α of Eqs. (8)-(9) for a row: --position-alpha, else the input's scheme.position_alpha, else
// the default of the row's velocity update (1 for FLIP, 1/2 otherwise).
std::optional<double> chosen_alpha(const StabilityArgs& a, const StepOptions& base) {
  if (!std::isnan(a.position_alpha))
    return a.position_alpha;
  return base.position_alpha;
}

std::pair<int, double> parse_blend(const std::string& b) {
  const size_t colon = b.find(':');
  int every = 0;
  double alpha = 0;
  try {
    if (colon == std::string::npos)
      throw std::invalid_argument(b);
    every = std::stoi(b.substr(0, colon));
    alpha = std::stod(b.substr(colon + 1));
  } catch (const std::exception&) {
    throw InputError("--blend " + b + ": expected m:alpha, e.g. 2:0.8");
  }
  if (every < 1 || !(alpha >= 0 && alpha <= 1))
    throw InputError("--blend " + b + ": m must be >= 1 and alpha in [0, 1]");
  return {every, alpha};
}

double parse_cx(const std::string& text) {
  double cx = 0;
  try {
    cx = std::stod(text);
  } catch (const std::exception&) {
    throw InputError("--periodic " + text + ": expected a Courant budget C_X");
  }
  if (!(cx > 0) || !std::isfinite(cx))
    throw InputError("--periodic " + text + ": C_X must be positive");
  return cx;
}

std::vector<Row> make_rows(const StabilityArgs& a, const StepOptions& base) {
  std::vector<Row> rows;
  auto row = [&](const std::string& scheme, VelocityUpdate v) {
    Row r;
    r.scheme = scheme;
    r.opt = base;
    r.opt.velocity = v;
    r.opt.position_alpha = chosen_alpha(a, base);
    r.opt.periodic_cx = 0;
    r.opt.fmpm.metric = ConvergenceMetric::None;
    return r;
  };
  rows.push_back(row("FLIP", VelocityUpdate::FLIP));
  auto fmpm = [&](int k, double alpha, int every, double cx) {
    Row r = row("FMPM", VelocityUpdate::FMPM);
    r.k = k;
    r.alpha = alpha;
    r.every = every;
    r.cx = cx;
    r.opt.fmpm.order = k;
    r.opt.fmpm.blend_alpha = alpha;
    r.opt.fmpm.blend_every = every;
    r.opt.periodic_cx = cx;
    return r;
  };
  for (int k : a.orders)
    rows.push_back(fmpm(k, 1.0, 1, 0.0));
  for (const std::string& b : a.blends)
    if (!b.empty() && b != "none")
      for (const auto [every, alpha] = parse_blend(b); int k : a.orders)
        if (k > 1)
          rows.push_back(fmpm(k, alpha, every, 0.0));
  for (const std::string& text : a.periodic)
    if (!text.empty() && text != "none")
      for (const double cx = parse_cx(text); int k : a.orders)
        if (k > 1)
          rows.push_back(fmpm(k, 1.0, 1, cx));
  if (a.exact) {
    Row r = row("exact", VelocityUpdate::Exact); // the input's exact_* options
    if (!r.opt.exact_solver)
      r.opt.exact_solver = cholmod_solver_factory();
    rows.push_back(r);
  }
  return rows;
}

std::string cell(double v, int precision = 4) {
  if (std::isnan(v))
    return "";
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

// A value as a message shows it (a table cell leaves NaN empty).
std::string shown(double v) {
  return std::isnan(v) ? std::string("nan") : cell(v, 6);
}

// Writes `text` to `path` through the temporary file `path`.tmp, so that a table appears whole
// or not at all. The temporary name is unlinked and created anew (O_EXCL | O_NOFOLLOW): a file
// or link found there, left by a killed command, is never written through. The output is
// checked again just before the move (a run may have claimed the path during the work); a
// failed write or move is an error (exit 1) and removes the temporary file.
void write_text_file(const std::string& path, const std::string& text,
                     const std::vector<std::string>& inputs) {
  const std::string tmp = path + ".tmp";
  ::unlink(tmp.c_str());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  int why = fd < 0 ? errno : 0;
  for (size_t done = 0; !why && done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0)
      why = n < 0 ? errno : EIO;
    else
      done += size_t(n);
  }
  if (fd >= 0 && ::close(fd) != 0 && !why)
    why = errno;
  if (!why) {
    try {
      check_table_output(path, inputs, "-o");
    } catch (const InputError&) {
      ::unlink(tmp.c_str());
      throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      why = errno;
  }
  if (why) {
    if (fd >= 0)
      ::unlink(tmp.c_str());
    throw std::runtime_error("-o " + path + ": cannot write the table (" + std::strerror(why) +
                             ")");
  }
}

void write_table(const std::vector<Row>& rows, const std::string& path,
                 const std::vector<std::string>& inputs) {
  std::ostringstream out;
  out << "scheme,k,alpha,blend_every,periodic_cx,position_alpha,c_spectral,config_spectral,"
         "spectral_status,c_simulation,energy_change\n";
  for (const Row& r : rows) {
    const bool fmpm = r.scheme == "FMPM";
    out << r.scheme << "," << (r.k ? std::to_string(r.k) : "") << "," << (fmpm ? cell(r.alpha) : "")
        << "," << (fmpm ? std::to_string(r.every) : "") << "," << (r.cx > 0 ? cell(r.cx) : "")
        << "," << cell(position_alpha(r.opt)) << "," << cell(r.c_spectral) << "," << r.config << ","
        << r.spectral_status << "," << cell(r.c_simulation) << "," << cell(r.energy_change) << "\n";
  }
  write_text_file(path, out.str(), inputs);
}

void print_table(const std::vector<Row>& rows) {
  std::printf("%-6s %4s %6s %6s %6s %6s %10s %-16s %12s %14s\n", "scheme", "k", "alpha", "every",
              "C_X", "pos_a", "C*(spec)", "configuration", "C*(sim)", "energy change");
  for (const Row& r : rows) {
    const bool fmpm = r.scheme == "FMPM";
    std::printf("%-6s %4s %6s %6s %6s %6s %10s %-16s %12s %14s\n", r.scheme.c_str(),
                r.k ? std::to_string(r.k).c_str() : "", fmpm ? cell(r.alpha).c_str() : "",
                fmpm ? std::to_string(r.every).c_str() : "", r.cx > 0 ? cell(r.cx).c_str() : "",
                cell(position_alpha(r.opt)).c_str(), cell(r.c_spectral).c_str(), r.config.c_str(),
                cell(r.c_simulation).c_str(), cell(r.energy_change).c_str());
  }
}

// Calls task(i) for i = 0 … count − 1 on two workers of one OpenMP thread each (independent
// tasks fill both cores); the first failure stops both and is rethrown.
void on_two_workers(size_t count, const std::function<void(size_t)>& task) {
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
  std::thread t1(worker), t2(worker);
  t1.join();
  t2.join();
  if (failure)
    std::rethrow_exception(failure);
}

// Spectral C* of every row: the minimum over the lattice shifts and the stored frames. One task
// per configuration and series of rows that differ only in k (FMPM with one α, m and C_X; FLIP
// and exact alone), taking its rows in the order of --k and starting each search from the C* of
// the previous k on the same configuration (critical_courant's hint; the same C*, fewer
// evaluations: FMPM 2026 Fig. 12A's C* changes little between neighbouring k).
void spectral_rows(std::vector<Row>& rows, const Model& model, const StabilityArgs& a,
                   const std::vector<Model>& frames, const std::vector<std::string>& frame_names) {
  std::vector<Model> configs;
  std::vector<std::string> names;
  for (const LatticeShift& s : lattice_shifts(model, a.shifts)) {
    configs.push_back(shifted(model, s.cells));
    names.push_back(s.name);
  }
  configs.insert(configs.end(), frames.begin(), frames.end());
  names.insert(names.end(), frame_names.begin(), frame_names.end());
  std::vector<std::vector<size_t>> series;
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    auto same = [&](const std::vector<size_t>& s) {
      const Row& q = rows[s.front()];
      return r.scheme == "FMPM" && q.scheme == "FMPM" && q.alpha == r.alpha && q.every == r.every &&
             q.cx == r.cx;
    };
    auto it = std::find_if(series.begin(), series.end(), same);
    if (it == series.end())
      series.push_back({i});
    else
      it->push_back(i);
  }
  std::vector<std::vector<CriticalCourant>> c(rows.size(),
                                              std::vector<CriticalCourant>(configs.size()));
  on_two_workers(series.size() * configs.size(), [&](size_t task) {
    const size_t f = task % configs.size();
    double hint = 0;
    for (size_t i : series[task / configs.size()]) {
      c[i][f] = critical_courant(configs[f], rows[i].opt, 1e-6, 2.0, 1e-3, hint);
      // Periodic FMPM's T(C) spans ⌈C_X/C⌉ steps, a count that jumps with C: its stability need
      // not be monotone in C, so its searches start from scratch.
      hint = rows[i].cx > 0 ? 0.0 : c[i][f].courant;
    }
  });
  for (size_t i = 0; i < rows.size(); ++i) {
    Row& r = rows[i];
    size_t best = 0;
    for (size_t f = 1; f < configs.size(); ++f)
      if (c[i][f].courant < c[i][best].courant)
        best = f;
    r.c_spectral = c[i][best].courant;
    r.config = names[best];
    // Non-finite radii count as unstable inside critical_courant; unconverged Arnoldi runs are
    // named so that a reader knows the minimum rests on measured growth rates.
    const int unconverged = c[i][best].not_converged;
    r.spectral_status = unconverged ? std::to_string(unconverged) + "/" +
                                          std::to_string(c[i][best].evaluations) + " not converged"
                                    : "converged";
  }
}

// Both methods for every row: the spectral C* (spectral_rows), then the simulations, one row
// per task.
void compute_rows(std::vector<Row>& rows, const RunConfig& cfg, const StabilityArgs& a,
                  const std::vector<Model>& frames, const std::vector<std::string>& frame_names) {
  if (a.method != "simulation")
    spectral_rows(rows, cfg.model, a, frames, frame_names);
  SimulationCourantOptions sim;
  sim.end = cfg.time.end;
  sim.max_energy_change = a.max_energy_change;
  std::mutex print;
  on_two_workers(rows.size(), [&](size_t i) {
    Row& r = rows[i];
    if (a.method != "spectral") {
      const SimulationCourant c = simulation_courant(cfg.model, r.opt, sim);
      r.c_simulation = c.courant;
      r.energy_change = c.energy_change;
    }
    if (!a.quiet) {
      std::lock_guard<std::mutex> lock(print);
      std::fprintf(stderr,
                   "  %-5s k=%-3s alpha=%-4s m=%s C_X=%-4s  C* spectral %-7s simulation %s\n",
                   r.scheme.c_str(), r.k ? std::to_string(r.k).c_str() : "-", cell(r.alpha).c_str(),
                   std::to_string(r.every).c_str(), r.cx > 0 ? cell(r.cx).c_str() : "-",
                   cell(r.c_spectral).c_str(), cell(r.c_simulation).c_str());
    }
  });
}

constexpr int kMaxOrder = kMaxFmpmOrder; // FMPM orders, blend periods (fmpm.hpp)
constexpr int kMaxShifts = 1000;
constexpr size_t kMaxList = 1000; // entries of a list option

void check_int(const std::string& option, int value, int lo, int hi) {
  if (value < lo || value > hi)
    throw InputError(option + " " + std::to_string(value) + ": must lie in [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]");
}
void check_fraction(const std::string& option, double value) {
  if (!(value >= 0 && value <= 1))
    throw InputError(option + " " + shown(value) + ": must lie in [0, 1]");
}
template <class T>
void check_list(const std::string& option, const std::vector<T>& values) {
  if (values.empty() || values.size() > kMaxList)
    throw InputError(option + ": give 1 to " + std::to_string(kMaxList) + " values");
}

// Every option of smpm stability, checked before any work (the input is read afterwards).
void validate(const StabilityArgs& a) {
  if (a.method != "spectral" && a.method != "simulation" && a.method != "both")
    throw InputError("--method " + a.method + ": expected spectral | simulation | both");
  check_list("--k", a.orders);
  for (int k : a.orders)
    check_int("--k", k, 1, kMaxOrder);
  for (const std::string& b : a.blends)
    if (!b.empty() && b != "none")
      (void)parse_blend(b);
  for (const std::string& p : a.periodic)
    if (!p.empty() && p != "none")
      (void)parse_cx(p);
  check_int("--shifts", a.shifts, 1, kMaxShifts);
  check_int("--frame-stride", a.frame_stride, 1, 1000000);
  if (!std::isnan(a.position_alpha))
    check_fraction("--position-alpha", a.position_alpha);
  if (!(a.max_energy_change > 0))
    throw InputError("--max-energy-change " + shown(a.max_energy_change) + ": must be positive");
  check_table_output(a.output, {a.input, a.frames}, "-o");
  check_regular_file(a.input, kMaxInputBytes, "input file");
  if (!a.frames.empty())
    check_regular_file(a.frames, kMaxRunFileBytes, "run file");
}

void validate(const SpectrumArgs& a) {
  check_list("--k", a.orders);
  for (int k : a.orders)
    check_int("--k", k, 1, kMaxOrder);
  check_list("--alpha", a.alphas);
  for (double alpha : a.alphas)
    check_fraction("--alpha", alpha);
  check_list("--every", a.every);
  for (int m : a.every)
    check_int("--every", m, 1, kMaxOrder);
  if (!(a.courant >= 0) || !std::isfinite(a.courant))
    throw InputError("--courant " + shown(a.courant) + ": must be positive (or 0: no rho(T))");
  check_table_output(a.output, {a.input}, "-o");
  check_regular_file(a.input, kMaxInputBytes, "input file");
}
} // namespace

int stability_command(const StabilityArgs& a) {
  validate(a);
  RunConfig cfg = read_input_file(a.input, a.sets);
  print_notes(cfg);
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
  compute_rows(rows, cfg, a, frames, frame_names);
  write_table(rows, a.output, {a.input, a.frames});
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_table(rows);
  std::printf("%zu schemes in %.1f s; table in %s\n", rows.size(), wall, a.output.c_str());
  return 0;
}

int spectrum_command(const SpectrumArgs& a) {
  validate(a);
  RunConfig cfg = read_input_file(a.input, a.sets);
  print_notes(cfg);
  const Model& model = cfg.model;
  const Operators ops = assemble(model.grid, model.particles, cfg.step.shape);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  const MassSpectrum ms = mass_spectrum(ops, mt.matrix);
  Field p, exact;
  map_momentum(particle_operators(ops), model.particles.V, p);
  cfg.step.exact_solver(cfg.step.exact)
      ->solve(ops, mt.matrix, {}, p, exact); // the input's exact_* options
  std::printf("active nodes %ld: rho(A) = %.8f, min eig(m^-1 m~) = %.3e, cond(m~) = %.4g\n",
              long(ms.active), ms.rho_A, ms.min_eig_minv_mt, ms.cond_mt);
  std::ostringstream out;
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
          const LinearizedStep T(model, opt, stable_time_step(model, a.courant));
          const SpectralRadius r = spectral_radius(T);
          rho = r.status == SpectralStatus::NonFinite ? std::numeric_limits<double>::infinity()
                                                      : r.rho;
        }
        out << k << "," << alpha << "," << m << "," << err << ","
            << (a.courant > 0 ? std::to_string(a.courant) : "") << "," << cell(rho, 10) << "\n";
        std::printf("%4d %6.3g %6d %16.6e %10s\n", k, alpha, m, err, cell(rho, 8).c_str());
      }
  write_text_file(a.output, out.str(), {a.input});
  std::printf("table in %s\n", a.output.c_str());
  return 0;
}

} // namespace smpm::app
