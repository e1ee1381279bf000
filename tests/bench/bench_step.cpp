// Cost of the matrix form of MPM against a lean matrix-free step measured in the same run
// (FMPM 2026 §3.4, Eq. 3: relative time 1 + φ(k − 1)F).
//
//   build/tests/bench/bench_step [--benchmark_filter=...]
//
// Problems: "block", a 2D block of side × side cells with 2 × 2 particles per cell (linear
// shape functions, linear elastic; side = 500 gives 10⁶ particles and 251,001 nodes; set
// SMPM_BENCH_SIDE to change it), "plate", a plane-strain plate of 200 × 50 cells (uGIMP,
// 2 × 2 per cell, linear elastic, 39,204 particles), and "impact", examples/block_impact.toml
// (CPDI, neo-Hookean, 8000 particles). For each problem the baseline is the matrix-free USL FLIP
// step below, run on the same particles with linear shape functions. Printed after the runs: every
// time as a ratio to that baseline, F = (one FMPM pass)/(baseline), FMPM(20)/FLIP, exact/FMPM(k),
// and the peak resident memory per particle. Everything runs on one thread except the steps named
// "..._2_threads" (the same FLIP and FMPM(4) steps on two threads; their speed-ups over one
// thread are printed; the results are the same bits, threads.hpp).

#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/sparsempm.hpp>
#include <sparsempm/threads.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <sys/resource.h>

namespace {

int side() {
  const char* s = std::getenv("SMPM_BENCH_SIDE");
  return s ? std::atoi(s) : 500;
}

smpm::Model block_model(int n, int ny = 0) {
  using namespace smpm;
  if (ny == 0)
    ny = n;
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {n, ny, 1}));
  Material mat;
  mat.name = "block";
  mat.youngs = 100;
  mat.poisson = 0.3;
  model.materials = {mat};
  model.particles =
      make_block(model.grid, {0.5, 0.5, 0}, {n - 0.5, ny - 0.5, 0}, {2, 2, 1}, 1.0, 0);
  auto& P = model.particles;
  for (Eigen::Index p = 0; p < P.size(); ++p) { // a smooth velocity field
    P.V(p, 0) = 0.01 * std::sin(0.1 * P.X(p, 1));
    P.V(p, 1) = 0.01 * std::cos(0.1 * P.X(p, 0));
  }
  return model;
}

struct Problem {
  std::string name;
  smpm::Model model;
  smpm::Shape shape;
  double dt;
};

Problem make_problem(const std::string& name) {
  if (name == "block") {
    smpm::Model m = block_model(side());
    return {name, m, smpm::Shape::Linear, 1e-4};
  }
  if (name == "plate") { // 2D plane strain, 200 × 50 cells, 2 × 2 per cell: 39,204 particles
    smpm::Model m = block_model(201, 51);
    m.materials[0].model = smpm::MaterialModel::Linear;
    return {name, m, smpm::Shape::GIMP, 1e-4};
  }
  smpm::RunConfig cfg =
      smpm::read_input_file(std::string(SMPM_EXAMPLES_DIR) + "/block_impact.toml");
  // The cost of a step does not depend on Δt: a tiny one keeps the particles in place however
  // many iterations the benchmark runs.
  return {name, cfg.model, cfg.step.shape, 1e-6 * smpm::stable_time_step(cfg.model, 0.2)};
}

// The baseline: one USL FLIP step written as plain loops over particles and nodes.
struct MatrixFree {
  int nx, ny;
  std::vector<double> m, px, py, fx, fy;
  void step(smpm::Model& model, double dt) {
    auto& P = model.particles;
    const double lam = model.materials[0].lame_lambda(), G = model.materials[0].shear_modulus();
    const Eigen::Index N = P.size();
    const size_t n = size_t(nx) * ny;
    m.assign(n, 0);
    px.assign(n, 0);
    py.assign(n, 0);
    fx.assign(n, 0);
    fy.assign(n, 0);
    for (Eigen::Index p = 0; p < N; ++p) { // P2G: mass, momentum, internal force
      const double x = P.X(p, 0), y = P.X(p, 1);
      const int i = int(x), j = int(y);
      const double tx = x - i, ty = y - j;
      const double wx[2] = {1 - tx, tx}, wy[2] = {1 - ty, ty}, gx[2] = {-1, 1};
      const double F00 = P.F(p, 0), F01 = P.F(p, 1), F10 = P.F(p, 2), F11 = P.F(p, 3);
      const double vol = P.volume0[p] * (F00 * F11 - F01 * F10);
      const double sxx = P.stress(p, 0), sxy = P.stress(p, 1), syy = P.stress(p, 3);
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const size_t k = size_t(i + a) + size_t(j + b) * nx;
          const double w = wx[a] * wy[b], dx = gx[a] * wy[b], dy = wx[a] * gx[b];
          m[k] += w * P.mass[p];
          px[k] += w * P.mass[p] * P.V(p, 0);
          py[k] += w * P.mass[p] * P.V(p, 1);
          fx[k] -= vol * (sxx * dx + sxy * dy);
          fy[k] -= vol * (sxy * dx + syy * dy);
        }
    }
    for (size_t k = 0; k < n; ++k) { // grid update: a = f/m, v⁺ = (p + f dt)/m
      if (m[k] > 1e-12) {
        px[k] = (px[k] + fx[k] * dt) / m[k];
        py[k] = (py[k] + fy[k] * dt) / m[k];
        fx[k] /= m[k];
        fy[k] /= m[k];
      } else {
        px[k] = py[k] = fx[k] = fy[k] = 0;
      }
    }
    for (Eigen::Index p = 0; p < N; ++p) { // G2P: FLIP, position, L, F, stress
      const double x = P.X(p, 0), y = P.X(p, 1);
      const int i = int(x), j = int(y);
      const double tx = x - i, ty = y - j;
      const double wx[2] = {1 - tx, tx}, wy[2] = {1 - ty, ty}, gx[2] = {-1, 1};
      double ax = 0, ay = 0, vx = 0, vy = 0, L00 = 0, L01 = 0, L10 = 0, L11 = 0;
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const size_t k = size_t(i + a) + size_t(j + b) * nx;
          const double w = wx[a] * wy[b], dx = gx[a] * wy[b], dy = wx[a] * gx[b];
          ax += w * fx[k];
          ay += w * fy[k];
          vx += w * px[k];
          vy += w * py[k];
          L00 += px[k] * dx;
          L01 += px[k] * dy;
          L10 += py[k] * dx;
          L11 += py[k] * dy;
        }
      P.V(p, 0) += dt * ax;
      P.V(p, 1) += dt * ay;
      P.X(p, 0) += dt * vx;
      P.X(p, 1) += dt * vy;
      const double F00 = P.F(p, 0), F01 = P.F(p, 1), F10 = P.F(p, 2), F11 = P.F(p, 3);
      const double n00 = F00 + dt * (L00 * F00 + L01 * F10),
                   n01 = F01 + dt * (L00 * F01 + L01 * F11);
      const double n10 = F10 + dt * (L10 * F00 + L11 * F10),
                   n11 = F11 + dt * (L10 * F01 + L11 * F11);
      P.F(p, 0) = n00;
      P.F(p, 1) = n01;
      P.F(p, 2) = n10;
      P.F(p, 3) = n11;
      const double exx = n00 - 1, eyy = n11 - 1, exy = 0.5 * (n01 + n10), tr = exx + eyy;
      P.stress(p, 0) = lam * tr + 2 * G * exx;
      P.stress(p, 1) = P.stress(p, 2) = 2 * G * exy;
      P.stress(p, 3) = lam * tr + 2 * G * eyy;
    }
  }
};

// The matrix-free baseline works on linear shape functions and linear elasticity: give it the
// problem's particles with a linear material of the same moduli.
void BM_MatrixFree(benchmark::State& state, const std::string& problem) {
  Problem pb = make_problem(problem);
  for (auto& m : pb.model.materials)
    m.model = smpm::MaterialModel::Linear;
  const smpm::Grid& g = pb.model.grid;
  // shift to a grid with origin 0 and unit cells, as the baseline indexes cells directly
  for (int a = 0; a < 2; ++a)
    pb.model.particles.X.col(a) =
        (pb.model.particles.X.col(a).array() - g.origin(a)) / g.cell_size(a);
  MatrixFree mf{g.nodes(0), g.nodes(1), {}, {}, {}, {}, {}};
  mf.step(pb.model, pb.dt); // warm-up
  for (auto _ : state)
    mf.step(pb.model, pb.dt);
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
             int threads = 1) {
  smpm::set_threads(threads);
  Problem pb = make_problem(problem);
  smpm::StepOptions opt{.shape = pb.shape, .velocity = vel, .fmpm = {.order = k}};
  if (vel == smpm::VelocityUpdate::Exact)
    opt.exact_solver = smpm::cholmod_solver_factory();
  smpm::Stepper stepper(opt);
  stepper.step(pb.model, pb.dt); // warm-up: sizes every workspace, CHOLMOD analysis
  for (auto _ : state)
    stepper.step(pb.model, pb.dt);
  state.counters["particles"] = double(pb.model.particles.size());
  state.counters["threads"] = threads;
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

// STREAM triad a = b + s c on 3 × 10⁷ doubles: the machine's sustainable memory bandwidth, the
// bound for passes that stream S, G or m̃ from memory.
void BM_StreamTriad(benchmark::State& state) {
  const size_t n = 10'000'000;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  for (auto _ : state) {
    for (size_t i = 0; i < n; ++i)
      a[i] = b[i] + 3.0 * c[i];
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["GB/s"] = benchmark::Counter(3.0 * 8 * n * double(state.iterations()) / 1e9,
                                              benchmark::Counter::kIsRate);
}
BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond);

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

void register_problem(const std::string& pb) {
  using smpm::VelocityUpdate;
  auto reg = [&](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark((pb + "/" + name).c_str(), fn)->Unit(benchmark::kMillisecond);
  };
  reg("matrix_free_flip_step", [pb](benchmark::State& s) { BM_MatrixFree(s, pb); });
  reg("assemble_S_G_m", [pb](benchmark::State& s) { BM_Assemble(s, pb); });
  reg("assemble_S_G_m_new_pattern", [pb](benchmark::State& s) { BM_AssembleFresh(s, pb); });
  reg("S_by_setFromTriplets", [pb](benchmark::State& s) { BM_SetFromTriplets(s, pb); });
  reg("consistent_mass_stencil", [pb](benchmark::State& s) { BM_ConsistentMass(s, pb); });
  reg("consistent_mass_eigen_product",
      [pb](benchmark::State& s) { BM_ConsistentMassEigen(s, pb); });
  reg("fmpm_pass", [pb](benchmark::State& s) { BM_FmpmPass(s, pb); });
  reg("flip_step", [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FLIP, 1); });
  reg("fmpm4_step", [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FMPM, 4); });
  reg("flip_step_2_threads",
      [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FLIP, 1, 2); });
  reg("fmpm4_step_2_threads",
      [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FMPM, 4, 2); });
  reg("fmpm20_step", [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::FMPM, 20); });
  reg("exact_step", [pb](benchmark::State& s) { BM_Step(s, pb, VelocityUpdate::Exact, 1); });
  reg("diagnostics", [pb](benchmark::State& s) { BM_Diagnostics(s, pb, true); });
  reg("diagnostics_recomputed", [pb](benchmark::State& s) { BM_Diagnostics(s, pb, false); });
}

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  smpm::set_threads(1); // the baseline is serial; the "_2_threads" steps set their own count
  register_problem("block");
  register_problem("plate");
  register_problem("impact");
  RatioReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  for (const std::string pb : {"block", "plate", "impact"}) {
    auto t = [&](const std::string& n) {
      const auto it = rep.ms.find(pb + "/" + n);
      return it == rep.ms.end() ? std::nan("") : it->second;
    };
    const double base = t("matrix_free_flip_step");
    if (std::isnan(base))
      continue;
    std::printf("\n%s: ratios to the matrix-free USL FLIP step (%.3f ms)\n", pb.c_str(), base);
    for (const auto& [name, ms] : rep.ms)
      if (name.rfind(pb + "/", 0) == 0)
        std::printf("  %-36s %10.3f ms  %8.3f   (%.3f-%.3f ms)\n", name.c_str() + pb.size() + 1, ms,
                    ms / base, rep.lo[name], rep.hi[name]);
    std::printf("  F = fmpm_pass / matrix-free step                 %8.3f (target <= 0.05)\n",
                t("fmpm_pass") / base);
    std::printf("  assembly (S, G, m, m~) / matrix-free step        %8.3f (target <= 1.0)\n",
                (t("assemble_S_G_m") + t("consistent_mass_stencil")) / base);
    std::printf("  FLIP step / matrix-free step                     %8.3f (target <= 1.5)\n",
                t("flip_step") / base);
    std::printf("  FMPM(20) step / FLIP step                        %8.3f (target <= 1.8)\n",
                t("fmpm20_step") / t("flip_step"));
    std::printf("  diagnostics (energies, time step) / FLIP step    %8.3f (target <= 0.05)\n",
                t("diagnostics") / t("flip_step"));
    std::printf("  exact step / FMPM(4) step, / FMPM(20) step       %8.3f, %.3f\n",
                t("exact_step") / t("fmpm4_step"), t("exact_step") / t("fmpm20_step"));
    std::printf("  2-thread speed-up: FLIP step %.3f, FMPM(4) step %.3f (target >= 1.7)\n",
                t("flip_step") / t("flip_step_2_threads"),
                t("fmpm4_step") / t("fmpm4_step_2_threads"));
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
  const double N = 4.0 * (side() - 1) * (side() - 1);
  const auto triad = rep.ms.find("BM_StreamTriad");
  if (triad != rep.ms.end())
    std::printf("\nSTREAM triad: %.1f GB/s (2.4e8 bytes in %.3f ms)\n", 240.0 / triad->second,
                triad->second);
  std::printf("\npeak resident memory %.0f MiB: %.0f bytes per particle of the %d x %d block "
              "(target <= 700)\n",
              ru.ru_maxrss / 1024.0, ru.ru_maxrss * 1024.0 / N, side(), side());
  return 0;
}
