// SPDX-License-Identifier: BSD-3-Clause
// The distributed component (sparsempm::petsc) against the serial library, on the 2D block of
// bench_step (SMPM_BENCH_SIDE² cells, 2 × 2 particles per cell: 10⁶ particles at the default
// side 500). Run under mpiexec by scripts/bench-petsc, which runs it on 1 and 2 ranks and prints
// the ratios; the serial baselines run only on one rank (in the same process as the 1-rank
// distributed ones).
//   FmpmPass/*      one pass of FMPM 2026 Table 1 (Eq. 6 with Eq. 5): fmpm_velocity of order 2
//   Exact/*         m̃ v = p on the block of side `arg` (nodes ≈ arg², up to 10⁶): CHOLMOD, and
//                   each KSP and MUMPS
//   MassSpectrum/*  ρ(A) and cond(m̃): Spectra, and SLEPc
//   RhoProduct/*    one product T x of the linearised step of FMPM(4) on the 10⁶-particle block
//                   (every Krylov–Schur iteration of a ρ(T) evaluation is one): LinearizedStep,
//                   and the same step across ranks (WindowSums) as spectral_radius runs it
//   Rho/*           one whole ρ(T) evaluation of FMPM(4) on the block of side `arg`: the serial
//                   spectral_radius (Spectra), and SLEPc's across ranks; SMPM_BENCH_RHO_SIDE adds
//                   one larger side
//   Step/*          whole time steps of the 10⁶-particle block (linear hats) and the
//   40,000-particle
//                   plate (uGIMP), FLIP and FMPM(4): the serial Stepper on 1 and 2 threads, and
//                   DistributedStepper (migration included) with the bytes each rank sent and
//                   received per step (the largest over the ranks)
// Every benchmark runs a fixed number of iterations: the ranks make the same collective calls.
#include "problems.hpp"

#include <benchmark/benchmark.h>
#include <sparsempm/exact.hpp>
#include <sparsempm/petsc.hpp>
#include <sparsempm/petsc_run.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>
#include <sparsempm/threads.hpp>

#include <cstdlib>
#include <map>
#include <memory>

namespace {

using namespace smpm;
namespace sp = smpm::petsc;

int ranks() {
  int n = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &n);
  return n;
}

// One block, serial and distributed, built on first use.
struct Block {
  Model model;
  Operators ops;
  ConsistentMass mt;
  Field p;
  std::unique_ptr<sp::DistributedGrid> grid;
  sp::DistributedOperators dops;
  sp::OwnedVec p_d;
  explicit Block(int side) : model(smpm::bench::block_model(2, {side, side, 1})) {
    if (ranks() == 1) {
      assemble(model.grid, model.particles, Shape::Linear, ops);
      assemble_consistent_mass(ops, mt);
      map_momentum(particle_operators(ops), model.particles.V, p);
    }
    grid = std::make_unique<sp::DistributedGrid>(model.grid);
    sp::assemble(*grid, model.particles, Shape::Linear, dops);
    const Particles own = sp::select_particles(model.particles, dops.particles);
    p_d = sp::momentum(*grid, dops, own.V);
  }
};

// The blocks, released before the PETSc session ends (main).
std::map<int, std::unique_ptr<Block>> blocks;

Block& block(int side) {
  auto& b = blocks[side];
  if (!b)
    b = std::make_unique<Block>(side);
  return *b;
}

void BM_FmpmPass_Serial(benchmark::State& state) {
  Block& b = block(smpm::bench::side());
  Field v;
  FmpmWorkspace w;
  for (auto _ : state) {
    lumped_solve(b.ops.m_inv, b.p, v);
    fmpm_velocity(b.ops, b.mt.matrix, {.order = 2}, {}, v, w);
    benchmark::DoNotOptimize(v.data());
  }
  state.counters["particles"] = double(b.model.particles.size());
}

void BM_FmpmPass_Petsc(benchmark::State& state) {
  Block& b = block(smpm::bench::side());
  sp::OwnedVec v = sp::node_vector(*b.grid, 2);
  sp::DistributedFmpmWorkspace w;
  for (auto _ : state) {
    SMPM_PETSC_CALL(VecPointwiseMult(v, b.dops.m_inv_d, b.p_d));
    sp::fmpm_velocity(*b.grid, b.dops, {.order = 2}, {}, v, w);
  }
  state.counters["ranks"] = ranks();
}

void BM_Exact_Cholmod(benchmark::State& state) {
  Block& b = block(int(state.range(0)));
  CholmodSolver solver;
  Field v;
  for (auto _ : state)
    solver.solve(b.ops, b.mt.matrix, {}, b.p, v);
  state.counters["nodes"] = double(b.ops.active.count());
}

void BM_Exact_Petsc(benchmark::State& state) {
  Block& b = block(int(state.range(0)));
  const auto method = sp::ExactMethod(state.range(1));
  sp::OwnedVec v = sp::node_vector(*b.grid, 2);
  sp::ExactSolveReport r;
  for (auto _ : state)
    r = sp::exact_solve(*b.grid, b.dops, {.method = method}, {}, b.p_d, v);
  state.SetLabel(std::string(sp::to_string(method)));
  state.counters["iterations"] = r.iterations;
  state.counters["ranks"] = ranks();
}

void BM_MassSpectrum_Spectra(benchmark::State& state) {
  Block& b = block(int(state.range(0)));
  for (auto _ : state)
    state.counters["rho_A"] = mass_spectrum(b.ops, b.mt.matrix).rho_A;
}

void BM_MassSpectrum_Slepc(benchmark::State& state) {
  Block& b = block(int(state.range(0)));
  for (auto _ : state)
    state.counters["rho_A"] = sp::mass_spectrum(*b.grid, b.dops).rho_A;
  state.counters["ranks"] = ranks();
}

// The options of the ρ(T) benchmarks: FMPM(4) with the block's linear shape functions, at C = 0.5.
StepOptions rho_options() {
  StepOptions o;
  o.shape = Shape::Linear;
  o.velocity = VelocityUpdate::FMPM;
  o.fmpm.order = 4;
  return o;
}

void BM_RhoProduct_Serial(benchmark::State& state) {
  const Model& model = block(smpm::bench::side()).model;
  const LinearizedStep T(model, rho_options(), stable_time_step(model, 0.5));
  Eigen::VectorXd x = Eigen::VectorXd::Ones(T.rows()), y(T.rows());
  for (auto _ : state) {
    T.perform_op(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  state.counters["rows"] = double(T.rows());
}

void BM_RhoProduct_Petsc(benchmark::State& state) {
  const Block& b = block(smpm::bench::side());
  Model local = b.model; // this rank's particles (DistributedOperators::particles)
  local.particles = sp::select_particles(b.model.particles, b.dops.particles);
  sp::WindowSums sums(*b.grid, b.dops);
  const LinearizedStep T(local, rho_options(), stable_time_step(b.model, 0.5), sums);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(T.rows()), y(T.rows());
  for (auto _ : state) {
    T.perform_op(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  state.counters["ranks"] = ranks();
}

void BM_Rho_Serial(benchmark::State& state) {
  const Model& model = block(int(state.range(0))).model;
  for (auto _ : state)
    state.counters["rho"] =
        spectral_radius(LinearizedStep(model, rho_options(), stable_time_step(model, 0.5))).rho_T;
  state.counters["rows"] = double(model.particles.size() * 6);
}

void BM_Rho_Petsc(benchmark::State& state) {
  const Block& b = block(int(state.range(0)));
  for (auto _ : state)
    state.counters["rho"] =
        sp::spectral_radius(*b.grid, b.model, rho_options(), stable_time_step(b.model, 0.5)).rho_T;
  state.counters["rows"] = double(b.model.particles.size() * 6);
  state.counters["ranks"] = ranks();
}

StepOptions step_options(const smpm::bench::Problem& pb, int order) {
  StepOptions o;
  o.shape = pb.shape;
  if (order > 1) {
    o.velocity = VelocityUpdate::FMPM;
    o.fmpm.order = order;
  }
  return o;
}

void BM_Step_Serial(benchmark::State& state, const std::string& name, int order, int threads) {
  smpm::bench::Problem pb = smpm::bench::make_problem(name);
  const int before = smpm::threads();
  smpm::set_threads(threads);
  Stepper stepper(step_options(pb, order));
  stepper.step(pb.model, pb.dt); // the first step makes the storage the others reuse
  for (auto _ : state)
    stepper.step(pb.model, pb.dt);
  smpm::set_threads(before);
  state.counters["particles"] = double(pb.model.particles.size());
}

void BM_Step_Petsc(benchmark::State& state, const std::string& name, int order) {
  smpm::bench::Problem pb = smpm::bench::make_problem(name);
  const sp::DistributedGrid grid(pb.model.grid);
  sp::RankModel local = sp::distribute(grid, pb.model);
  sp::DistributedStepper stepper(grid, step_options(pb, order));
  stepper.step(local, pb.dt);
  const double before = stepper.communicated_bytes();
  for (auto _ : state)
    stepper.step(local, pb.dt);
  double bytes = (stepper.communicated_bytes() - before) / double(state.iterations()), most = 0;
  MPI_Allreduce(&bytes, &most, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  state.counters["bytes_per_step"] = most;
  state.counters["particles"] = double(local.total);
  state.counters["ranks"] = ranks();
}

void register_benchmarks() {
  for (const std::string problem : {"block", "plate"})
    for (const int order : {1, 4}) {
      const std::string tail = problem + (order == 1 ? "/FLIP" : "/FMPM4");
      const int iterations = problem == "block" ? 6 : 40;
      if (ranks() == 1)
        for (const int threads : {1, 2})
          benchmark::RegisterBenchmark(
              ("Step/serial/" + tail + "/" + std::to_string(threads)).c_str(),
              [=](benchmark::State& s) { BM_Step_Serial(s, problem, order, threads); })
              ->Unit(benchmark::kMillisecond)
              ->Iterations(iterations);
      benchmark::RegisterBenchmark(("Step/petsc/" + tail).c_str(),
                                   [=](benchmark::State& s) { BM_Step_Petsc(s, problem, order); })
          ->Unit(benchmark::kMillisecond)
          ->Iterations(iterations);
    }
  const bool one = ranks() == 1;
  if (one)
    benchmark::RegisterBenchmark("FmpmPass/serial", BM_FmpmPass_Serial)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(20);
  benchmark::RegisterBenchmark("FmpmPass/petsc", BM_FmpmPass_Petsc)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(20);
  if (one)
    benchmark::RegisterBenchmark("RhoProduct/serial", BM_RhoProduct_Serial)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(5);
  benchmark::RegisterBenchmark("RhoProduct/petsc", BM_RhoProduct_Petsc)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(5);
  std::vector<int> rho_sides{25, 50};
  if (const char* s = std::getenv("SMPM_BENCH_RHO_SIDE"))
    rho_sides.push_back(std::atoi(s));
  for (int side : rho_sides) {
    if (one)
      benchmark::RegisterBenchmark("Rho/serial", BM_Rho_Serial)
          ->Args({side})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1);
    benchmark::RegisterBenchmark("Rho/petsc", BM_Rho_Petsc)
        ->Args({side})
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
  }
  for (int side : {100, 300, 700, 1000}) {
    if (one)
      benchmark::RegisterBenchmark("Exact/cholmod", BM_Exact_Cholmod)
          ->Args({side})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(2);
    for (int m = 0; m < 4; ++m)
      benchmark::RegisterBenchmark("Exact/petsc", BM_Exact_Petsc)
          ->Args({side, m})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(2);
  }
  for (int side : {100}) {
    if (one)
      benchmark::RegisterBenchmark("MassSpectrum/spectra", BM_MassSpectrum_Spectra)
          ->Args({side})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1);
    benchmark::RegisterBenchmark("MassSpectrum/slepc", BM_MassSpectrum_Slepc)
        ->Args({side})
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
  }
}

// The other ranks run the same benchmarks silently.
class Silent : public benchmark::BenchmarkReporter {
public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>&) override {}
};

} // namespace

int main(int argc, char** argv) {
  sp::Session session(&argc, &argv);
  benchmark::Initialize(&argc, argv);
  register_benchmarks();
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    benchmark::RunSpecifiedBenchmarks();
  } else {
    Silent silent;
    benchmark::RunSpecifiedBenchmarks(&silent);
  }
  benchmark::Shutdown();
  blocks.clear();
  return 0;
}
