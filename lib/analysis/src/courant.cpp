// SPDX-License-Identifier: BSD-3-Clause
// The spectral critical Courant number: ρ of the linearised step at one configuration, searched
// from small C up (FMPM 2026 §3.3, Fig. 12A). The simulation method is simulation_courant.cpp's.

#include "sparsempm/stability.hpp"

#include "radius.hpp"
#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace smpm {

namespace {

// The search of critical_courant and critical_fourier: ρ at the parameter x (C or F) on the
// edges e_0 = 0, e_1 = 0.05, e_j = 2 e_{j−1} (up to x_max), then on a grid of spacing
// ≤ resolution inside one bracket [e_{j−1}, e_j]; below e_1 at the points e_1 / 4^j down to the
// floor and in the limit x → 0 (scan_small). `radius(x, steps)` gives ρ of the operator at x and
// the steps one application spans.
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
  double tol() const { return tol_; }
  double resolution() const { return resolution_; }
  // The start of the first bracket when a small x below it is unstable (e_0 = 0 otherwise).
  void set_base(double x) { edge_[0] = x; }
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

// Doubling: the edges upward from e_j until one is unstable. Returns true when every edge up to
// c_max is stable (C* = c_max, set in search.out).
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

// The grid points of [a, b]: i = 0 … n, spacing h ≤ resolution (n a power of 2).
struct BracketGrid {
  double a, b, h;
  Index n;
  double at(Index i) const { return i == n ? b : a + double(i) * h; }
};

BracketGrid grid_of(double a, double b, double resolution) {
  BracketGrid g{a, b, 0, 1};
  while ((g.b - g.a) / double(g.n) > resolution)
    g.n *= 2;
  g.h = (g.b - g.a) / double(g.n);
  return g;
}

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

// Bisection between the stable grid point s and the unstable u (either order): the stable point
// next to the transition, and ρ there in rho_s.
Index bisect(CourantSearch& search, const BracketGrid& g, Index s, Index u, double& rho_s) {
  double rho = 0;
  while (std::abs(u - s) > 1) {
    const Index mid = s + (u - s) / 2;
    if (search.stable(g.at(mid), rho)) {
      s = mid;
      rho_s = rho;
    } else {
      u = mid;
    }
  }
  return s;
}

// C* as the last stable grid point of [a, b] before the unstable b, a stable with ρ rho_a.
void critical_between(CourantSearch& search, double a, double b, double rho_a) {
  const BracketGrid g = grid_of(a, b, search.resolution());
  const Index s = bisect(search, g, 0, g.n, rho_a);
  search.out.critical_courant = g.at(s);
  search.out.rho_T = rho_a;
}

// stable_from as the first stable grid point of [a, b] after the unstable a, b stable.
void stable_between(CourantSearch& search, double a, double b) {
  const BracketGrid g = grid_of(a, b, search.resolution());
  double rho = 0;
  search.out.stable_from = g.at(bisect(search, g, g.n, 0, rho));
}

// The small x, from the bottom up: the limit x → 0 (with scan.limit; ρ at kLimitFraction of the
// lowest point, and the first-order term γ) and the points e_1 / 4^j down to the
// first at or below the floor. Each is a point of `points` with whether it is stable and ρ there.
struct SmallPoint {
  double x;
  bool stable;
  double rho;
};

std::vector<SmallPoint> scan_small(CourantSearch& search, const SmallCourantScan& scan) {
  std::vector<double> xs;
  for (double x = search.edge(1) / 4;; x /= 4) {
    xs.push_back(x);
    if (x <= scan.floor)
      break;
  }
  std::reverse(xs.begin(), xs.end());
  search.out.floor = xs.front();
  std::vector<SmallPoint> points;
  if (scan.limit) {
    SmallPoint p{kLimitFraction * xs.front(), false, 0};
    p.stable = search.stable(p.x, p.rho);
    points.push_back(p);
  }
  for (double x : xs) {
    SmallPoint p{x, false, 0};
    p.stable = search.stable(x, p.rho);
    points.push_back(p);
  }
  if (scan.limit) { // ρ(T(C)) ≈ ρ(T(0)) + γ C: γ is the growth over the time of a C = 1 step
    SmallPoint& limit = points.front();
    search.out.rho_limit = limit.rho;
    // γ by Richardson extrapolation from the two lowest points c and 4c: (16 d(c) − d(4c)) / 12c
    // with d = ρ − ρ(T(0)), exact for ρ quadratic in C (a term a C², whose growth per unit time
    // vanishes as C → 0, does not count); the secant d(c) / c when there is one point or ρ(4c)
    // is not finite.
    const double c = points[1].x, d1 = points[1].rho - limit.rho;
    double gamma = d1 / (c - limit.x);
    if (points.size() > 2 && std::isfinite(points[2].rho))
      gamma = (16 * d1 - (points[2].rho - limit.rho)) / (12 * c);
    search.out.growth_rate = gamma;
    limit.stable = limit.stable && gamma <= search.tol();
  }
  return points;
}

// The small x first, from the bottom up, and where the interval [stable_from, C*] starts (it
// holds the smallest stable x, f): sets small, stable_from and floor of search.out, and the
// bracket b and the hint the bracket search starts from. Returns true when the search is done
// (C* is among the small x, or no x is stable).
bool start_interval(CourantSearch& search, const SmallCourantScan& scan, Bracket& b, double& hint) {
  CriticalCourant& out = search.out;
  if (!(scan.floor < search.edge(1))) { // no small x: x → 0 taken as stable (e_0 = 0)
    out.small = SmallCourant::NotExamined;
    out.floor = search.edge(1);
    out.stable_from = std::numeric_limits<double>::quiet_NaN();
    return false;
  }
  const std::vector<SmallPoint> small = scan_small(search, scan);
  const auto first = std::find_if(small.begin(), small.end(), [](auto& p) { return p.stable; });
  out.small = scan.limit ? SmallCourant::Stable : SmallCourant::StableToFloor;
  if (first == small.end()) { // no small x is stable: the first stable edge starts the interval
    out.small = SmallCourant::UnstableBelow;
    double rho = 0;
    int k = 1;
    while (k <= search.last() && !search.stable(search.edge(k), rho))
      ++k;
    if (k > search.last()) {
      out.small = SmallCourant::Unstable;
      return true; // C* = 0: no x examined is stable
    }
    stable_between(search, k == 1 ? small.back().x : search.edge(k - 1), search.edge(k));
    if (k == search.last()) {
      out.critical_courant = search.edge(k);
      out.rho_T = rho;
      return true;
    }
    b = {.j = k + 1, .low_known = true, .high_known = false, .entered = false, .low_rho = rho};
    hint = 0;
    return double_up(search, b); // b.j > 1 from here: the bracket is found
  }
  if (first != small.begin()) { // an unstable small x below f
    out.small = SmallCourant::UnstableBelow;
    const SmallPoint& below = *(first - 1);
    if (scan.limit && first - 1 == small.begin()) // the limit x → 0
      out.stable_from = first->x;
    else
      stable_between(search, below.x, first->x);
  }
  // An unstable small x above f ends the interval there.
  const auto end = std::find_if(first, small.end(), [](auto& p) { return !p.stable; });
  if (end != small.end()) {
    critical_between(search, (end - 1)->x, end->x, (end - 1)->rho);
    return true;
  }
  if (out.small == SmallCourant::UnstableBelow) { // the first bracket starts at the top one
    search.set_base(small.back().x);
    b.low_rho = small.back().rho;
    if (hint < small.back().x)
      hint = 0;
  }
  return false;
}

} // namespace

std::string_view to_string(SmallCourant s) {
  switch (s) {
  case SmallCourant::Stable:
    return "stable";
  case SmallCourant::StableToFloor:
    return "stable to floor";
  case SmallCourant::NotExamined:
    return "not examined";
  case SmallCourant::UnstableBelow:
    return "unstable below";
  case SmallCourant::Unstable:
    return "unstable";
  }
  return "?";
}

std::string small_courant_text(SmallCourant small, double stable_from, double floor) {
  char text[64];
  switch (small) {
  case SmallCourant::Stable:
    return "stable to 0";
  case SmallCourant::StableToFloor:
    std::snprintf(text, sizeof text, "stable to %.4g", floor);
    return text;
  case SmallCourant::NotExamined:
    std::snprintf(text, sizeof text, "not examined below %.4g", floor);
    return text;
  case SmallCourant::UnstableBelow:
    std::snprintf(text, sizeof text, "unstable below %.4g", stable_from);
    return text;
  case SmallCourant::Unstable:
    return "unstable";
  }
  return "?";
}

std::string small_courant_text(const CriticalCourant& c) {
  return small_courant_text(c.small, c.stable_from, c.floor);
}

bool worse_small(SmallCourant a, double stable_from_a, SmallCourant b, double stable_from_b) {
  return std::pair(int(a), stable_from_a) > std::pair(int(b), stable_from_b);
}

std::string small_courant_cell(SmallCourant small, double stable_from, double floor,
                               const std::string& configuration, double smallest,
                               std::string_view parameter) {
  std::string text = small_courant_text(small, stable_from, floor);
  if (small == SmallCourant::UnstableBelow || small == SmallCourant::Unstable)
    text += " (" + configuration + ")";
  if (stable_from > smallest) // [stable_from, smallest] is empty
    text += ": no " + std::string(parameter) + " stable on every configuration";
  return text;
}

namespace detail {

CriticalCourant critical_parameter(const std::function<SpectralRadius(double, int&)>& radius,
                                   const char* what, double tol, double c_max, double resolution,
                                   double hint, const std::atomic<int>* interrupt,
                                   const SmallCourantScan& scan) {
  if (!(tol >= 0) || !std::isfinite(tol))
    throw InputError(std::string("the search for ") + what +
                     ": tol must be non-negative and finite, got " + number_text(tol));
  SMPM_VERIFY(c_max > 0 && std::isfinite(c_max) && resolution >= 1e-12 * c_max,
              std::string("the search for ") + what +
                  ": the largest value must be positive and finite and the resolution at least "
                  "1e-12 of it");
  SMPM_VERIFY(scan.floor > 0,
              std::string("the search for ") + what + ": the floor must be positive");
  hint = std::isfinite(hint) ? std::min(hint, c_max) : 0.0;
  CourantSearch search(radius, what, tol, c_max, resolution, interrupt);
  CriticalCourant& out = search.out;
  Bracket b;
  if (start_interval(search, scan, b, hint))
    return out;
  const double base_rho = b.low_rho;
  // C* is the last stable grid point before an unstable one: the same point whether the search
  // starts from the hint or from below, if stability is monotone in C (which bisection assumes
  // anyway).
  if (b.j > 1) {
    // doubling from the first stable edge has found the bracket
  } else if (hint > 0) { // the bracket that holds the hint
    while (b.j < search.last() && search.edge(b.j) <= hint)
      ++b.j;
    b.low_known = b.j == 1;
  } else if (double_up(search, b)) {
    return out;
  }
  for (;;) {
    const BracketGrid g = grid_of(search.edge(b.j - 1), search.edge(b.j), resolution);
    Index s = b.low_known ? 0 : -1, u = b.high_known ? g.n : -1; // stable s < unstable u
    double rho_s = b.low_rho;
    // In a bracket entered from a neighbour, its far end first, as doubling does.
    Index i = hint > g.a ? Index(std::floor((hint - g.a) / g.h)) : 0;
    if (b.entered)
      i = s >= 0 ? g.n : 0;
    gallop(search, g, i, s, u, rho_s);
    if (u < 0) { // stable at e_j: the transition is in a higher bracket
      if (b.j == search.last()) {
        out.critical_courant = g.b;
        out.rho_T = rho_s;
        return out;
      }
      b = {.j = b.j + 1, .low_known = true, .high_known = false, .entered = true, .low_rho = rho_s};
      continue;
    }
    if (s < 0) { // unstable at e_{j−1} (j > 1): in a lower bracket
      b = {.j = b.j - 1,
           .low_known = b.j - 1 == 1,
           .high_known = true,
           .entered = true,
           .low_rho = base_rho};
      continue;
    }
    s = bisect(search, g, s, u, rho_s);
    out.critical_courant = g.at(s);
    out.rho_T = rho_s;
    return out;
  }
}

} // namespace detail

SmallCourantScan small_courant_scan(const StepOptions& options) {
  if (options.periodic_cx > 0 && options.velocity != VelocityUpdate::FLIP) // T(C) spans ⌈C_X / C⌉
    return {.floor = std::numeric_limits<double>::infinity(), .limit = false}; // steps
  return {};
}

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
      tol, c_max, resolution, hint, interrupt, small_courant_scan(options));
}

CriticalCourant
critical_courant_search(const std::function<SpectralRadius(double courant, int& steps)>& radius,
                        double tol, double c_max, double resolution, double hint,
                        const std::atomic<int>* interrupt, const SmallCourantScan& small) {
  return detail::critical_parameter(radius, "C*", tol, c_max, resolution, hint, interrupt, small);
}

} // namespace smpm
