// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The problems of tests/bench/bench_step.cpp (its header lists them): blocks of particles on
// grids of unit cells, and the block impact example.

#include <sparsempm/input.hpp>
#include <sparsempm/sparsempm.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <string>

namespace smpm::bench {

inline int side() {
  const char* s = std::getenv("SMPM_BENCH_SIDE");
  return s ? std::atoi(s) : 500;
}

// A block of cells[a] cells per axis of particles (ppc per axis 2) on a grid with two empty cells
// around it (B2CPDI reaches 1.5 cells beyond a particle), unit cells from the origin.
inline smpm::Model block_model(int dim, std::array<int, 3> cells) {
  using namespace smpm;
  std::array<int, 3> grid_cells{1, 1, 1}, ppc{1, 1, 1};
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int a = 0; a < dim; ++a) {
    grid_cells[size_t(a)] = cells[size_t(a)] + 4;
    lo[size_t(a)] = 2;
    hi[size_t(a)] = 2 + cells[size_t(a)];
    ppc[size_t(a)] = 2;
  }
  Model model(Grid(dim, {0, 0, 0}, {1, 1, 1}, grid_cells));
  Material mat;
  mat.name = "block";
  mat.youngs = 100;
  mat.poisson = 0.3;
  model.materials = {mat};
  model.particles = make_block(model.grid, lo, hi, ppc, 1.0, 0);
  auto& P = model.particles;
  for (Eigen::Index p = 0; p < P.size(); ++p) // a smooth velocity field
    for (int a = 0; a < dim; ++a)
      P.V(p, a) = 0.01 * std::sin(0.1 * P.X(p, (a + 1) % dim) + a);
  return model;
}

struct Problem {
  std::string name;
  smpm::Model model;
  smpm::Shape shape;
  double dt;
};

inline Problem make_problem(const std::string& name) {
  using smpm::Shape;
  if (name == "block")
    return {name, block_model(2, {side(), side(), 1}), Shape::Linear, 1e-4};
  if (name.rfind("scaling_", 0) == 0) // scaling_<side>
    return {name, block_model(2, {std::stoi(name.substr(8)), std::stoi(name.substr(8)), 1}),
            Shape::Linear, 1e-4};
  if (name == "block3d")
    return {name, block_model(3, {40, 40, 40}), Shape::Linear, 1e-4};
  if (name == "small_body") { // a 40 × 40-cell block (6400 particles) on 1000 × 1000 cells
    Problem pb{name, block_model(2, {40, 40, 1}), Shape::GIMP, 1e-4};
    pb.model.grid = smpm::Grid(2, {0, 0, 0}, {1, 1, 1}, {1000, 1000, 1});
    return pb;
  }
  if (name.rfind("plate", 0) == 0) {
    const Shape shape = name == "plate_cpdi"     ? Shape::CPDI
                        : name == "plate_b2cpdi" ? Shape::B2CPDI
                                                 : Shape::GIMP;
    return {name, block_model(2, {200, 50, 1}), shape, 1e-4};
  }
  smpm::RunConfig cfg =
      smpm::read_input_file(std::string(SMPM_EXAMPLES_DIR) + "/block_impact.toml");
  // The cost of a step does not depend on Δt: a tiny one keeps the particles in place however
  // many iterations the benchmark runs.
  return {name, cfg.model, cfg.step.shape, 1e-6 * smpm::stable_time_step(cfg.model, 0.2)};
}

} // namespace smpm::bench
