// Cost of the matrix form of an MPM step against a lean matrix-free step measured in the same
// run. Block of particles (2 × 2 per cell, i.e. 4 per cell) in 2D plane strain, linear
// shape functions, USL FLIP, linear elastic. Prints each benchmark and then the ratios.
//
//   build/tests/bench/bench_step [--benchmark_filter=...]
//
// The block fills side × side cells, side = 500 by default (10⁶ particles, 251,001
// nodes); set SMPM_BENCH_SIDE to change it.

#include <sparsempm/sparsempm.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

namespace {

int side() {
  const char* s = std::getenv("SMPM_BENCH_SIDE");
  return s ? std::atoi(s) : 500;
}

smpm::Model block_model(int n) {
  using namespace smpm;
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {n, n, 1}));
  Material mat;
  mat.name = "block";
  mat.youngs = 100;
  mat.poisson = 0.3;
  model.materials = {mat};
  model.particles = make_block(model.grid, {0.5, 0.5, 0}, {n - 0.5, n - 0.5, 0}, {2, 2, 1}, 1.0, 0);
  auto& P = model.particles;
  for (Eigen::Index p = 0; p < P.size(); ++p) { // a smooth velocity field
    P.V(p, 0) = 0.01 * std::sin(0.1 * P.X(p, 1));
    P.V(p, 1) = 0.01 * std::cos(0.1 * P.X(p, 0));
  }
  return model;
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

void BM_MatrixFreeStep(benchmark::State& state) {
  smpm::Model model = block_model(side());
  MatrixFree mf{side() + 1, side() + 1, {}, {}, {}, {}, {}};
  mf.step(model, 1e-4); // warm-up
  for (auto _ : state)
    mf.step(model, 1e-4);
  state.counters["particles"] = double(model.particles.size());
}

void BM_AssembleOperators(benchmark::State& state) {
  smpm::Model model = block_model(side());
  smpm::Operators ops;
  smpm::assemble(model.grid, model.particles, smpm::Shape::Linear, ops);
  for (auto _ : state)
    smpm::assemble(model.grid, model.particles, smpm::Shape::Linear, ops);
}

void BM_FlipStep(benchmark::State& state) {
  smpm::Model model = block_model(side());
  smpm::Stepper stepper({.shape = smpm::Shape::Linear, .velocity = smpm::VelocityUpdate::FLIP});
  stepper.step(model, 1e-4); // warm-up: sizes every workspace once
  for (auto _ : state)
    stepper.step(model, 1e-4);
}

void BM_ConsistentMassProduct(benchmark::State& state) { // one n × n product with n × 2
  smpm::Model model = block_model(side());
  const smpm::Operators ops = smpm::assemble(model.grid, model.particles, smpm::Shape::Linear);
  const smpm::SparseMatrix mt = smpm::consistent_mass(ops);
  const Eigen::MatrixXd v = Eigen::MatrixXd::Random(mt.rows(), 2);
  Eigen::MatrixXd w(mt.rows(), 2);
  for (auto _ : state) {
    w.noalias() = mt * v;
    benchmark::DoNotOptimize(w.data());
  }
}

BENCHMARK(BM_MatrixFreeStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AssembleOperators)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlipStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConsistentMassProduct)->Unit(benchmark::kMillisecond);

// Collects real times so that ratios to the baseline of the same run can be printed.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  std::map<std::string, double> ns;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs)
      if (r.run_type == Run::RT_Iteration)
        ns[r.benchmark_name()] = r.GetAdjustedRealTime() * 1e6; // ms → ns
    ConsoleReporter::ReportRuns(runs);
  }
};

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  const auto base = rep.ns.find("BM_MatrixFreeStep");
  if (base == rep.ns.end())
    return 0;
  const double N = 4.0 * (side() - 1) * (side() - 1); // the block leaves half a cell free
  std::printf("\nbaseline matrix-free USL FLIP step: %.1f ns per particle (%d x %d cells, %.0f "
              "particles)\n",
              base->second / N, side(), side(), N);
  for (const auto& [name, t] : rep.ns)
    std::printf("%-28s %10.3f ms   ratio to matrix-free step %.3f\n", name.c_str(), t * 1e-6,
                t / base->second);
  return 0;
}
