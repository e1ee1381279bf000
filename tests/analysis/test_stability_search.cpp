// SPDX-License-Identifier: BSD-3-Clause
// The C* search examines small C before it brackets C*: the points 0.05 / 4^j down to the floor
// and the limit C → 0, so that the interval it reports, [stable_from, C*], holds no unstable
// point it has seen (stability.hpp, critical_courant_search).

#include "support.hpp"

#include <sparsempm/stability.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <tuple>
#include <vector>

using namespace smpm;

namespace {

// A search on a made-up ρ(C): the logic alone, with the default tol 1e-6 and resolution 1e-3.
CriticalCourant search(const std::function<double(double)>& rho, double hint = 0,
                       SmallCourantScan small = {}) {
  return critical_courant_search(
      [&](double C, int& steps) {
        steps = 1;
        return SpectralRadius{rho(C), SpectralStatus::Converged};
      },
      1e-6, 2.0, 1e-3, hint, nullptr, small);
}

// ρ(T(C)) of the linearised step of `model` (the growth per step).
double rho_at(const Model& model, const StepOptions& options, double C) {
  const LinearizedStep T(model, options, stable_time_step(model, C));
  return std::pow(spectral_radius(T).rho_T, 1.0 / T.steps_per_application());
}

} // namespace

TEST_CASE("the search's interval starts where small C become stable", "[stability]") {
  // The small points are 0.0125, 0.003125 and 7.8125e-4. The grids at resolution 1e-3:
  // [0.0125, 0.05] and [0.003125, 0.0125] have spacing h = 0.0375 / 64 = 0.009375 / 16 =
  // 5.859375e-4, [0.4, 0.8] spacing 0.4 / 512. Stable below 0.6995 with nothing unstable beneath:
  // C* the last grid point of [0.4, 0.8] below it, 0.69921875, and stable to 0. Grid points to
  // 1e-12 (a + i h).
  const auto at = [](double x) { return smpm::test::approx(x, 1e-12); };
  CriticalCourant c = search([](double C) { return C > 0.6995 ? 1.1 : 1.0; });
  CHECK(c.critical_courant == at(0.69921875));
  CHECK(c.stable_from == 0);
  CHECK(c.small == SmallCourant::Stable);
  CHECK(small_courant_text(c) == "stable to 0");
  CHECK(c.floor == 0.05 / 64); // the first 0.05 / 4^j at or below kCourantFloor
  CHECK(c.growth_rate == 0);

  // Unstable below 0.04: stable_from is the first grid point of [0.0125, 0.05] above 0.04,
  // 0.0125 + 47 h = 0.0400390625; C* as before, with or without a hint.
  const double h = 0.0375 / 64;
  const auto band = [](double C) { return C < 0.04 || C > 0.6995 ? 1.01 : 1.0; };
  for (double hint : {0.0, 0.01, 0.5, 0.69921875}) {
    CAPTURE(hint);
    c = search(band, hint);
    CHECK(c.critical_courant == at(0.69921875));
    CHECK(c.stable_from == at(0.0125 + 47 * h));
    CHECK(c.small == SmallCourant::UnstableBelow);
    CHECK(small_courant_text(c) == "unstable below 0.04004");
  }

  // Unstable below 0.004 only: the interval starts in [0.003125, 0.0125] at 0.003125 + 2 h,
  // the first bracket starts at the top small point 0.0125, and the hint, above it, is used:
  // the same C* from every hint.
  for (double hint : {0.0, 0.01, 0.03, 0.15, 0.5}) {
    CAPTURE(hint);
    c = search([](double C) { return C < 0.004 || C > 0.6995 ? 1.01 : 1.0; }, hint);
    CHECK(c.critical_courant == at(0.69921875));
    CHECK(c.stable_from == at(0.003125 + 2 * h));
    CHECK(c.small == SmallCourant::UnstableBelow);
  }
  // Stable on [0.004, 0.045] only, from a hint in [0.1, 0.2]: the gallop descends to the first
  // bracket, [0.0125, 0.05], whose start is known stable: C* = 0.0125 + 55 h, ρ = 1.
  c = search([](double C) { return C < 0.004 || C > 0.045 ? 1.01 : 1.0; }, 0.15);
  CHECK(c.critical_courant == at(0.0125 + 55 * h));
  CHECK(c.rho_T == 1.0);
  CHECK(c.stable_from == at(0.003125 + 2 * h));

  // Unstable at every small C and up to 0.3004: the first stable edge (0.4) starts the interval,
  // stable_from is the first grid point of [0.2, 0.4] above 0.3004 (0.2 + 129 · 0.2 / 256).
  c = search([](double C) { return C < 0.3004 || C > 0.6995 ? 1.01 : 1.0; });
  CHECK(c.critical_courant == at(0.69921875));
  CHECK(c.stable_from == at(0.2 + 129 * 0.2 / 256));
  CHECK(c.small == SmallCourant::UnstableBelow);

  // A stable pocket: stable below 0.01, unstable on (0.01, 0.02), stable above. The interval is
  // the one that holds small C: C* is the last grid point of [0.003125, 0.0125] at or below
  // 0.01, 0.003125 + 11 h, and nothing below it is unstable.
  c = search([](double C) { return C > 0.01 && C < 0.02 ? 1.01 : 1.0; });
  CHECK(c.critical_courant == at(0.003125 + 11 * h));
  CHECK(c.stable_from == 0);
  CHECK(c.small == SmallCourant::Stable);

  // No C stable: C* = 0.
  c = search([](double) { return 1.01; });
  CHECK(c.critical_courant == 0);
  CHECK(c.small == SmallCourant::Unstable);
  CHECK(small_courant_text(c) == "unstable");
}

TEST_CASE("the limit C -> 0 is judged by T(0) and its first-order term", "[stability]") {
  // ρ = 1 + γ C below C = 0.004 (1 from there to 0.4995): the two lowest points, 7.8e-4 and
  // 3.1e-3, pass ρ ≤ 1 + 10⁻⁶, but the growth per unit time does not vanish as C → 0. γ = 10⁻⁴
  // (> tol): the limit is unstable and the interval starts at the floor; γ = 10⁻⁷ (≤ tol):
  // stable to 0. growth_rate is γ to round-off (Richardson's extrapolation of a linear
  // function: ρ's rounding 1e-16 over γ C_floor, 7.8e-8 and 7.8e-11).
  for (double gamma : {1e-4, 1e-7}) {
    CAPTURE(gamma);
    const CriticalCourant c = search([gamma](double C) {
      return C < 0.004 ? 1 + gamma * C : C < 0.4995 ? 1.0 : 1.1;
    });
    CHECK(c.growth_rate == smpm::test::approx(gamma, 0, 1e-4));
    CHECK(c.rho_limit == smpm::test::approx(1, 1e-12));
    CHECK(c.critical_courant == smpm::test::approx(0.5 - 0.4 / 512, 1e-12));
    CHECK(c.stable_from == (gamma > 1e-6 ? c.floor : 0.0));
  }
  // ρ = 1 + 0.05 C² below C = 0.004: a growth per unit time that vanishes as C → 0. The secant
  // through the floor would give 0.05 · 7.8e-4 = 3.9e-5 > tol; Richardson's γ is 0 to round-off
  // and the limit is stable.
  {
    const CriticalCourant c = search([](double C) {
      return C < 0.004 ? 1 + 0.05 * C * C : C < 0.4995 ? 1.0 : 1.1;
    });
    CHECK(std::abs(c.growth_rate) < 1e-9);
    CHECK(c.small == SmallCourant::Stable);
    CHECK(c.stable_from == 0);
  }
  // An unstable T(0) (ρ = 1.01 at any small C) with every grid point from 0.05 up stable.
  CriticalCourant c = search([](double C) { return C < 1e-5 ? 1.01 : 1.0; });
  CHECK(c.small == SmallCourant::UnstableBelow);
  CHECK(c.stable_from == c.floor);
  CHECK(c.critical_courant == 2.0);
  // Without the limit (periodic FMPM): the scan stops at the floor and says so.
  c = search([](double C) { return C < 1e-5 ? 1.01 : 1.0; }, 0, {.floor = 0.03, .limit = false});
  CHECK(c.small == SmallCourant::StableToFloor);
  CHECK(c.floor == 0.0125);
  CHECK(std::isnan(c.rho_limit));
  CHECK(small_courant_text(c) == "stable to 0.0125");
  // A floor at or above e_1 = 0.05: no small C examined, the search of earlier versions (C → 0
  // taken as stable), as critical_courant does for periodic FMPM, whose T(C) spans ⌈C_X / C⌉
  // steps. The instability below 0.004 is not seen, and the status says so.
  constexpr double inf = std::numeric_limits<double>::infinity();
  c = search([](double C) { return C < 0.004 || C > 0.6995 ? 1.01 : 1.0; }, 0,
             {.floor = inf, .limit = false});
  CHECK(c.small == SmallCourant::NotExamined);
  CHECK(std::isnan(c.stable_from));
  CHECK(c.critical_courant == smpm::test::approx(0.69921875, 1e-12));
  CHECK(small_courant_text(c) == "not examined below 0.05");
  StepOptions periodic{.velocity = VelocityUpdate::FMPM, .fmpm = {.order = 4}};
  periodic.periodic_cx = 2;
  CHECK(small_courant_scan(periodic).floor == inf);
  CHECK(small_courant_scan({}).floor == kCourantFloor);
}

TEST_CASE("no reported interval holds an unstable point: the bar with and without gradients",
          "[stability][long]") {
  // The §3.3 bar (CPDI, USL, α = 1). With the velocity-gradient transfer, FLIP at lattice shift
  // 1/8 of a cell has an eigenvalue of modulus above 1 below C ≈ 0.042, 1 + γ C with γ = 0.016
  // as C → 0 (measured ρ − 1 = 1.6e-5 at C = 0.001, 1.7e-4 at 0.02, 1.5e-14 at 0.05), and is
  // stable from there to 1.164: the search reports that interval and growth_rate γ, and an
  // independent evaluation of ρ(T) inside the unstable part is above 1 + tol. Without
  // gradients FLIP at shift 0 is stable from C → 0 to C* = 0.755 (Fig. 12A's bar;
  // docs/studies/stability.md), with γ at round-off (|γ| < 1e-10). In each reported interval ρ(T) ≤
  // 1 + 10⁻⁶ on 24 points spread logarithmically from its lower end (or 10⁻⁴) to C*.
  const Model bar = vibrating_bar({});
  const StepOptions gradient{.shape = Shape::CPDI, .transfer = Transfer::VelocityGradient};
  const StepOptions standard{.shape = Shape::CPDI};
  const Model shifted_bar = shifted(bar, {0.125, 0, 0});

  const CriticalCourant g = critical_courant(shifted_bar, gradient);
  CHECK(g.small == SmallCourant::UnstableBelow);
  CHECK(g.stable_from == smpm::test::approx(0.0422, 0.001));
  CHECK(g.critical_courant == smpm::test::approx(1.164, 0.001));
  CHECK(g.growth_rate == smpm::test::approx(0.016, 0.0005));
  CHECK(rho_at(shifted_bar, gradient, 0.02) > 1 + 1e-4);
  CHECK(rho_at(shifted_bar, gradient, 0.001) > 1 + 1e-5);

  const CriticalCourant s = critical_courant(bar, standard);
  CHECK(s.small == SmallCourant::Stable);
  CHECK(s.stable_from == 0);
  CHECK(s.critical_courant == smpm::test::approx(0.755, 0.001));
  CHECK(std::abs(s.growth_rate) < 1e-10);

  for (const auto& [model, options, c] :
       {std::tuple{shifted_bar, gradient, g}, std::tuple{bar, standard, s}}) {
    const double lo = std::max(c.stable_from, 1e-4), hi = c.critical_courant;
    for (int i = 0; i < 24; ++i) {
      const double C = lo * std::pow(hi / lo, i / 23.0);
      CAPTURE(C);
      CHECK(rho_at(model, options, C) <= 1 + 1e-6);
    }
  }
}

TEST_CASE("a dense rho(T) that Eigen's real Schur iteration cannot resolve is resolved",
          "[stability]") {
  // The §3.3 bar with quadratic B-splines, APIC and FMPM(4) blended with FMPM(2) (α = 0.8) at
  // C = 0.003125, one of the search's small points: T (240 rows, dense) is near the identity
  // and Eigen's EigenSolver stops without converging, which the search took for ρ = ∞, an
  // unstable point (it reported C* = 0.0025). The complex Schur iteration resolves it: ρ(T) = 1
  // to 1e-12 (numpy's LAPACK: 1 + 6e-15).
  const Model bar = vibrating_bar({});
  const StepOptions o{.shape = Shape::BSpline2,
                      .velocity = VelocityUpdate::FMPM,
                      .fmpm = {.order = 4, .blend_alpha = 0.8, .blend_every = 2},
                      .transfer = Transfer::Apic};
  const LinearizedStep T(bar, o, stable_time_step(bar, 0.003125));
  const SpectralRadius r = spectral_radius(T);
  CHECK(r.status == SpectralStatus::Converged);
  CHECK(std::abs(r.rho_T - 1) <= 1e-12);
}
