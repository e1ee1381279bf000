// SPDX-License-Identifier: BSD-3-Clause
// Uses the installed distributed component (when the installation has it) on one rank: the
// lumped masses of the free-vibrating bar summed by PETSc equal the particles' mass.
#include <cmath>
#include <iostream>
#include <sparsempm/petsc.hpp>
#include <sparsempm/sparsempm.hpp>

int main(int argc, char** argv) {
  smpm::petsc::Session session(&argc, &argv);
  const smpm::Model bar = smpm::vibrating_bar({});
  const smpm::petsc::DistributedGrid grid(bar.grid);
  smpm::petsc::DistributedOperators ops;
  smpm::petsc::assemble(grid, bar.particles, smpm::Shape::GIMP, ops);
  PetscScalar sum = 0;
  SMPM_PETSC_CALL(VecSum(ops.m, &sum));
  std::cout << "distributed mass error = " << std::abs(sum - bar.particles.mass.sum()) << "\n";
  return 0;
}
