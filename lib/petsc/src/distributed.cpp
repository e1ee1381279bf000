// SPDX-License-Identifier: BSD-3-Clause
// The grid on a PETSc DMDA, this rank's particles, and the distributed operators m, p and m̃
// (FMPM 2026 §2.1) added over the ranks by PETSc's assembly.
#include "sparsempm/petsc.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/particle_columns.hpp"
#include "sparsempm/stages.hpp"

#include <slepcsys.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace smpm::petsc {

namespace {
// PETSc's message of the error in hand (the routine that raised it and its text), kept by
// record_error in place of PETSc's default traceback on stderr: check() throws it as one line.
thread_local std::string petsc_message;

PetscErrorCode record_error(MPI_Comm, int, const char* function, const char*, PetscErrorCode code,
                            PetscErrorType type, const char* message, void*) {
  if (type == PETSC_ERROR_INITIAL)
    petsc_message = std::string(function ? function : "?") + ": " + (message ? message : "");
  return code;
}
} // namespace

void check(PetscErrorCode code, const char* call) {
  if (code == 0)
    return;
  std::string text = std::exchange(petsc_message, std::string());
  if (text.empty()) {
    const char* generic = nullptr;
    PetscErrorMessage(code, &generic, nullptr);
    text = generic ? generic : "";
  }
  throw NumericalError(std::string(call) + ": PETSc error " + std::to_string(int(code)) + " (" +
                       text + ")");
}

Session::Session(int* argc, char*** argv) {
  SMPM_PETSC_CALL(SlepcInitialize(argc, argv, nullptr, nullptr));
  // Errors become exceptions with PETSc's message (check), not tracebacks on stderr.
  SMPM_PETSC_CALL(PetscPushErrorHandler(record_error, nullptr));
}

Session::~Session() {
  SlepcFinalize();
}

namespace {
// The natural index of node `node` of the whole grid and field α: the DMDA's application
// ordering numbers the unknowns of a node together (node · fields + α).
PetscInt natural(Index node, int fields, int field) {
  return PetscInt(node) * fields + field;
}

AO application_ordering(DM dm) {
  AO ao = nullptr;
  SMPM_PETSC_CALL(DMDAGetAO(dm, &ao));
  return ao;
}
} // namespace

DistributedGrid::DistributedGrid(const Grid& grid, int fields, MPI_Comm comm,
                                 const std::array<int, 3>& ranks_per_axis)
    : grid_(grid), owned_(grid), fields_(fields), comm_(comm) {
  if (grid.is_window())
    throw UsageError("DistributedGrid: give the whole grid, not a window of it");
  if (fields < 1)
    throw UsageError("DistributedGrid: " + std::to_string(fields) + " velocity fields");
  // Every row index of a node field (nodes × fields × d) must fit PetscInt.
  const double unknowns = double(grid.whole_num_nodes()) * fields * grid.dim();
  if (unknowns > double(PETSC_MAX_INT))
    throw InputError("DistributedGrid: " + std::to_string(grid.whole_num_nodes()) + " nodes x " +
                     std::to_string(fields) + " fields x " + std::to_string(grid.dim()) +
                     " components exceed the " + std::to_string(sizeof(PetscInt) * 8) +
                     "-bit indices of this PETSc (build against one with 64-bit indices: "
                     "Debian's petsc64-dev and slepc64-dev)");
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
  auto ranks = [&](int a) {
    return ranks_per_axis[a] > 0 ? PetscInt(ranks_per_axis[a]) : PETSC_DECIDE;
  };
  const PetscInt n[3] = {grid.nodes(0), grid.nodes(1), grid.nodes(2)};
  // Stencil width 1: the component adds over ranks with VecSetValues and MatSetValues
  // (ADD_VALUES), not through the DMDA's ghosts, so the width only bounds the smallest box.
  switch (grid.dim()) {
  case 1:
    SMPM_PETSC_CALL(DMDACreate1d(comm, DM_BOUNDARY_NONE, n[0], fields, 1, nullptr, dm_.out()));
    break;
  case 2:
    SMPM_PETSC_CALL(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, n[0],
                                 n[1], ranks(0), ranks(1), fields, 1, nullptr, nullptr, dm_.out()));
    break;
  default:
    SMPM_PETSC_CALL(DMDACreate3d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                                 DMDA_STENCIL_BOX, n[0], n[1], n[2], ranks(0), ranks(1), ranks(2),
                                 fields, 1, nullptr, nullptr, nullptr, dm_.out()));
  }
  SMPM_PETSC_CALL(DMSetUp(dm_));
  PetscInt first[3], count[3];
  SMPM_PETSC_CALL(
      DMDAGetCorners(dm_, &first[0], &first[1], &first[2], &count[0], &count[1], &count[2]));
  owned_ = grid.window({int(first[0]), int(first[1]), int(first[2])},
                       {int(count[0]), int(count[1]), int(count[2])});
  // The boxes' first nodes along each axis: the rank of box (a, b, c) is a + P_x (b + P_y c).
  const PetscInt* boxes[3] = {nullptr, nullptr, nullptr};
  SMPM_PETSC_CALL(DMDAGetOwnershipRanges(dm_, &boxes[0], &boxes[1], &boxes[2]));
  PetscInt per_axis[3] = {1, 1, 1};
  SMPM_PETSC_CALL(DMDAGetInfo(dm_, nullptr, nullptr, nullptr, nullptr, &per_axis[0], &per_axis[1],
                              &per_axis[2], nullptr, nullptr, nullptr, nullptr, nullptr, nullptr));
  for (int a = 0; a < grid.dim(); ++a) {
    int start = 0;
    for (PetscInt b = 0; b < per_axis[a]; ++b) {
      box_starts_[size_t(a)].push_back(start);
      start += int(boxes[a][b]);
    }
  }
  OwnedVec x;
  SMPM_PETSC_CALL(DMCreateGlobalVector(dm_, x.out()));
  PetscInt end = 0;
  SMPM_PETSC_CALL(VecGetOwnershipRange(x, &first_row_, &end));
  if (end - first_row_ != owned_rows())
    throw NumericalError("DistributedGrid: the DMDA's rows " + std::to_string(end - first_row_) +
                         " are not the owned nodes × fields " + std::to_string(owned_rows()));
}

void DistributedGrid::petsc_rows(const std::vector<PetscInt>& nodes, int field,
                                 std::vector<PetscInt>& rows) const {
  rows.resize(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k)
    rows[k] = natural(nodes[k], fields_, field);
  SMPM_PETSC_CALL(AOApplicationToPetsc(application_ordering(dm_), PetscInt(rows.size()),
                                       rows.empty() ? nullptr : rows.data()));
}

bool DistributedGrid::owns_cell(const std::array<int, 3>& cell) const {
  for (int a = 0; a < grid_.dim(); ++a)
    if (cell[a] < owned_.first_node(a) || cell[a] >= owned_.first_node(a) + owned_.nodes(a))
      return false;
  return true;
}

int DistributedGrid::owner_of_cell(const std::array<int, 3>& cell) const {
  int rank = 0;
  for (int a = grid_.dim() - 1; a >= 0; --a) {
    const std::vector<int>& starts = box_starts_[size_t(a)];
    const auto box = std::upper_bound(starts.begin(), starts.end(), cell[a]) - starts.begin() - 1;
    rank = rank * int(starts.size()) + int(box);
  }
  return rank;
}

std::array<int, 3> DistributedGrid::cell_of(const double* x) const {
  std::array<int, 3> cell{0, 0, 0};
  for (int a = 0; a < grid_.dim(); ++a) {
    const double s = std::floor((x[a] - grid_.origin(a)) / grid_.cell_size(a));
    cell[a] = int(std::clamp(s, 0.0, double(grid_.cells(a) - 1)));
  }
  return cell;
}

std::vector<Index> DistributedGrid::owned_particles(const Particles& all) const {
  std::vector<Index> ids;
  for (Index p = 0; p < all.size(); ++p)
    if (owns_cell(cell_of(all.X.row(p).data())))
      ids.push_back(p);
  return ids;
}

Particles select_particles(const Particles& all, const std::vector<Index>& ids) {
  const auto rows =
      Eigen::Map<const Eigen::Matrix<Index, Eigen::Dynamic, 1>>(ids.data(), Index(ids.size()));
  Particles P;
  P.dim = all.dim;
  auto take = [&](const auto& from, auto& to) {
    if (from.rows() == all.size())
      to = from(rows, Eigen::all);
  };
  auto take_vector = [&](const auto& from, auto& to) {
    if (from.size() == all.size())
      to = from(rows);
  };
  take(all.X, P.X);
  take(all.V, P.V);
  take(all.F, P.F);
  take(all.stress, P.stress);
  take(all.half_length, P.half_length);
  take_vector(all.mass, P.mass);
  take_vector(all.volume0, P.volume0);
  take_vector(all.material, P.material);
  for (const ParticleColumn& c : particle_columns()) // the parts' columns the particles carry
    if (has_column(all, c))
      set_column(P, c, column_values(all, c)(rows, Eigen::all));
  return P;
}

namespace {
// Inserts the rows of the local m̃ (window columns) into `a` at their PETSc rows (ADD_VALUES),
// and a zero on the diagonal of every owned row: rows of nodes without mass keep a diagonal entry
// (MatDiagonalSet of the regularisation needs every diagonal entry in the pattern).
void add_local_rows(const DistributedGrid& grid, const DistributedOperators& ops,
                    const SparseRowMatrix& local, Mat a, std::vector<PetscInt>& cols) {
  for (PetscInt r = grid.first_row(); r < grid.first_row() + grid.owned_rows(); ++r)
    SMPM_PETSC_CALL(MatSetValue(a, r, r, 0.0, ADD_VALUES));
  for (Index r = 0; r < local.rows(); ++r) {
    const int begin = local.outerIndexPtr()[r], end = local.outerIndexPtr()[r + 1];
    if (begin == end)
      continue;
    cols.resize(size_t(end - begin));
    for (int k = begin; k < end; ++k)
      cols[size_t(k - begin)] = ops.rows[size_t(local.innerIndexPtr()[k])];
    const PetscInt row = ops.rows[size_t(r)];
    SMPM_PETSC_CALL(MatSetValues(a, 1, &row, PetscInt(cols.size()), cols.data(),
                                 local.valuePtr() + begin, ADD_VALUES));
  }
}

// The PETSc row of each column α n_w + i of the window: AO(node · fields + α).
void window_rows(const DistributedGrid& grid, DistributedOperators& ops) {
  const int fields = grid.fields();
  const Index cols = ops.local.num_nodes();
  ops.rows.resize(size_t(cols));
  for (Index c = 0; c < cols; ++c) {
    const Index ng = ops.local.grid_node_count;
    ops.rows[size_t(c)] = natural(ops.local.grid.whole_node(c % ng), fields, int(c / ng));
  }
  SMPM_PETSC_CALL(AOApplicationToPetsc(application_ordering(grid.dm()), PetscInt(cols),
                                       cols ? ops.rows.data() : nullptr));
}

// m = Sᵀ M: each rank adds its particles' sums into the rows (PETSc sends off-rank rows).
void add_mass(const DistributedGrid& grid, DistributedOperators& ops) {
  const Index cols = ops.local.num_nodes();
  ops.m = node_vector(grid, 1);
  if (cols)
    SMPM_PETSC_CALL(
        VecSetValues(ops.m, PetscInt(cols), ops.rows.data(), ops.local.m.data(), ADD_VALUES));
  SMPM_PETSC_CALL(VecAssemblyBegin(ops.m));
  SMPM_PETSC_CALL(VecAssemblyEnd(ops.m));
}

// m̃ = Sᵀ diag(M) S: the rank's particles' stencil (assemble_consistent_mass on the window),
// preallocated by a first insertion into a MATPREALLOCATOR.
void add_consistent_mass(const DistributedGrid& grid, const SparseRowMatrix& local,
                         DistributedOperators& ops) {
  const PetscInt n = grid.owned_rows(), N = grid.global_rows();
  std::vector<PetscInt> colidx;
  OwnedMat pre;
  SMPM_PETSC_CALL(MatCreate(grid.comm(), pre.out()));
  SMPM_PETSC_CALL(MatSetSizes(pre, n, n, N, N));
  SMPM_PETSC_CALL(MatSetType(pre, MATPREALLOCATOR));
  SMPM_PETSC_CALL(MatSetUp(pre));
  add_local_rows(grid, ops, local, pre, colidx);
  SMPM_PETSC_CALL(MatAssemblyBegin(pre, MAT_FINAL_ASSEMBLY));
  SMPM_PETSC_CALL(MatAssemblyEnd(pre, MAT_FINAL_ASSEMBLY));
  SMPM_PETSC_CALL(MatCreate(grid.comm(), ops.mt.out()));
  SMPM_PETSC_CALL(MatSetSizes(ops.mt, n, n, N, N));
  SMPM_PETSC_CALL(MatSetType(ops.mt, MATAIJ));
  SMPM_PETSC_CALL(MatPreallocatorPreallocate(pre, PETSC_TRUE, ops.mt));
  add_local_rows(grid, ops, local, ops.mt, colidx);
  SMPM_PETSC_CALL(MatAssemblyBegin(ops.mt, MAT_FINAL_ASSEMBLY));
  SMPM_PETSC_CALL(MatAssemblyEnd(ops.mt, MAT_FINAL_ASSEMBLY));
  SMPM_PETSC_CALL(MatSetOption(ops.mt, MAT_SYMMETRIC, PETSC_TRUE));
  SMPM_PETSC_CALL(MatSetOption(ops.mt, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
}

// The active rows: m^α_i > kMassTolerance · max_j Σ_α m^α_j over every node (operators.hpp),
// with m⁻¹ on them (one column, and d in the MAIJ layout of m̃ ⊗ I_d).
void active_rows(const DistributedGrid& grid, DistributedOperators& ops) {
  Field m_owned;
  get_owned(grid, ops.m, 1, m_owned);
  const Index no = grid.owned().num_nodes(), rows = m_owned.rows();
  const double local_max = largest_total_mass(m_owned.col(0), grid.fields(), no, 0, no);
  MPI_Allreduce(&local_max, &ops.max_mass, 1, MPI_DOUBLE, MPI_MAX, grid.comm());
  Eigen::VectorXd m_inv(rows);
  ops.active.resize(rows);
  active_nodes_of(m_owned.col(0), ops.max_mass, 0, rows, ops.active, m_inv);
  Field inv = m_inv;
  ops.m_inv = node_vector(grid, 1);
  set_owned(grid, inv, ops.m_inv);
  SMPM_PETSC_CALL(MatCreateMAIJ(ops.mt, ops.dim, ops.mt_d.out()));
  ops.m_inv_d = node_vector(grid, ops.dim);
  set_owned(grid, inv.replicate(1, ops.dim), ops.m_inv_d);
}
} // namespace

void assemble(const DistributedGrid& grid, const Particles& particles,
              const std::vector<Index>& ids, Shape shape, DistributedOperators& ops,
              const Eigen::VectorXi* field) {
  if (Index(ids.size()) != particles.size())
    throw UsageError("petsc::assemble: " + std::to_string(ids.size()) + " ids for " +
                     std::to_string(particles.size()) + " particles");
  const int fields = grid.fields();
  ops.dim = grid.grid().dim();
  ops.particles = ids;
  ops.local.node_range = NodeRange::Particles;
  // A rank without particles has the serial one-node window of no particle (shape.cpp), with
  // zero mass: the window a step on no particles assembles too (WindowSums needs the same).
  assemble(grid.grid(), particles, shape, ops.local, fields, fields > 1 ? field : nullptr);
  window_rows(grid, ops);
  add_mass(grid, ops);
  ConsistentMass local;
  if (particles.size() > 0)
    assemble_consistent_mass(ops.local, local);
  add_consistent_mass(grid, local.matrix, ops);
  active_rows(grid, ops);
}

void assemble_step(const DistributedGrid& grid, const WindowSums& sums, const Operators& local,
                   const SparseRowMatrix& mt, int dim, DistributedOperators& ops) {
  ops.dim = dim;
  ops.rows = sums.rows();
  ops.particles.clear();
  ops.m = node_vector(grid, 1);
  sums.to_global(Field(local.m), ops.m); // the window's totals into the owners' rows
  add_consistent_mass(grid, mt, ops);
  active_rows(grid, ops);
}

void assemble(const DistributedGrid& grid, const Particles& all, Shape shape,
              DistributedOperators& ops, const Eigen::VectorXi* field) {
  const std::vector<Index> ids = grid.owned_particles(all);
  Eigen::VectorXi own_field;
  if (field) {
    own_field.resize(Index(ids.size()));
    for (size_t k = 0; k < ids.size(); ++k)
      own_field[Index(k)] = (*field)[ids[k]];
  }
  assemble(grid, select_particles(all, ids), ids, shape, ops, field ? &own_field : nullptr);
}

OwnedVec momentum(const DistributedGrid& grid, const DistributedOperators& ops,
                  const ConstFieldRef& V) {
  const int d = ops.dim;
  OwnedVec p = node_vector(grid, d);
  if (ops.local.num_particles() > 0) {
    if (V.rows() != ops.local.num_particles() || V.cols() != d)
      throw UsageError("petsc::momentum: V is " + std::to_string(V.rows()) + " x " +
                       std::to_string(V.cols()) + ", the rank's particles are " +
                       std::to_string(ops.local.num_particles()) + " x " + std::to_string(d));
    Field local;
    map_momentum(particle_operators(ops.local), V, local); // p = Sᵀ (M ∘ V) on the window
    std::vector<PetscInt> idx(ops.rows.size() * size_t(d));
    for (size_t c = 0; c < ops.rows.size(); ++c)
      for (int a = 0; a < d; ++a)
        idx[c * size_t(d) + size_t(a)] = ops.rows[c] * d + a;
    SMPM_PETSC_CALL(VecSetValues(p, PetscInt(idx.size()), idx.data(), local.data(), ADD_VALUES));
  }
  SMPM_PETSC_CALL(VecAssemblyBegin(p));
  SMPM_PETSC_CALL(VecAssemblyEnd(p));
  return p;
}

} // namespace smpm::petsc
