// Critical Courant numbers: spectral (ρ of the linearised step, over lattice shifts) and by
// simulation (bisection over full runs), FMPM 2026 §3.3, Fig. 12A.

#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace smpm {

CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol,
                                 double c_max, double resolution, double hint) {
  SMPM_VERIFY(c_max > 0 && std::isfinite(c_max) && resolution >= 1e-12 * c_max,
              "critical_courant: c_max must be positive and finite and resolution at least "
              "1e-12 c_max");
  hint = std::isfinite(hint) ? std::min(hint, c_max) : 0.0;
  LinearizedStep T(model, options, stable_time_step(model, 0.05));
  CriticalCourant out;
  auto stable = [&](double C, double& rho) {
    T.set_dt(stable_time_step(model, C));
    const SpectralRadius r = spectral_radius(T);
    ++out.evaluations;
    out.not_converged += r.status == SpectralStatus::NotConverged;
    out.non_finite += r.status == SpectralStatus::NonFinite;
    rho = std::pow(r.rho, 1.0 / T.steps_per_application()); // growth per step
    return r.status != SpectralStatus::NonFinite && rho <= 1 + tol;
  };
  // The brackets [e_{j−1}, e_j]: e_0 = 0 (the identity step, ρ = 1), e_1 = 0.05, doubling up
  // to c_max; in a bracket, the grid of 2^n intervals with n the least that makes them no wider
  // than `resolution`. C* is the last stable grid point before an unstable one: the same point
  // whether the search starts from the hint or from below, if stability is monotone in C (which
  // bisection assumes anyway).
  std::vector<double> edge{0.0, std::min(0.05, c_max)};
  while (edge.back() < c_max)
    edge.push_back(std::min(2 * edge.back(), c_max));
  const int last = int(edge.size()) - 1;
  double rho = 0, low_rho = 1; // ρ at e_{j−1} when it is known stable
  bool low_known = true, high_known = false, entered = false;
  int j = 1;
  if (hint > 0) { // the bracket that holds the hint
    while (j < last && edge[size_t(j)] <= hint)
      ++j;
    low_known = j == 1;
  } else { // doubling: the edges upward until one is unstable
    for (; !high_known; ++j) {
      if (!stable(edge[size_t(j)], rho)) {
        high_known = true;
        break;
      }
      low_rho = rho;
      if (j == last) {
        out.courant = edge[size_t(j)];
        out.rho = rho;
        return out;
      }
    }
  }
  for (;;) {
    const double a = edge[size_t(j - 1)], b = edge[size_t(j)];
    Index n = 1;
    while ((b - a) / double(n) > resolution)
      n *= 2;
    const double h = (b - a) / double(n);
    auto at = [&](Index i) { return i == n ? b : a + double(i) * h; };
    Index s = low_known ? 0 : -1, u = high_known ? n : -1; // stable s < unstable u
    double rho_s = low_rho;
    // Gallop from the hint until both are found (in a bracket entered from a neighbour, its
    // far end first, as doubling does) ...
    Index i = hint > a ? Index(std::floor((hint - a) / h)) : 0;
    if (entered)
      i = s >= 0 ? n : 0;
    if (s < 0 || u < 0)
      i = std::clamp(i, s + 1, u >= 0 ? u - 1 : n);
    for (Index step = 1; s < 0 || u < 0; step *= 2) {
      if (stable(at(i), rho)) {
        s = i;
        rho_s = rho;
        if (u >= 0 || i == n)
          break;
        i = std::min(n, i + step);
      } else {
        u = i;
        if (s >= 0 || i == 0)
          break;
        i = std::max(Index(0), i - step);
      }
    }
    if (u < 0) { // stable at b: the transition is in a higher bracket
      if (j == last) {
        out.courant = b;
        out.rho = rho_s;
        return out;
      }
      ++j;
      low_known = true, low_rho = rho_s, high_known = false, entered = true;
      continue;
    }
    if (s < 0) { // unstable at a (j > 1): in a lower bracket
      --j;
      high_known = true, low_known = j == 1, low_rho = 1, entered = true;
      continue;
    }
    // ... then bisect between them.
    while (u - s > 1) {
      const Index mid = s + (u - s) / 2;
      if (stable(at(mid), rho)) {
        s = mid;
        rho_s = rho;
      } else {
        u = mid;
      }
    }
    out.courant = at(s);
    out.rho = rho_s;
    return out;
  }
}

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
  if (shifts < 1)
    throw InputError("the number of lattice shifts must be at least 1");
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

ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol, double resolution) {
  ConfigurationSweep out;
  out.minimum.courant = std::numeric_limits<double>::infinity();
  for (const LatticeShift& s : lattice_shifts(model, shifts)) {
    const CriticalCourant c =
        critical_courant(shifted(model, s.cells), options, tol, 2.0, resolution);
    out.all.emplace_back(s.name, c.courant);
    if (c.courant < out.minimum.courant) {
      out.minimum = c;
      out.configuration = s.name;
    }
  }
  return out;
}

double simulation_energy_change(const Model& start, const StepOptions& options, double courant,
                                const SimulationCourantOptions& sim) {
  Model model = start;
  Stepper stepper(options);
  const AdvanceOptions adv{.end = sim.end,
                           .courant = courant,
                           .stop_every = 0,
                           .land_on_stops = false, // constant Courant steps
                           .failure = sim.failure,
                           .energy_start = std::nullopt};
  AdvanceReport r;
  try {
    r = advance(model, stepper, adv);
  } catch (const NumericalError&) {
    return std::nan("");
  }
  const double change =
      r.energy_start != 0 ? (r.energy_end - r.energy_start) / r.energy_start : 0.0;
  return std::abs(change) <= sim.max_energy_change ? change : std::nan("");
}

SimulationCourant simulation_courant(const Model& model, const StepOptions& options,
                                     const SimulationCourantOptions& sim) {
  if (!(sim.end > model.time) || !(sim.lo > 0) || !(sim.hi > sim.lo) || !(sim.resolution > 0))
    throw InputError("simulation C*: needs end > t, 0 < lo < hi and a positive resolution");
  SimulationCourant out;
  auto run = [&](double C) {
    ++out.runs;
    return simulation_energy_change(model, options, C, sim);
  };
  double lo = sim.lo, hi = sim.hi, e_lo = std::nan("");
  if (std::isinf(sim.max_energy_change)) {
    // Blow-up is monotone in C: bisection from the bracket.
    e_lo = run(lo);
    if (std::isnan(e_lo))
      return out; // unstable even at lo
    if (const double e_hi = run(hi); !std::isnan(e_hi)) {
      out.courant = hi;
      out.energy_change = e_hi;
      return out;
    }
  } else {
    // Dissipation accumulates over more steps at small C, so "low dissipation" is not monotone
    // in C: scan the bracket from hi down on 16 intervals for the largest passing C, then bisect
    // between it and the failing point above.
    const int intervals = 16;
    const double h = (hi - lo) / intervals;
    int j = intervals;
    for (; j >= 0; --j)
      if (e_lo = run(lo + j * h); !std::isnan(e_lo))
        break;
    if (j < 0)
      return out; // no C of the bracket passes
    if (j == intervals) {
      out.courant = hi;
      out.energy_change = e_lo;
      return out;
    }
    lo += j * h;
    hi = lo + h;
  }
  while (hi - lo > sim.resolution) {
    const double mid = 0.5 * (lo + hi);
    const double e = run(mid);
    if (std::isnan(e)) {
      hi = mid;
    } else {
      lo = mid;
      e_lo = e;
    }
  }
  out.courant = lo;
  out.energy_change = e_lo;
  return out;
}

} // namespace smpm
