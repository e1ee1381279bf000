// SPDX-License-Identifier: BSD-3-Clause
// Spectral analysis at scale (issue target: ρ(T) of FMPM(4) in under 30 s and ρ(A) in under
// 5 s for a 2D plane-strain block of 10⁵ particles, on 2 cores): the matrix-free linearised
// update (power iteration, then Spectra's Arnoldi solver when an eigenvalue stands out; a stable
// C = 0.3 and an unstable C = 0.9), and ρ(A) with Spectra's Lanczos solver.
//
//   build/tests/bench/bench_stability      (SMPM_BENCH_STAB_SIDE: block side in cells, 158)

#include <sparsempm/problems.hpp>
#include <sparsempm/sparsempm.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>

namespace {

int side() {
  const char* s = std::getenv("SMPM_BENCH_STAB_SIDE");
  return s ? std::atoi(s) : 158; // 157² cells × 4 = 98,596 particles
}

smpm::Model block() {
  using namespace smpm;
  const int n = side();
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {n + 2, n + 2, 1}));
  Material mat;
  mat.name = "block";
  mat.model = MaterialModel::Linear;
  mat.youngs = 100;
  mat.poisson = 0.3;
  model.materials = {mat};
  model.particles = make_block(model.grid, {1.5, 1.5, 0}, {n + 0.5, n + 0.5, 0}, {2, 2, 1}, 1.0, 0);
  return model;
}

void BM_RhoT_FMPM4(benchmark::State& state) {
  const smpm::Model model = block();
  const smpm::StepOptions opt{
      .shape = smpm::Shape::CPDI, .velocity = smpm::VelocityUpdate::FMPM, .fmpm = {.order = 4}};
  for (auto _ : state) {
    const double C = double(state.range(0)) / 100; // Courant number
    const smpm::LinearizedStep T(model, opt, C / smpm::courant_of(model, 1.0));
    const double rho = smpm::spectral_radius(T, 0).rho_T; // Spectra, matrix-free
    state.counters["rho_T"] = rho;
  }
  state.counters["particles"] = double(model.particles.size());
}

void BM_RhoA(benchmark::State& state) {
  const smpm::Model model = block();
  const smpm::Operators ops = smpm::assemble(model.grid, model.particles, smpm::Shape::CPDI);
  smpm::ConsistentMass mt;
  smpm::assemble_consistent_mass(ops, mt);
  for (auto _ : state) {
    const smpm::MassSpectrum s = smpm::mass_spectrum(ops, mt.matrix, 0);
    state.counters["rho_A"] = s.rho_A;
    state.counters["cond_mt"] = s.cond_mt;
  }
  state.counters["active_nodes"] = double(ops.active.count());
}

// The C* search along a series (FMPM 2026 Fig. 12A's FMPM(k), k = 1 … 20, on the §3.3 bar at the
// lattice shift that sets the plateau): each search from scratch (range 0), or started from the
// C* of k − 1 (range 1, critical_courant's hint; the same C*). Counters: spectral radii computed
// and, for the hinted series, its time over the plain series' of the same run.
double g_plain_seconds = 0;

void BM_CourantSeries(benchmark::State& state) {
  const bool hinted = state.range(0) == 1;
  const smpm::Model bar = smpm::shifted(smpm::vibrating_bar({}), {0.375, 0, 0});
  int evaluations = 0;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    double hint = 0;
    evaluations = 0;
    for (int k = 1; k <= 20; ++k) {
      const smpm::StepOptions opt{
          .shape = smpm::Shape::CPDI, .velocity = smpm::VelocityUpdate::FMPM, .fmpm = {.order = k}};
      const smpm::CriticalCourant c = smpm::critical_courant(bar, opt, 1e-6, 2.0, 1e-3, hint);
      evaluations += c.evaluations;
      if (hinted)
        hint = c.critical_courant;
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["evaluations"] = evaluations;
  if (!hinted)
    g_plain_seconds = seconds;
  else if (g_plain_seconds > 0)
    state.counters["time_over_plain"] = seconds / g_plain_seconds;
}

BENCHMARK(BM_RhoT_FMPM4)->Arg(30)->Arg(90)->Unit(benchmark::kSecond)->Iterations(1); // C = 0.3, 0.9
BENCHMARK(BM_RhoA)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_CourantSeries)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);

} // namespace

BENCHMARK_MAIN();
