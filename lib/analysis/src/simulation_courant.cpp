// SPDX-License-Identifier: BSD-3-Clause
// The critical Courant number by simulation: bisection over full runs with the Courant time step
// held constant (FMPM 2026 §3.3, Fig. 12A, the paper's method).

#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <string>

namespace smpm {

double simulation_energy_change(const Model& start, const StepOptions& options, double courant,
                                const SimulationCourantOptions& sim) {
  Model model = start;
  Stepper stepper(options);
  const AdvanceOptions adv{.end = sim.end,
                           .courant = courant,
                           .stop_every = 0,
                           .land_on_stops = false, // constant Courant steps
                           .failure = sim.failure,
                           .energy_start = std::nullopt,
                           .interrupt = sim.interrupt};
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
      out.simulation_courant = hi;
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
      out.simulation_courant = hi;
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
  out.simulation_courant = lo;
  out.energy_change = e_lo;
  return out;
}

} // namespace smpm
