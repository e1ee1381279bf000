// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Reductions over the ranks of PETSC_COMM_WORLD for the tests of sparsempm::petsc.

#include <petscsys.h>

namespace smpm::test {

/// The largest x over the ranks.
inline double all_max(double x) {
  double y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return y;
}

/// The sum of x over the ranks.
inline long all_sum(long x) {
  long y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  return y;
}

/// The number of ranks.
inline int world_size() {
  int n = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &n);
  return n;
}

/// This process's rank.
inline int rank() {
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

} // namespace smpm::test
