// SPDX-License-Identifier: BSD-3-Clause
// Catch2's runner inside a PETSc session: every rank runs every test (their collective calls
// in the same order); the program fails when a test failed on any rank.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <sparsempm/petsc.hpp>

int main(int argc, char** argv) {
  smpm::petsc::Session session(&argc, &argv);
  const int failed = Catch::Session().run(argc, argv);
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return any ? 1 : 0;
}
