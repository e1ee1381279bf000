// SPDX-License-Identifier: BSD-3-Clause
// Critical Courant numbers: spectral (ρ of the linearised step at one configuration) and by
// simulation (bisection over full runs), FMPM 2026 §3.3, Fig. 12A.

#include "sparsempm/stability.hpp"

#include "radius.hpp"
#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace smpm {

namespace {

// The search of critical_courant and critical_fourier: ρ at the parameter x (C or F) on the
// edges e_0 = 0, e_1 = 0.05, e_j = 2 e_{j−1} (up to x_max), then on a grid of spacing
// ≤ resolution inside one bracket [e_{j−1}, e_j]. `radius(x, steps)` gives ρ of the operator at
// x and the steps one application spans.
class CourantSearch {
public:
  using Radius = std::function<SpectralRadius(double x, int& steps)>;
  CourantSearch(Radius radius, const char* what, double tol, double x_max, double resolution,
                const std::atomic<int>* interrupt)
      : radius_(std::move(radius)), what_(what), tol_(tol), resolution_(resolution),
        interrupt_(interrupt), edge_{0.0, std::min(0.05, x_max)} {
    while (edge_.back() < x_max)
      edge_.push_back(std::min(2 * edge_.back(), x_max));
  }

  // Whether ρ^{1/s} ≤ 1 + tol at x (the growth per step; a non-finite ρ is unstable).
  bool stable(double x, double& rho) {
    check_interrupt(interrupt_, [&] {
      return std::string("in the search for ") + what_ + " after " +
             std::to_string(out.evaluations) + " evaluations of rho(T)";
    });
    int steps = 1;
    const SpectralRadius r = radius_(x, steps);
    ++out.evaluations;
    out.not_converged += r.status == SpectralStatus::NotConverged;
    out.non_finite += r.status == SpectralStatus::NonFinite;
    rho = std::pow(r.rho_T, 1.0 / steps);
    return r.status != SpectralStatus::NonFinite && rho <= 1 + tol_;
  }

  double edge(int j) const { return edge_[size_t(j)]; }
  int last() const { return int(edge_.size()) - 1; }
  double resolution() const { return resolution_; }
  CriticalCourant out;

private:
  Radius radius_;
  const char* what_;
  double tol_, resolution_;
  const std::atomic<int>* interrupt_;
  std::vector<double> edge_;
};

// The bracket [e_{j−1}, e_j] being searched and what is known of its ends.
struct Bracket {
  int j = 1;
  bool low_known = true;   // e_{j−1} stable (e_0 = 0: the identity step, ρ = 1)
  bool high_known = false; // e_j unstable
  bool entered = false;    // moved in from a neighbouring bracket
  double low_rho = 1;      // ρ at e_{j−1} when it is known stable
};

// Doubling: the edges upward until one is unstable. Returns true when every edge up to c_max is
// stable (C* = c_max, set in search.out).
bool double_up(CourantSearch& search, Bracket& b) {
  double rho = 0;
  for (;; ++b.j) {
    if (!search.stable(search.edge(b.j), rho)) {
      b.high_known = true;
      return false;
    }
    b.low_rho = rho;
    if (b.j == search.last()) {
      search.out.critical_courant = search.edge(b.j);
      search.out.rho_T = rho;
      return true;
    }
  }
}

// The grid points of bracket b: i = 0 … n, spacing h ≤ resolution.
struct BracketGrid {
  double a, b, h;
  Index n;
  double at(Index i) const { return i == n ? b : a + double(i) * h; }
};

// Gallops on the grid of the bracket from index i until a stable s and an unstable u (s < u) are
// known, or one of them is shown not to exist in the bracket (s or u left at −1).
void gallop(CourantSearch& search, const BracketGrid& g, Index i, Index& s, Index& u,
            double& rho_s) {
  double rho = 0;
  if (s < 0 || u < 0)
    i = std::clamp(i, s + 1, u >= 0 ? u - 1 : g.n);
  for (Index step = 1; s < 0 || u < 0; step *= 2) {
    if (search.stable(g.at(i), rho)) {
      s = i;
      rho_s = rho;
      if (u >= 0 || i == g.n)
        break;
      i = std::min(g.n, i + step);
    } else {
      u = i;
      if (s >= 0 || i == 0)
        break;
      i = std::max(Index(0), i - step);
    }
  }
}

// Bisection between the stable grid point s and the unstable u: the last stable point.
void bisect(CourantSearch& search, const BracketGrid& g, Index s, Index u, double rho_s) {
  double rho = 0;
  while (u - s > 1) {
    const Index mid = s + (u - s) / 2;
    if (search.stable(g.at(mid), rho)) {
      s = mid;
      rho_s = rho;
    } else {
      u = mid;
    }
  }
  search.out.critical_courant = g.at(s);
  search.out.rho_T = rho_s;
}

} // namespace

namespace detail {

CriticalCourant critical_parameter(const std::function<SpectralRadius(double, int&)>& radius,
                                   const char* what, double tol, double c_max, double resolution,
                                   double hint, const std::atomic<int>* interrupt) {
  if (!(tol >= 0) || !std::isfinite(tol))
    throw InputError(std::string("the search for ") + what +
                     ": tol must be non-negative and finite, got " + number_text(tol));
  SMPM_VERIFY(c_max > 0 && std::isfinite(c_max) && resolution >= 1e-12 * c_max,
              std::string("the search for ") + what +
                  ": the largest value must be positive and finite and the resolution at least "
                  "1e-12 of it");
  hint = std::isfinite(hint) ? std::min(hint, c_max) : 0.0;
  CourantSearch search(radius, what, tol, c_max, resolution, interrupt);
  // C* is the last stable grid point before an unstable one: the same point whether the search
  // starts from the hint or from below, if stability is monotone in C (which bisection assumes
  // anyway).
  Bracket b;
  if (hint > 0) { // the bracket that holds the hint
    while (b.j < search.last() && search.edge(b.j) <= hint)
      ++b.j;
    b.low_known = b.j == 1;
  } else if (double_up(search, b)) {
    return search.out;
  }
  for (;;) {
    BracketGrid g{search.edge(b.j - 1), search.edge(b.j), 0, 1};
    while ((g.b - g.a) / double(g.n) > resolution)
      g.n *= 2;
    g.h = (g.b - g.a) / double(g.n);
    Index s = b.low_known ? 0 : -1, u = b.high_known ? g.n : -1; // stable s < unstable u
    double rho_s = b.low_rho;
    // In a bracket entered from a neighbour, its far end first, as doubling does.
    Index i = hint > g.a ? Index(std::floor((hint - g.a) / g.h)) : 0;
    if (b.entered)
      i = s >= 0 ? g.n : 0;
    gallop(search, g, i, s, u, rho_s);
    if (u < 0) { // stable at e_j: the transition is in a higher bracket
      if (b.j == search.last()) {
        search.out.critical_courant = g.b;
        search.out.rho_T = rho_s;
        return search.out;
      }
      b = {.j = b.j + 1, .low_known = true, .high_known = false, .entered = true, .low_rho = rho_s};
      continue;
    }
    if (s < 0) { // unstable at e_{j−1} (j > 1): in a lower bracket
      b = {.j = b.j - 1,
           .low_known = b.j - 1 == 1,
           .high_known = true,
           .entered = true,
           .low_rho = 1};
      continue;
    }
    bisect(search, g, s, u, rho_s);
    return search.out;
  }
}

} // namespace detail

CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol,
                                 double c_max, double resolution, double hint,
                                 const std::atomic<int>* interrupt) {
  LinearizedStep T(model, options, stable_time_step(model, 0.05));
  return critical_courant_search(
      [&](double C, int& steps) {
        T.set_dt(stable_time_step(model, C));
        steps = T.steps_per_application();
        return spectral_radius(T);
      },
      tol, c_max, resolution, hint, interrupt);
}

CriticalCourant
critical_courant_search(const std::function<SpectralRadius(double courant, int& steps)>& radius,
                        double tol, double c_max, double resolution, double hint,
                        const std::atomic<int>* interrupt) {
  return detail::critical_parameter(radius, "C*", tol, c_max, resolution, hint, interrupt);
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
