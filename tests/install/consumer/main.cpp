// Uses the installed library: 4 particles of mass 1/4 (ρ = 1/2, spacing 1/2); Σ m_i = Σ M_p = 1.
#include <iostream>
#include <sparsempm/sparsempm.hpp>

int main() {
  const smpm::Grid grid(1, {0, 0, 0}, {1, 1, 1}, {4, 1, 1});
  const smpm::Particles P = smpm::make_block(grid, {1, 0, 0}, {3, 0, 0}, {2, 1, 1}, 0.5, 0);
  const smpm::Operators ops = smpm::assemble(grid, P, smpm::Shape::Linear);
  std::cout << "sum of lumped masses = " << ops.m.sum() << "\n";
  return 0;
}
