// SPDX-License-Identifier: BSD-3-Clause
// Set-up and output costs a run pays outside its steps, as ratios to a baseline of the same
// run: [[bc]] planes and boxes against the scan of every node, and a frame after thousands of
// frames against the first frames of a file.

#include <sparsempm/boundary.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/output.hpp>

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

// [[bc]] planes and boxes on a grid of 10⁶ nodes: nodes_on_plane / nodes_in_box select by index
// along each axis; the baseline is the scan of every node (the selection before, 3,000 planes in
// 26 s), with the same tolerance.
const smpm::Grid& plane_grid() {
  static const smpm::Grid g(2, {0, 0, 0}, {0.1, 0.1, 1}, {999, 999, 1});
  return g;
}
void BM_PlaneSelection(benchmark::State& state) {
  const smpm::Grid& g = plane_grid();
  for (auto _ : state)
    for (int q = 0; q < 10; ++q) {
      auto x = smpm::nodes_on_plane(g, q % 2, 0.1 * 97 * q);
      auto b = smpm::nodes_in_box(g, {0.1 * q, 0.5, 0}, {0.1 * q + 0.3, 20.0, 0});
      benchmark::DoNotOptimize(x.data());
      benchmark::DoNotOptimize(b.data());
    }
}
void BM_PlaneScan(benchmark::State& state) {
  const smpm::Grid& g = plane_grid();
  for (auto _ : state)
    for (int q = 0; q < 10; ++q) {
      std::vector<smpm::Index> x, b;
      const int axis = q % 2;
      const double at = 0.1 * 97 * q, tol = 1e-9 * g.cell_size(axis);
      for (smpm::Index i = 0; i < g.num_nodes(); ++i)
        if (std::abs(g.node_coordinate(i, axis) - at) <= tol)
          x.push_back(i);
      const std::array<double, 3> lo{0.1 * q, 0.5, 0}, hi{0.1 * q + 0.3, 20.0, 0};
      for (smpm::Index i = 0; i < g.num_nodes(); ++i) {
        bool inside = true;
        for (int a = 0; a < 2; ++a) {
          const double c = g.node_coordinate(i, a), t = 1e-9 * g.cell_size(a);
          inside = inside && c >= lo[size_t(a)] - t && c <= hi[size_t(a)] + t;
        }
        if (inside)
          b.push_back(i);
      }
      benchmark::DoNotOptimize(x.data());
      benchmark::DoNotOptimize(b.data());
    }
}
BENCHMARK(BM_PlaneSelection)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlaneScan)->Unit(benchmark::kMillisecond);

// Frames of a 4-particle run: 100 frames written after `before` frames of the same file. A
// frame must cost the same whatever number of frames precede it (the metadata cache of every
// frame kept made frame n cost O(n): 10,000 frames slowed from 60 to a few per second).
void BM_FramesAfter(benchmark::State& state) {
  const int before = int(state.range(0));
  smpm::RunConfig cfg = smpm::read_input(
      "[grid]\ndim = 1\norigin = [0.0]\ncell_size = [1.0]\ncells = [10]\n\n[[material]]\n"
      "name = \"m\"\ndensity = 1.0\nyoungs = 1.0\n\n[[body]]\nmaterial = \"m\"\nregion = "
      "\"box\"\nmin = [2.0]\nmax = [4.0]\nppc = [2]\n\n[time]\nend = 1.0\n",
      "frames.toml", {});
  const std::string path =
      (std::filesystem::temp_directory_path() / "sparsempm_bench_frames.h5").string();
  for (auto _ : state) {
    state.PauseTiming();
    {
      smpm::OutputFile out(path, cfg);
      for (int k = 0; k < before; ++k)
        out.write_frame(k, cfg.model, smpm::Shape::Linear, false);
      state.ResumeTiming();
      for (int k = before; k < before + 100; ++k)
        out.write_frame(k, cfg.model, smpm::Shape::Linear, false);
      state.PauseTiming();
    }
    std::filesystem::remove(path);
    std::filesystem::remove(std::filesystem::path(path).replace_extension(".xmf"));
    state.ResumeTiming();
  }
}
BENCHMARK(BM_FramesAfter)->Arg(0)->Arg(4000)->Iterations(2)->Unit(benchmark::kMillisecond);

// Real times by name (the console reporter's, kept for the ratios).
class TimeReporter : public benchmark::ConsoleReporter {
public:
  std::map<std::string, double> ms;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& r : runs)
      ms[r.run_name.str()] = r.GetAdjustedRealTime();
    ConsoleReporter::ReportRuns(runs);
  }
};

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  TimeReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  if (rep.ms.count("BM_PlaneSelection") && rep.ms.count("BM_PlaneScan"))
    std::printf("\n10 planes and 10 boxes on 10^6 nodes: selection by index / scan of every node "
                "%.4f (%.3f / %.3f ms)\n",
                rep.ms["BM_PlaneSelection"] / rep.ms["BM_PlaneScan"], rep.ms["BM_PlaneSelection"],
                rep.ms["BM_PlaneScan"]);
  if (rep.ms.count("BM_FramesAfter/0/iterations:2") &&
      rep.ms.count("BM_FramesAfter/4000/iterations:2"))
    std::printf(
        "100 frames of 4 particles after 4000 frames / after none %.3f (%.2f / %.2f ms; "
        "target <= 1.5)\n",
        rep.ms["BM_FramesAfter/4000/iterations:2"] / rep.ms["BM_FramesAfter/0/iterations:2"],
        rep.ms["BM_FramesAfter/4000/iterations:2"], rep.ms["BM_FramesAfter/0/iterations:2"]);
  return 0;
}
