// SPDX-License-Identifier: BSD-3-Clause
// The boxes of nodes a PETSc DMDA gives each rank, for analysis/ghost_nodes.py --check-boxes.
//
//     mpiexec -n P smpm_dmda_boxes dim Nx Ny [Nz] [dim Nx Ny [Nz] ...]
//
// For each grid of Nx × Ny (× Nz) nodes (dim 2 or 3; several grids share one launch of
// mpiexec), creates the DMDA as lib/petsc/src/distributed.cpp does: no periodic boundaries, box
// stencil of width 1, PETSC_DECIDE ranks per axis, DMSetUp (one field: the split does not
// depend on the fields). Rank 0 prints
//
//     # grid dim Nx Ny Nz
//     # ranks m n p                      the process grid (p = 1 in 2D)
//     rank xs ys zs xm ym zm             one line per rank: its first node and node count
//     ...                                on each axis (zs = 0, zm = 1 in 2D)
//
// or, when PETSc refuses to split the grid over P ranks (DMSetUp fails),
//
//     # grid dim Nx Ny Nz
//     # cannot split: PETSc's message
//
// The boxes come from the ownership ranges lx, ly, lz that every rank holds and the process
// grid of DMDAGetInfo, with PETSc's ordering of the ranks (x fastest, then y, then z); each rank
// also checks that its own DMDAGetCorners is the box printed for it. Exit status: 0, or 3 when
// a grid could not be split, 2 for bad arguments, 1 for any other error.
#include <petscdmda.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {
const char help[] = "Prints the DMDA's box of nodes for each rank: dim Nx Ny [Nz] ...\n";
constexpr int cannot_split = 3, bad_arguments = 2;

// One grid of the command line: dim and the nodes per axis (1 on the unused z axis in 2D).
struct Grid {
  PetscInt dim = 0;
  PetscInt nodes[3] = {1, 1, 1};
};

// A positive integer from the command line, or 0 when `text` is not one.
PetscInt count_from(const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return (end != text && *end == '\0' && value > 0) ? PetscInt(value) : 0;
}

// The grids of argv[1..argc), or none when the arguments are not a sequence of grids.
std::vector<Grid> grids_from(int argc, char** argv) {
  std::vector<Grid> grids;
  for (int at = 1; at < argc;) {
    Grid g;
    g.dim = count_from(argv[at]);
    if ((g.dim != 2 && g.dim != 3) || at + g.dim >= argc)
      return {};
    for (PetscInt a = 0; a < g.dim; ++a)
      if ((g.nodes[a] = count_from(argv[at + 1 + a])) == 0)
        return {};
    grids.push_back(g);
    at += 1 + int(g.dim);
  }
  return grids;
}

// The first node of part `i` of an axis split into the ownership range `l` (l[0], l[1], ...).
PetscInt first_of(const PetscInt* l, PetscInt i) {
  PetscInt first = 0;
  for (PetscInt k = 0; k < i; ++k)
    first += l[k];
  return first;
}

// Prints the boxes of grid `g`'s DMDA; sets `split` false when DMSetUp refuses the split (the
// same on every rank: the process grid depends on the sizes only).
PetscErrorCode print_boxes(const Grid& g, bool& split) {
  PetscFunctionBeginUser;
  PetscMPIInt rank = 0, size = 0;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const PetscInt* N = g.nodes;
  if (rank == 0)
    std::printf("# grid %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT "\n",
                g.dim, N[0], N[1], N[2]);
  DM da = nullptr;
  if (g.dim == 2)
    PetscCall(DMDACreate2d(PETSC_COMM_WORLD, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX,
                           N[0], N[1], PETSC_DECIDE, PETSC_DECIDE, 1, 1, nullptr, nullptr, &da));
  else
    PetscCall(DMDACreate3d(PETSC_COMM_WORLD, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                           DMDA_STENCIL_BOX, N[0], N[1], N[2], PETSC_DECIDE, PETSC_DECIDE,
                           PETSC_DECIDE, 1, 1, nullptr, nullptr, nullptr, &da));
  // PETSc's default handler would make every rank but 0 sleep 10 s and exit without
  // MPI_Finalize: return the error instead, and rank 0 prints its message.
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode setup = DMSetUp(da);
  PetscCall(PetscPopErrorHandler());
  split = setup == 0;
  if (!split) {
    char* message = nullptr;
    PetscCall(PetscErrorMessage(setup, nullptr, &message));
    if (rank == 0)
      std::printf("# cannot split: %s\n", message ? message : "");
    std::fflush(stdout);
    PetscCall(DMDestroy(&da));
    PetscFunctionReturn(0);
  }

  // The process grid m × n × p (p = 1 in 2D) and the nodes of each part of each axis.
  PetscInt m = 0, n = 0, p = 0;
  PetscCall(DMDAGetInfo(da, nullptr, nullptr, nullptr, nullptr, &m, &n, &p, nullptr, nullptr,
                        nullptr, nullptr, nullptr, nullptr));
  const PetscInt* lx = nullptr;
  const PetscInt* ly = nullptr;
  const PetscInt* lz = nullptr;
  PetscCall(DMDAGetOwnershipRanges(da, &lx, &ly, g.dim == 3 ? &lz : nullptr));
  const PetscInt one = 1;
  if (g.dim == 2)
    lz = &one;
  // Rank r is part (r mod m, (r div m) mod n, r div mn) of the process grid.
  auto box = [&](PetscMPIInt r, PetscInt first[3], PetscInt count[3]) {
    const PetscInt i = r % m, j = (r / m) % n, k = r / (m * n);
    first[0] = first_of(lx, i), first[1] = first_of(ly, j), first[2] = first_of(lz, k);
    count[0] = lx[i], count[1] = ly[j], count[2] = lz[k];
  };
  PetscInt first[3], count[3];
  if (rank == 0) {
    std::printf("# ranks %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT "\n", m, n, p);
    for (PetscMPIInt r = 0; r < size; ++r) {
      box(r, first, count);
      std::printf("%d %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT
                  " %" PetscInt_FMT " %" PetscInt_FMT "\n",
                  r, first[0], first[1], first[2], count[0], count[1], count[2]);
    }
  }
  std::fflush(stdout);
  // This rank's own corners must be the box printed for it.
  PetscInt xs, ys, zs, xm, ym, zm;
  PetscCall(DMDAGetCorners(da, &xs, &ys, &zs, &xm, &ym, &zm));
  box(rank, first, count);
  PetscCheck(xs == first[0] && ys == first[1] && zs == first[2] && xm == count[0] &&
                 ym == count[1] && zm == count[2],
             PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "rank %d: DMDAGetCorners %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT
             " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT
             " differs from the box of the ownership ranges",
             rank, xs, ys, zs, xm, ym, zm);
  PetscCall(DMDestroy(&da));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char** argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, help));
  const std::vector<Grid> grids = grids_from(argc, argv);
  int status = EXIT_SUCCESS;
  if (grids.empty()) {
    PetscCall(PetscFPrintf(PETSC_COMM_WORLD, PETSC_STDERR,
                           "usage: %s dim Nx Ny [Nz] [dim Nx Ny [Nz] ...] (dim 2 or 3, nodes "
                           "per axis)\n",
                           argv[0]));
    status = bad_arguments;
  }
  for (const Grid& g : grids) {
    bool split = true;
    if (print_boxes(g, split) != 0) {
      status = EXIT_FAILURE;
      break;
    }
    if (!split)
      status = cannot_split;
  }
  PetscCall(PetscFinalize());
  return status;
}
