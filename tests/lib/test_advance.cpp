// SPDX-License-Identifier: BSD-3-Clause
// The run loop (advance.hpp): the Courant relation, the failure test, and stops that do not change
// the dynamics of a constant-step run (FMPM 2026 §3.3).

#include "support.hpp"

#include <cmath>

using namespace smpm;
using smpm::test::approx;

TEST_CASE("the Courant relation and its inverse", "[advance]") {
  // The §3.3 bar: wave speed √(E/ρ) = 2, cell 1, max |V| = 0.16 < 2, so Δt = C / 2.
  Model bar = vibrating_bar({});
  CHECK(signal_speed(bar) == approx(2.0, 1e-15));
  CHECK(stable_time_step(bar, 0.5) == approx(0.25, 1e-15));
  CHECK(courant_of(bar, 0.25) == approx(0.5, 1e-15));
  // A particle faster than the wave sets the speed.
  bar.particles.V(3, 0) = 5;
  CHECK(signal_speed(bar) == approx(5.0, 1e-15));
  CHECK(stable_time_step(bar, 0.5) == approx(0.1, 1e-15));
  CHECK_THROWS_AS(stable_time_step(bar, 0.0), InputError);
}

TEST_CASE("the failure test: energy growth with its threshold", "[advance]") {
  Model bar = vibrating_bar({});
  CHECK_NOTHROW(check_energy(bar, 9.9, 1.0, {}));
  CHECK_THROWS_WITH(check_energy(bar, 10.1, 1.0, {}), Catch::Contains("exceeds 10 times"));
  CHECK_THROWS_WITH(check_energy(bar, 2.1, 1.0, {.energy_growth = 2}),
                    Catch::Contains("exceeds 2 times") && Catch::Contains("fastest particle"));
  CHECK_NOTHROW(check_energy(bar, 1e9, 1.0, {.energy_growth = 0})); // off
  CHECK_THROWS_WITH(check_energy(bar, std::nan(""), 1.0, {}), Catch::Contains("not finite"));
  bar.gravity = {0, -9.8, 0}; // gravity does work: no growth test
  CHECK_NOTHROW(check_energy(bar, 1e9, 1.0, {}));
}

TEST_CASE("a failing run stops with the step named", "[advance]") {
  // FLIP on the §3.3 bar is unstable at C = 1.5 (C* ≈ 0.86, FMPM 2026 Fig. 12A).
  Model bar = vibrating_bar({});
  Stepper stepper({.shape = Shape::CPDI});
  CHECK_THROWS_WITH(advance(bar, stepper, {.end = 400, .courant = 1.5}),
                    Catch::StartsWith("step "));
  CHECK(bar.step > 0);
  CHECK(bar.time < 400);
}

TEST_CASE("stops do not change a constant-step run, landing on them does", "[advance]") {
  // land_on_stops = false: every step is the Courant step, so a run with stops every 7.3 is bit
  // for bit the run without stops; stops are reported at the first step past 7.3 k (10 of them)
  // and at the end (t ≥ 80). With landing, the steps before stops are shortened: the reports
  // fall exactly on 7.3 k and the state differs.
  const StepOptions opt{
      .shape = Shape::CPDI, .velocity = VelocityUpdate::FMPM, .fmpm = {.order = 4}};
  auto run = [&](double every, bool land, std::vector<double>& stops) {
    Model bar = vibrating_bar({});
    Stepper stepper(opt);
    advance(bar, stepper, {.end = 80, .courant = 0.3, .stop_every = every, .land_on_stops = land},
            [&](const Model& m, const Energies&, bool at_stop) {
              if (at_stop)
                stops.push_back(m.time);
            });
    return bar;
  };
  std::vector<double> none, constant, landed;
  const Model a = run(0, false, none), b = run(7.3, false, constant), c = run(7.3, true, landed);
  CHECK((a.particles.X - b.particles.X).cwiseAbs().maxCoeff() == 0.0);
  CHECK((a.particles.V - b.particles.V).cwiseAbs().maxCoeff() == 0.0);
  CHECK(a.step == b.step);
  REQUIRE(constant.size() == 11);
  REQUIRE(landed.size() == 11);
  for (int k = 1; k <= 10; ++k) {
    CHECK(constant[size_t(k - 1)] >= 7.3 * k - 80e-12);      // advance's tolerance: 1e-12 t_end
    CHECK(constant[size_t(k - 1)] < 7.3 * k + 0.15 + 1e-12); // within one step Δt = 0.15
    CHECK(landed[size_t(k - 1)] == approx(7.3 * k, 1e-12));
  }
  CHECK(constant.back() >= 80);
  CHECK(landed.back() == approx(80, 1e-12));
  CHECK((a.particles.X - c.particles.X).cwiseAbs().maxCoeff() > 0.0);
}

TEST_CASE("the energies of a step equal those of its particle state", "[advance]") {
  // Stepper::energies takes W(F_p) from the step's stress update; energies() evaluates it
  // again from F: the same terms in the same order, so the same bits (==). The largest speed
  // is max_p |V_p| (to one rounding: Eigen's norm may sum the axes in another order).
  auto block = [](int dim, MaterialModel model) {
    Model m(Grid(dim, {0, 0, 0}, {1, 1, 1}, {8, 8, 8}));
    Material mat = smpm::test::material("block", model, 100, 0.3);
    if (model == MaterialModel::MieGruneisen) {
      mat.bulk = 80;
      mat.shear = 30;
      mat.gruneisen = 1.6;
      mat.hugoniot_slope = 1.4;
    }
    m.materials = {mat};
    m.particles = make_block(m.grid, {2, 2, dim == 3 ? 2.0 : 0.0}, {6, 6, dim == 3 ? 6.0 : 0.0},
                             {2, 2, dim == 3 ? 2 : 1}, 1.0, 0);
    for (Index p = 0; p < m.particles.size(); ++p)
      for (int a = 0; a < dim; ++a) // a compression toward the centre and a shear
        m.particles.V(p, a) =
            -0.2 * (m.particles.X(p, a) - 4) + 0.1 * m.particles.X(p, (a + 1) % dim);
    return m;
  };
  std::vector<std::pair<std::string, Model>> models;
  models.emplace_back("1D linear bar", vibrating_bar({}));
  models.emplace_back("2D linear", block(2, MaterialModel::Linear));
  models.emplace_back("3D linear", block(3, MaterialModel::Linear));
  models.emplace_back("2D neo-Hookean", block(2, MaterialModel::NeoHookean));
  models.emplace_back("3D hyperelastic", block(3, MaterialModel::Hyperelastic));
  models.emplace_back("2D Mie-Gruneisen", block(2, MaterialModel::MieGruneisen));
  for (auto& [name, model] : models) {
    CAPTURE(name);
    Stepper stepper({.shape = Shape::GIMP});
    for (int s = 0; s < 5; ++s)
      stepper.step(model, stable_time_step(model, 0.3));
    const Energies fused = stepper.energies(model), direct = energies(model);
    CHECK(fused.strain == direct.strain);
    CHECK(fused.kinetic == direct.kinetic);
    CHECK(fused.total == direct.total);
    CHECK(fused.momentum == direct.momentum);
    CHECK(fused.max_speed == direct.max_speed);
    CHECK(direct.strain > 0);
    const double vmax = model.particles.V.rowwise().norm().maxCoeff();
    CHECK(std::abs(direct.max_speed - vmax) <= 2.3e-16 * vmax);
    // A stepper that has not stepped evaluates W from F.
    Model other = model;
    other.particles.F *= 1.01;
    Stepper fresh({.shape = Shape::GIMP});
    CHECK(fresh.energies(other).strain == energies(other).strain);
  }
}

TEST_CASE("an observer that changes the model sets the next time step", "[advance]") {
  // The §3.3 bar: Δt = C Δx / 2 until the observer gives a particle the speed 50 after the
  // first step; with observer_changes_model the second step has Δt = C Δx / 50 (without it the
  // loop takes the speed from the step's energies, before the change).
  Model bar = vibrating_bar({});
  Stepper stepper({.shape = Shape::CPDI});
  std::vector<double> times;
  advance(
      bar, stepper,
      {.end = 1.0, .courant = 0.5, .failure = {.energy_growth = 0}, .observer_changes_model = true},
      [&](const Model& m, const Energies&, bool) {
        times.push_back(m.time);
        if (times.size() == 1)
          bar.particles.V(3, 0) = 50;
      });
  REQUIRE(times.size() >= 2);
  CHECK(times[0] == approx(0.25, 1e-15));
  CHECK(times[1] - times[0] == approx(0.5 / 50, 1e-12));
}
