// SPDX-License-Identifier: BSD-3-Clause
// Cost of the matrix form of MPM against a lean matrix-free step measured in the same run
// (FMPM 2026 §3.4, Eq. 3: relative time 1 + φ(k − 1)F).
//
//   build/tests/bench/bench_step [--benchmark_filter=...] [--benchmark_repetitions=3]
//
// Problems (SMPM_BENCH_SIDE sets the block's side, 500):
//   block         2D block of side × side cells, 2 × 2 particles per cell, linear shape functions,
//                 linear elastic, with two empty cells around it (side 500:
//                 10⁶ particles, 255,025 nodes);
//   plate         plane-strain plate of 200 × 50 cells, 2 × 2 per cell, uGIMP, linear elastic
//                 (40,000 particles); plate_cpdi and plate_b2cpdi: the same with CPDI and B2CPDI;
//   block3d       3D block of 40³ cells, 2 × 2 × 2 per cell, linear, linear elastic (512,000);
//   impact        examples/block_impact.toml (CPDI, neo-Hookean, 8000 particles);
//   small_body    a 40 × 40-cell block (uGIMP, 6400 particles) on a grid of 1000 × 1000 cells:
//                 FLIP and FMPM(4) steps on the particles' window and on the whole grid.
// For each, the baseline is a matrix-free USL FLIP step (plain loops over particles and nodes,
// linear shape functions, linear elasticity) on the same particles. Steps: FLIP and FMPM(k) for
// k = 2, 4, 8, 16, 20, 32 on 1 thread and ("/2t") on 2 (the same bits, threads.hpp), and the
// exact consistent-mass update on 1 (2D). "scaling/<N>/<step>/<threads>": ns per particle-step of
// the block for N = 10⁴, 10⁵, 10⁶. Printed after the runs: the ratios to the baseline, the targets
// of the step's cost at 1 and 2 threads (medians over --benchmark_repetitions, with the
// smallest and largest run), the FMPM pass's share of the STREAM triad bandwidth and the peak
// resident memory per particle.

#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/sparsempm.hpp>
#include <sparsempm/threads.hpp>

#include <benchmark/benchmark.h>

#include "matrix_free.hpp"
#include "problems.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <sys/resource.h>
#include <thread>

namespace {

using smpm::bench::make_problem;
using smpm::bench::Problem;
using smpm::bench::side;

// The matrix-free baseline works on linear shape functions and linear elasticity: give it the
// problem's particles with a linear material of the same moduli.
void BM_MatrixFree(benchmark::State& state, const std::string& problem) {
  Problem pb = make_problem(problem);
  for (auto& m : pb.model.materials)
    m.model = smpm::MaterialModel::Linear;
  const smpm::Grid& g = pb.model.grid;
  const int d = g.dim();
  // shift to a grid with origin 0 and unit cells, as the baseline indexes cells directly
  for (int a = 0; a < d; ++a)
    pb.model.particles.X.col(a) =
        (pb.model.particles.X.col(a).array() - g.origin(a)) / g.cell_size(a);
  const std::array<int, 3> nodes{g.nodes(0), d > 1 ? g.nodes(1) : 1, d > 2 ? g.nodes(2) : 1};
  auto run = [&](auto mf) {
    mf.step(pb.model, pb.dt); // warm-up
    for (auto _ : state)
      mf.step(pb.model, pb.dt);
  };
  if (d == 3)
    run(smpm::bench::MatrixFree<3>{nodes, {}, {}, {}});
  else
    run(smpm::bench::MatrixFree<2>{nodes, {}, {}, {}});
}

void BM_Assemble(benchmark::State& state, const std::string& problem) { // S, G_d, M, m
  Problem pb = make_problem(problem);
  smpm::Operators ops;
  smpm::assemble(pb.model.grid, pb.model.particles, pb.shape, ops);
  for (auto _ : state)
    smpm::assemble(pb.model.grid, pb.model.particles, pb.shape, ops);
}

void BM_AssembleFresh(benchmark::State& state, const std::string& problem) { // new pattern
  Problem pb = make_problem(problem);
  for (auto _ : state) {
    smpm::Operators ops;
    smpm::assemble(pb.model.grid, pb.model.particles, pb.shape, ops);
    benchmark::DoNotOptimize(ops.S.valuePtr());
  }
}

// Particles crossing cells: two configurations alternate, the second moving every seventh particle
// by half a cell along x, so that each assembly changes the pattern of S: the boxes of about
// one particle in fourteen move (linear: those past the middle of their cell).
void BM_AssembleCrossing(benchmark::State& state, const std::string& problem) {
  Problem pb = make_problem(problem);
  smpm::Particles moved = pb.model.particles;
  for (Eigen::Index p = 0; p < moved.size(); p += 7)
    moved.X(p, 0) += 0.5 * pb.model.grid.cell_size(0);
  smpm::Operators ops;
  smpm::assemble(pb.model.grid, pb.model.particles, pb.shape, ops);
  bool odd = false;
  for (auto _ : state) {
    odd = !odd;
    smpm::assemble(pb.model.grid, odd ? moved : pb.model.particles, pb.shape, ops);
  }
}

void BM_SetFromTriplets(benchmark::State& state, const std::string& problem) { // S only
  Problem pb = make_problem(problem);
  const smpm::Operators ops = smpm::assemble(pb.model.grid, pb.model.particles, pb.shape);
  std::vector<Eigen::Triplet<double>> t;
  for (auto _ : state) {
    t.clear();
    for (Eigen::Index p = 0; p < ops.S.outerSize(); ++p)
      for (smpm::SparseRowMatrix::InnerIterator it(ops.S, p); it; ++it)
        t.emplace_back(int(p), int(it.col()), it.value());
    smpm::SparseRowMatrix S(ops.S.rows(), ops.S.cols());
    S.setFromTriplets(t.begin(), t.end());
    benchmark::DoNotOptimize(S.valuePtr());
  }
}

void BM_ConsistentMass(benchmark::State& state, const std::string& problem) { // stencil scatter
  Problem pb = make_problem(problem);
  const smpm::Operators ops = smpm::assemble(pb.model.grid, pb.model.particles, pb.shape);
  smpm::ConsistentMass mt;
  smpm::assemble_consistent_mass(ops, mt);
  for (auto _ : state)
    smpm::assemble_consistent_mass(ops, mt);
}

void BM_ConsistentMassEigen(benchmark::State& state, const std::string& problem) { // Sᵀ M S
  Problem pb = make_problem(problem);
  const smpm::Operators ops = smpm::assemble(pb.model.grid, pb.model.particles, pb.shape);
  for (auto _ : state) {
    const smpm::SparseRowMatrix MS = ops.M.asDiagonal() * ops.S;
    smpm::SparseMatrix mt = smpm::SparseMatrix(ops.S.transpose()) * MS;
    benchmark::DoNotOptimize(mt.valuePtr());
  }
}

void BM_FmpmPass(benchmark::State& state, const std::string& problem) { // one Δv(ℓ) = A Δv(ℓ−1)
  Problem pb = make_problem(problem);
  const smpm::Operators ops = smpm::assemble(pb.model.grid, pb.model.particles, pb.shape);
  smpm::ConsistentMass mt;
  smpm::assemble_consistent_mass(ops, mt);
  smpm::Field p, v;
  smpm::map_momentum(smpm::particle_operators(ops), pb.model.particles.V, p);
  smpm::FmpmWorkspace fw;
  smpm::lumped_solve(ops.m_inv, p, v);
  fw.prev = v;
  long passes = 0;
  for (auto _ : state) { // the body of Table 1's loop: Δv(ℓ) = A Δv(ℓ−1), v += Δv(ℓ)
    smpm::fmpm_pass(ops.m_inv, mt.matrix, 1.0, fw.prev, fw.next, &v);
    fw.prev.swap(fw.next);
    if (++passes % 64 == 0)
      fw.prev = v; // keep the operand away from underflow (the increments decay)
  }
}

void BM_Step(benchmark::State& state, const std::string& problem, smpm::VelocityUpdate vel, int k,
             int threads = 1, smpm::NodeRange nodes = smpm::NodeRange::Particles) {
  smpm::set_threads(threads);
  Problem pb = make_problem(problem);
  smpm::StepOptions opt{.shape = pb.shape, .velocity = vel, .fmpm = {.order = k}, .nodes = nodes};
  if (vel == smpm::VelocityUpdate::Exact)
    opt.exact_solver = smpm::cholmod_solver_factory();
  smpm::Stepper stepper(opt);
  stepper.step(pb.model, pb.dt); // warm-up: sizes every workspace, CHOLMOD analysis
  for (auto _ : state)
    stepper.step(pb.model, pb.dt);
  state.counters["particles"] = double(pb.model.particles.size());
  smpm::set_threads(1);
}

// What advance() computes after every step besides the step itself: the energies and momentum
// of the particle state (the failure test and the series of a run), with the strain energy
// densities the step's stress update stored, and the largest particle speed for the next time
// step ("diagnostics"); and the same from the particle state alone, evaluating W(F_p) and the
// wave speed again ("diagnostics_recomputed": energies() and stable_time_step()).
void BM_Diagnostics(benchmark::State& state, const std::string& problem, bool fused) {
  Problem pb = make_problem(problem);
  smpm::Stepper stepper(smpm::StepOptions{.shape = pb.shape});
  stepper.step(pb.model, pb.dt); // a deformed state
  const double wave = smpm::max_wave_speed(pb.model.materials, pb.model.particles);
  for (auto _ : state) {
    if (fused) {
      const smpm::Energies e = stepper.energies(pb.model);
      benchmark::DoNotOptimize(std::max(wave, e.max_speed));
    } else {
      benchmark::DoNotOptimize(smpm::energies(pb.model));
      benchmark::DoNotOptimize(smpm::stable_time_step(pb.model, 0.5));
    }
  }
}

// Two blocks of 100 × 50 cells (2 × 2 particles per cell, GIMP, neo-Hookean, 40,000 particles)
// stacked on a grid line and pressed together (V_y = ∓0.01): the FLIP step in single material
// mode (one velocity field) and in multimaterial mode with contact (Coulomb μ = 0.2; contact
// 2020 §3.2) with AG normals and CP = 0.8, and with LR normals and d_LR (§3.1), one assembly
// of S with the fields as blocks of columns.
void BM_TwoBlocks(benchmark::State& state, bool contact, bool lr) {
  using namespace smpm;
  Model m(Grid(2, {0, 0, 0}, {1, 1, 1}, {104, 104, 1}));
  Material mat;
  mat.name = "block";
  mat.model = MaterialModel::NeoHookean;
  mat.youngs = 100;
  mat.poisson = 0.3;
  m.materials = {mat, mat};
  m.materials[1].name = "other";
  m.particles = make_block(m.grid, {2, 2, 0}, {102, 52, 0}, {2, 2, 1}, 1.0, 0);
  m.particles.V.col(1).setConstant(0.01);
  Particles top = make_block(m.grid, {2, 52, 0}, {102, 102, 0}, {2, 2, 1}, 1.0, 1);
  top.V.col(1).setConstant(-0.01);
  m.particles.append(top);
  if (contact) {
    ContactPair law;
    law.law = ContactLaw::Coulomb;
    law.friction = 0.2;
    law.detection = lr ? ContactDetection::LogisticRegression : ContactDetection::Position;
    law.normal = lr ? ContactNormal::LogisticRegression : ContactNormal::AverageGradient;
    m.contact.material_field = {0, 1};
    m.contact.pairs = {law};
  }
  Stepper stepper(StepOptions{.shape = Shape::GIMP});
  stepper.step(m, 0.05); // warm-up: sizes every workspace
  for (auto _ : state)
    stepper.step(m, 0.05);
  state.counters["particles"] = double(m.particles.size());
}
BENCHMARK_CAPTURE(BM_TwoBlocks, single_material, false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TwoBlocks, contact_AG_CP, true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TwoBlocks, contact_LR, true, true)->Unit(benchmark::kMillisecond);

// STREAM triad a = b + s c on three arrays of n doubles (3 × 10⁷ below: the machine's
// sustainable memory bandwidth), the bound for passes that stream S, G or m̃ from memory; on
// `threads` threads, each a contiguous share (what memory-bound kernels can gain from the second
// core). `sweeps` passes per thread and iteration keep the threads' start small beside short
// arrays.
void BM_StreamTriad(benchmark::State& state, int threads, size_t n, int sweeps) {
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  auto part = [&](int t) {
    for (int k = 0; k < sweeps; ++k)
      for (size_t i = n * size_t(t) / size_t(threads); i < n * size_t(t + 1) / size_t(threads); ++i)
        a[i] = b[i] + 3.0 * c[i];
  };
  for (auto _ : state) {
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t)
      pool.emplace_back(part, t);
    part(0);
    for (auto& th : pool)
      th.join();
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["GB/s"] = benchmark::Counter(
      3.0 * 8 * double(n) * sweeps * double(state.iterations()) / 1e9, benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_StreamTriad, 1_thread, 1, 10'000'000, 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_StreamTriad, 2_threads, 2, 10'000'000, 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// The same on 12 MB (3 × 5·10⁵ doubles), the size of the uGIMP plate's S, G_a, patterns and
// particle arrays: the ceiling of the plate's passes, which stream from the caches, not memory.
BENCHMARK_CAPTURE(BM_StreamTriad, cached_1_thread, 1, 500'000, 50)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_StreamTriad, cached_2_threads, 2, 500'000, 50)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Collects real times so that ratios to the baseline of the same run can be printed: the
// median over --benchmark_repetitions (the one run without), and the smallest and largest.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  std::map<std::string, double> ms, lo, hi;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs) {
      const std::string name = r.run_name.str();
      const double t = r.GetAdjustedRealTime();
      if (r.run_type == Run::RT_Iteration) {
        if (!lo.count(name))
          ms[name] = lo[name] = hi[name] = t;
        lo[name] = std::min(lo[name], t);
        hi[name] = std::max(hi[name], t);
      } else if (r.aggregate_name == "median") {
        ms[name] = t;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

const std::vector<int> kOrders{2, 4, 8, 16, 20, 32};

void register_problem(const std::string& pb) {
  using smpm::VelocityUpdate;
  auto reg = [&](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark((pb + "/" + name).c_str(), fn)->Unit(benchmark::kMillisecond);
  };
  reg("matrix_free_flip_step", [pb](benchmark::State& s) { BM_MatrixFree(s, pb); });
  reg("assemble_S_G_m", [pb](benchmark::State& s) { BM_Assemble(s, pb); });
  reg("assemble_S_G_m_new_pattern", [pb](benchmark::State& s) { BM_AssembleFresh(s, pb); });
  reg("assemble_S_G_m_crossing", [pb](benchmark::State& s) { BM_AssembleCrossing(s, pb); });
  reg("S_by_setFromTriplets", [pb](benchmark::State& s) { BM_SetFromTriplets(s, pb); });
  reg("consistent_mass_stencil", [pb](benchmark::State& s) { BM_ConsistentMass(s, pb); });
  reg("consistent_mass_eigen_product",
      [pb](benchmark::State& s) { BM_ConsistentMassEigen(s, pb); });
  reg("fmpm_pass", [pb](benchmark::State& s) { BM_FmpmPass(s, pb); });
  reg("diagnostics", [pb](benchmark::State& s) { BM_Diagnostics(s, pb, true); });
  reg("diagnostics_recomputed", [pb](benchmark::State& s) { BM_Diagnostics(s, pb, false); });
  for (int t : {1, 2}) {
    const std::string sfx = t == 1 ? "" : "/2t";
    reg("flip_step" + sfx,
        [pb, t](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FLIP, 1, t); });
    for (int k : kOrders)
      reg("fmpm" + std::to_string(k) + "_step" + sfx,
          [pb, k, t](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FMPM, k, t); });
  }
  if (pb.rfind("block3d", 0) != 0) // CHOLMOD's factor of the 3D m̃ is the cost there, not MPM
    reg("exact_step", [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::Exact, 1); });
}

// A small body on a large grid: FLIP and FMPM(4) steps on the particles' window of the grid
// (StepOptions::nodes, the default) and on every node of it.
void register_small_body() {
  using smpm::NodeRange;
  using smpm::VelocityUpdate;
  for (NodeRange nodes : {NodeRange::Particles, NodeRange::Grid})
    for (int k : {1, 4}) {
      const std::string name = std::string("small_body/") + (k == 1 ? "flip" : "fmpm4") +
                               (nodes == NodeRange::Grid ? "_step_grid" : "_step_window");
      benchmark::RegisterBenchmark(name.c_str(), [k, nodes](benchmark::State& s) {
        BM_Step(s, "small_body", k == 1 ? VelocityUpdate::FLIP : VelocityUpdate::FMPM, k, 1, nodes);
      })->Unit(benchmark::kMillisecond);
    }
}

// The scaling table: FLIP, FMPM(4) and FMPM(16) steps of the block for N = 10⁴, 10⁵, 10⁶.
const std::vector<std::pair<int, const char*>> kScaling{{50, "1e4"}, {158, "1e5"}, {500, "1e6"}};

void register_scaling() {
  using smpm::VelocityUpdate;
  for (const auto& [side, label] : kScaling)
    for (int k : {1, 4, 16})
      for (int t : {1, 2}) {
        const std::string pb = "scaling_" + std::to_string(side);
        const std::string name = std::string("scaling/") + label + "/" +
                                 (k == 1 ? std::string("flip") : "fmpm" + std::to_string(k)) + "/" +
                                 std::to_string(t);
        benchmark::RegisterBenchmark(name.c_str(), [pb, k, t](benchmark::State& s) {
          BM_Step(s, pb, k == 1 ? VelocityUpdate::FLIP : VelocityUpdate::FMPM, k, t);
        })->Unit(benchmark::kMillisecond);
      }
}

// Bytes one FMPM pass moves at least: m̃'s values, column indices and row offsets, and per node
// 1/m, Δv(ℓ−1) read, Δv(ℓ) written, v read and written.
double pass_bytes(const std::string& problem) {
  Problem pb = make_problem(problem);
  const smpm::Operators ops = smpm::assemble(pb.model.grid, pb.model.particles, pb.shape);
  smpm::ConsistentMass mt;
  smpm::assemble_consistent_mass(ops, mt);
  const double n = double(mt.matrix.rows()), nnz = double(mt.matrix.nonZeros());
  return 12 * nnz + 4 * n + 8 * n + 4 * 8 * n * pb.model.grid.dim();
}

const char* const kProblems[] = {"block",        "plate",   "plate_cpdi",
                                 "plate_b2cpdi", "block3d", "impact"};

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  smpm::set_threads(1); // the baseline is serial; the "/2t" steps set their own count
  for (const char* pb : kProblems)
    register_problem(pb);
  register_scaling();
  register_small_body();
  RatioReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  auto t = [&](const std::string& n) {
    const auto it = rep.ms.find(n);
    return it == rep.ms.end() ? std::nan("") : it->second;
  };
  auto spread = [&](const std::string& n) {
    char buf[64];
    if (!rep.lo.count(n))
      return std::string("");
    std::snprintf(buf, sizeof buf, "(%.3g-%.3g ms)", rep.lo[n], rep.hi[n]);
    return std::string(buf);
  };
  const double triad = t("BM_StreamTriad/1_thread/real_time"), triad_gbs = 240.0 / triad;
  const double triad2 = t("BM_StreamTriad/2_threads/real_time");
  for (const std::string pb : kProblems) {
    const double base = t(pb + "/matrix_free_flip_step");
    if (std::isnan(base))
      continue;
    std::printf("\n%s: ratios to the matrix-free USL FLIP step (%.3f ms)\n", pb.c_str(), base);
    for (const auto& [name, ms] : rep.ms)
      if (name.rfind(pb + "/", 0) == 0)
        std::printf("  %-36s %10.3f ms  %8.3f   %s\n", name.c_str() + pb.size() + 1, ms, ms / base,
                    spread(name).c_str());
    auto r = [&](const std::string& a, const std::string& b) {
      return t(pb + "/" + a) / t(pb + "/" + b);
    };
    const double pass = t(pb + "/fmpm_pass");
    std::printf("  F = fmpm_pass / matrix-free step                 %8.3f (target <= 0.05)\n",
                pass / base);
    if (!std::isnan(pass) && !std::isnan(triad))
      std::printf("  FMPM pass bandwidth / STREAM triad               %8.3f (target >= 0.6)\n",
                  pass_bytes(pb) / (pass * 1e6) / triad_gbs);
    std::printf("  assembly (S, G, m, m~) / matrix-free step        %8.3f (target <= 1.0)\n",
                (t(pb + "/assemble_S_G_m") + t(pb + "/consistent_mass_stencil")) / base);
    std::printf("  diagnostics (energies, time step) / FLIP step    %8.3f (target <= 0.05)\n",
                r("diagnostics", "flip_step"));
    for (const std::string sfx : {"", "/2t"}) {
      std::printf("  %s:\n", sfx.empty() ? "1 thread" : "2 threads");
      std::printf("    FLIP step / matrix-free step                   %8.3f (target <= 1.5)\n",
                  t(pb + "/flip_step" + sfx) / base);
      std::printf("    FMPM(20) step / FLIP step                      %8.3f (target <= 1.8)\n",
                  r("fmpm20_step" + sfx, "flip_step" + sfx));
      std::printf("    FMPM(k) / FLIP, k = 2 4 8 16 20 32            ");
      for (int k : kOrders)
        std::printf(" %.2f", r("fmpm" + std::to_string(k) + "_step" + sfx, "flip_step" + sfx));
      std::printf("\n");
    }
    std::printf("  2-thread speed-up: FLIP step %.3f, FMPM(4) step %.3f (target >= 1.7)\n",
                r("flip_step", "flip_step/2t"), r("fmpm4_step", "fmpm4_step/2t"));
    std::printf("  exact step / FMPM(4) step, / FMPM(20) step       %8.3f, %.3f\n",
                r("exact_step", "fmpm4_step"), r("exact_step", "fmpm20_step"));
  }
  if (!std::isnan(t("small_body/flip_step_window")))
    std::printf("\nsmall body (6400 particles, uGIMP) on 1000 x 1000 cells: step on the whole grid "
                "/ on the particles' window: FLIP %.1f, FMPM(4) %.1f\n",
                t("small_body/flip_step_grid") / t("small_body/flip_step_window"),
                t("small_body/fmpm4_step_grid") / t("small_body/fmpm4_step_window"));
  bool scaling = false;
  for (const auto& [side, label] : kScaling)
    scaling = scaling || !std::isnan(t(std::string("scaling/") + label + "/flip/1"));
  if (scaling) {
    std::printf("\nns per particle-step, 2D block, linear (1 thread / 2 threads):\n"
                "  N      FLIP            FMPM(4)         FMPM(16)\n");
    for (const auto& [side, label] : kScaling) {
      const double N = 4.0 * side * side;
      std::printf("  %-5s", label);
      for (const char* k : {"flip", "fmpm4", "fmpm16"}) {
        const std::string n = std::string("scaling/") + label + "/" + k + "/";
        std::printf("  %6.0f / %-6.0f", 1e6 * t(n + "1") / N, 1e6 * t(n + "2") / N);
      }
      std::printf("\n");
    }
  }
  const auto single = rep.ms.find("BM_TwoBlocks/single_material");
  for (const char* name : {"contact_AG_CP", "contact_LR"}) {
    const auto contact = rep.ms.find(std::string("BM_TwoBlocks/") + name);
    if (single != rep.ms.end() && contact != rep.ms.end())
      std::printf("two blocks: FLIP step with %s / single material mode %8.3f (target <= 2.0)\n",
                  name, contact->second / single->second);
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  const double N = 4.0 * side() * side();
  if (!std::isnan(triad))
    std::printf("\nSTREAM triad: %.1f GB/s on 1 thread, %.1f GB/s on 2 (2.4e8 bytes in %.3f, "
                "%.3f ms)\n",
                triad_gbs, 240.0 / triad2, triad, triad2);
  const double cached = t("BM_StreamTriad/cached_1_thread/real_time"),
               cached2 = t("BM_StreamTriad/cached_2_threads/real_time");
  if (!std::isnan(cached) && !std::isnan(cached2))
    std::printf(
        "STREAM triad on 12 MB (50 sweeps): %.1f GB/s on 1 thread, %.1f GB/s on 2 (%.2fx)\n",
        600.0 / cached, 600.0 / cached2, cached / cached2);
  std::printf("\npeak resident memory %.0f MiB: %.0f bytes per particle of the %d x %d block "
              "(target <= 700)\n",
              ru.ru_maxrss / 1024.0, ru.ru_maxrss * 1024.0 / N, side(), side());
  return 0;
}
