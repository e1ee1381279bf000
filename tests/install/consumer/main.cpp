// SPDX-License-Identifier: BSD-3-Clause
// Uses the installed library and its three components on the free-vibrating bar of FMPM 2026
// §3.3: ρ(A) through sparsempm::analysis (0.75 for this lattice), the exact inverse through
// sparsempm::exact (residual of m̃ v = p) and the input reader through sparsempm::io.
#include <iostream>
#include <sparsempm/exact.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/sparsempm.hpp>
#include <sparsempm/spectrum.hpp>

int main() {
  const smpm::Model bar = smpm::vibrating_bar({});
  const smpm::Operators ops = smpm::assemble(bar.grid, bar.particles, smpm::Shape::CPDI);
  smpm::ConsistentMass mt;
  smpm::assemble_consistent_mass(ops, mt);
  std::cout << "rho(A) = " << smpm::mass_spectrum(ops, mt.matrix).rho_A << "\n";
  smpm::Field p, v;
  smpm::map_momentum(smpm::particle_operators(ops), bar.particles.V, p);
  smpm::CholmodSolver().solve(ops, mt.matrix, {}, p, v);
  std::cout << "exact residual = " << (mt.matrix * v - p).norm() / p.norm() << "\n";
  const char* input = R"(
[grid]
dim = 1
origin = [0.0]
cell_size = [1.0]
cells = [4]
[[material]]
name = "bar"
density = 1.0
youngs = 1.0
[[body]]
material = "bar"
min = [1.0]
max = [3.0]
ppc = [2]
[time]
end = 1.0
)";
  const smpm::RunConfig cfg = smpm::read_input(input, "inline.toml");
  std::cout << "nodes read = " << cfg.model.grid.num_nodes() << "\n";
  return 0;
}
