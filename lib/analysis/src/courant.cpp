// Critical Courant numbers: spectral (ρ of the linearised step, over lattice shifts) and by
// simulation (bisection over full runs), FMPM 2026 §3.3, Fig. 12A.

#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace smpm {

CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol,
                                 double c_max, double resolution) {
  const double dt_per_c = 1.0 / courant_of(model, 1.0); // Δt for C = 1
  LinearizedStep T(model, options, 0.05 * dt_per_c);
  CriticalCourant out;
  auto stable = [&](double C, double& rho) {
    T.set_dt(C * dt_per_c);
    const SpectralRadius r = spectral_radius(T);
    ++out.evaluations;
    out.not_converged += r.status == SpectralStatus::NotConverged;
    out.non_finite += r.status == SpectralStatus::NonFinite;
    rho = std::pow(r.rho, 1.0 / T.steps_per_application()); // growth per step
    return r.status != SpectralStatus::NonFinite && rho <= 1 + tol;
  };
  double lo = 0, hi = 0.05, rho_lo = 1, rho = 0;
  while (stable(hi, rho)) { // bracket: lo stable, hi unstable
    lo = hi;
    rho_lo = rho;
    if (hi >= c_max) {
      out.courant = lo;
      out.rho = rho_lo;
      return out;
    }
    hi = std::min(2 * hi, c_max);
  }
  while (hi - lo > resolution) {
    const double mid = 0.5 * (lo + hi);
    if (stable(mid, rho)) {
      lo = mid;
      rho_lo = rho;
    } else {
      hi = mid;
    }
  }
  out.courant = lo;
  out.rho = rho_lo;
  return out;
}

Model shifted(const Model& model, const std::array<double, 3>& shift) {
  Model m = model;
  for (int a = 0; a < m.grid.dim(); ++a)
    m.particles.X.col(a).array() += shift[size_t(a)] * m.grid.cell_size(a);
  (void)assemble(m.grid, m.particles, Shape::Linear); // throws if a particle left the grid
  return m;
}

ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol, double resolution) {
  if (shifts < 1)
    throw InputError("the number of lattice shifts must be at least 1");
  ConfigurationSweep out;
  out.minimum.courant = std::numeric_limits<double>::infinity();
  // The lattice repeats itself after one particle spacing 2 r⁰: shifts j/shifts of it (in cells
  // along each axis) reach every distinct position of the lattice relative to the grid.
  std::array<double, 3> period{0, 0, 0};
  for (int a = 0; a < model.grid.dim(); ++a)
    period[size_t(a)] = model.particles.size()
                            ? 2 * model.particles.half_length(0, a) / model.grid.cell_size(a)
                            : 1.0;
  for (int j = 0; j < shifts; ++j) {
    const double f = double(j) / shifts;
    const std::array<double, 3> s{f * period[0], f * period[1], f * period[2]};
    std::ostringstream name;
    name << "shift " << s[0];
    const CriticalCourant c = critical_courant(shifted(model, s), options, tol, 2.0, resolution);
    out.all.emplace_back(name.str(), c.courant);
    if (c.courant < out.minimum.courant) {
      out.minimum = c;
      out.configuration = name.str();
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
