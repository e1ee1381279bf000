// SPDX-License-Identifier: BSD-3-Clause
// FMPM(k), XPIC(m), periodic FMPM and the update schemes inside the time step
// (FMPM 2026 §2.1, Fig. 1; §3.3), on the free-vibrating bar of §3.3.

#include "support.hpp"

#include <cmath>

using namespace smpm;
using smpm::test::approx;

using smpm::test::bar_energy_change;

TEST_CASE("FMPM(1) and XPIC(1) are PIC, step for step", "[step][fmpm]") {
  const BarSetup bar;
  Model pic = vibrating_bar(bar), fmpm1 = pic, xpic1 = pic;
  Stepper a({.shape = Shape::CPDI, .velocity = VelocityUpdate::PIC, .position_alpha = 0.5});
  Stepper b({.shape = Shape::CPDI,
             .velocity = VelocityUpdate::FMPM,
             .position_alpha = 0.5,
             .fmpm = {.order = 1}});
  Stepper c({.shape = Shape::CPDI,
             .velocity = VelocityUpdate::XPIC,
             .position_alpha = 0.5,
             .fmpm = {.order = 1}});
  for (int s = 0; s < 200; ++s) {
    a.step(pic, 0.1);
    b.step(fmpm1, 0.1);
    c.step(xpic1, 0.1);
  }
  CHECK((pic.particles.V - fmpm1.particles.V).cwiseAbs().maxCoeff() == 0.0); // identical
  CHECK((pic.particles.X - fmpm1.particles.X).cwiseAbs().maxCoeff() == 0.0);
  CHECK((pic.particles.V - xpic1.particles.V).cwiseAbs().maxCoeff() == 0.0);
  CHECK((pic.particles.F - xpic1.particles.F).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("periodic FMPM uses the FMPM loop once per Courant budget C_X", "[step][fmpm]") {
  // Bar wave speed 2, cell 1: Δt = 0.25 is C = 0.5 per step, so C_X = 2 is every 4th step.
  Model model = vibrating_bar({});
  Stepper stepper({.shape = Shape::CPDI,
                   .velocity = VelocityUpdate::FMPM,
                   .fmpm = {.order = 4},
                   .periodic_cx = 2.0});
  std::string pattern;
  for (int s = 0; s < 12; ++s) {
    stepper.step(model, 0.25);
    pattern += stepper.last_step_was_fmpm() ? 'F' : '.';
  }
  CHECK(pattern == "...F...F...F");
}

TEST_CASE("free-vibrating bar energies with FMPM(k), alpha = 1 and 1/2 (FMPM 2026 §3.3)",
          "[step][fmpm][validation]") {
  // Paper: FLIP and FMPM(k ≥ 2) end five periods within 0.03% of the initial energy (α = 1);
  // α = ½ (Eq. 9's consistent choice) loses more. Measured here (CPDI, USL): FMPM(4) and
  // FMPM(8) within 0.003%, FMPM(2) loses 0.085% at C = 0.2 and 0.041% at C = 0.4, and α = ½
  // loses 0.16–2.7%.
  for (double C : {0.2, 0.4})
    for (int k : {2, 4, 8}) {
      CAPTURE(C, k);
      StepOptions opt{.shape = Shape::CPDI, .velocity = VelocityUpdate::FMPM, .fmpm = {.order = k}};
      opt.position_alpha = 1.0;
      const double one = bar_energy_change(opt, C);
      opt.position_alpha = 0.5;
      const double half = bar_energy_change(opt, C);
      INFO("alpha = 1: " << one << ", alpha = 1/2: " << half);
      CHECK(std::abs(one) < (k == 2 ? 1e-3 : 3e-4));
      CHECK(half < 0);
      CHECK(std::abs(half) > std::abs(one));
    }
  // FMPM(1) near its stability limit dissipates strongly (paper: 27.7% at C = 0.86).
  const double pic = bar_energy_change(
      {.shape = Shape::CPDI, .velocity = VelocityUpdate::FMPM, .fmpm = {.order = 1}}, 0.8);
  INFO("FMPM(1) at C = 0.8: " << pic);
  CHECK(pic < -0.2);
}

TEST_CASE("every update scheme runs FMPM(4) on the bar without losing energy",
          "[step][fmpm][validation]") {
  // USF, USL+, USAVG, USAVG+ place the FMPM loop at tasks 1.c, 3.b and 4.c (FMPM 2026 Fig. 1).
  // Measured at C = 0.2: USL +0.0004%, USF +0.022%, USL+ +0.0003%, USAVG −0.0072%,
  // USAVG+ +0.0064%; asserted within 0.05%.
  for (UpdateScheme s : {UpdateScheme::USL, UpdateScheme::USF, UpdateScheme::USLPlus,
                         UpdateScheme::USAVG, UpdateScheme::USAVGPlus}) {
    CAPTURE(to_string(s));
    const double change = bar_energy_change({.shape = Shape::CPDI,
                                             .scheme = s,
                                             .velocity = VelocityUpdate::FMPM,
                                             .position_alpha = 1.0,
                                             .fmpm = {.order = 4}},
                                            0.2);
    CHECK(std::abs(change) < 5e-4);
  }
}
