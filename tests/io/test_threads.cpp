// SPDX-License-Identifier: BSD-3-Clause
// Expression boundary conditions in copies of a Model evaluated on two threads at once (the
// simulation method of `smpm stability` runs one bisection per thread): each copy owns its
// parser, so concurrent evaluations give exactly the serial values.

#include "support.hpp"

#include <sparsempm/input.hpp>
#include <sparsempm/stability.hpp>

#include <atomic>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

using namespace smpm;

namespace {
// The §3.3 bar with its x = 0 end driven by an expression velocity BC.
RunConfig driven_bar() {
  std::ifstream in(std::string(SMPM_EXAMPLES_DIR) + "/vibrating_bar.toml");
  std::ostringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const std::string fixed = "fixed = [\"x\"]";
  const size_t at = text.find(fixed);
  REQUIRE(at != std::string::npos);
  text.replace(at, fixed.size(), "velocity = { direction = [1.0], value = \"0.01*sin(0.1*t)\" }");
  return read_input(text, "driven_bar.toml", {"time.end=40"});
}
} // namespace

TEST_CASE("copies of a model evaluate their expression BCs independently", "[io][threads]") {
  // Two threads, each with its own copy, evaluate v_b(t) = 0.01 sin(0.1 t) at different times
  // 200,000 times; a shared parser would mix their variables. Every value must be exact.
  const RunConfig cfg = driven_bar();
  REQUIRE(cfg.model.bcs.conditions.size() == 1);
  std::atomic<long> wrong{0};
  auto worker = [&](double t0) {
    const Model copy = cfg.model;
    const VelocityCondition& c = copy.bcs.conditions[0];
    for (int k = 0; k < 200000; ++k) {
      const double t = t0 + 1e-3 * (k % 1000);
      if (c.value_at(t, Eigen::Vector3d::Zero()) != 0.01 * std::sin(0.1 * t))
        ++wrong;
    }
  };
  std::thread a(worker, 0.0), b(worker, 50.0);
  a.join();
  b.join();
  CHECK(wrong == 0);
}

TEST_CASE("the simulation method gives the serial result on two threads", "[io][threads]") {
  // One driven-bar run (FMPM(4), C = 0.3) per thread from the same configuration: both energy
  // changes equal the serial one bit for bit.
  const RunConfig cfg = driven_bar();
  const StepOptions opt{
      .shape = Shape::CPDI, .velocity = VelocityUpdate::FMPM, .fmpm = {.order = 4}};
  const SimulationCourantOptions sim{.end = cfg.time.end};
  const double serial = simulation_energy_change(cfg.model, opt, 0.3, sim);
  REQUIRE(std::isfinite(serial));
  double r1 = 0, r2 = 0;
  std::thread a([&] { r1 = simulation_energy_change(cfg.model, opt, 0.3, sim); });
  std::thread b([&] { r2 = simulation_energy_change(cfg.model, opt, 0.3, sim); });
  a.join();
  b.join();
  CHECK(r1 == serial);
  CHECK(r2 == serial);
}
