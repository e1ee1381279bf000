// SPDX-License-Identifier: BSD-3-Clause
// The node sums of a step across ranks (WindowSums, the NodeSums of fmpm.hpp on PETSc): the
// window's rows added into a distributed Vec by a VecScatter in reverse and sent back forward,
// the reductions, and the agreement every collective call starts with.
#include "sparsempm/petsc.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <utility>

namespace smpm::petsc {

struct WindowSums::Impl {
  Impl(const DistributedGrid& g, std::vector<PetscInt> r, const Grid& w)
      : grid(g), rows(std::move(r)), window(w) {}
  const DistributedGrid& grid;
  std::vector<PetscInt> rows; // the PETSc row of each window column
  Grid window;                // the window bound (bind), and its fields
  int fields = 0;
  bool bound = false;
  struct Buffers { // per number of components
    OwnedVec global, local;
    OwnedScatter scatter;
    std::vector<PetscInt> index;
  };
  std::map<Index, Buffers> buffers;
  Index remote_rows = 0;           // window rows another rank owns
  mutable double communicated = 0; // bytes this rank sent and received through the scatters

  // One scatter of a field of c components: its remote entries, 8 bytes each.
  void count(Index c) const { communicated += 8.0 * double(remote_rows * c); }

  Buffers& for_components(Index c) {
    Buffers& b = buffers[c];
    if (b.global.get())
      return b;
    b.index.resize(rows.size() * size_t(c));
    for (size_t r = 0; r < rows.size(); ++r)
      for (Index a = 0; a < c; ++a)
        b.index[r * size_t(c) + size_t(a)] = rows[r] * PetscInt(c) + PetscInt(a);
    b.global = node_vector(grid, int(c));
    SMPM_PETSC_CALL(VecCreateSeq(PETSC_COMM_SELF, PetscInt(b.index.size()), b.local.out()));
    OwnedIS is;
    SMPM_PETSC_CALL(ISCreateGeneral(PETSC_COMM_SELF, PetscInt(b.index.size()), b.index.data(),
                                    PETSC_COPY_VALUES, is.out()));
    SMPM_PETSC_CALL(VecScatterCreate(b.global, is, b.local, nullptr, b.scatter.out()));
    return b;
  }

  // The buffers of `window`'s components with the window in the local Vec (row-major: its rows
  // in order, their components together).
  Buffers& load(const Field& window) {
    if (size_t(window.rows()) != rows.size())
      throw UsageError("WindowSums: a field of " + std::to_string(window.rows()) +
                       " rows on a window of " + std::to_string(rows.size()) + " columns");
    Buffers& b = for_components(window.cols());
    PetscScalar* a = nullptr;
    SMPM_PETSC_CALL(VecGetArray(b.local, &a));
    std::copy(window.data(), window.data() + window.size(), a);
    SMPM_PETSC_CALL(VecRestoreArray(b.local, &a));
    return b;
  }

  // The largest of `flags` over the ranks, the first being whether a rank failed: every
  // collective call of the sums starts here, so that a rank's fail() meets the others' next
  // call whichever it is (NodeSums), and they throw.
  std::array<int, 2> agree(std::array<int, 2> flags) const {
    std::array<int, 2> any{0, 0};
    MPI_Allreduce(flags.data(), any.data(), 2, MPI_INT, MPI_MAX, grid.comm());
    if (any[0] && !flags[0])
      throw FailedElsewhere("the step failed on another rank");
    return any;
  }
};

WindowSums::WindowSums(const DistributedGrid& grid)
    : impl_(std::make_unique<Impl>(grid, std::vector<PetscInt>{}, grid.grid())) {}

WindowSums::WindowSums(const DistributedGrid& grid, const DistributedOperators& ops)
    : impl_(std::make_unique<Impl>(grid, ops.rows, ops.local.grid)) {
  impl_->fields = ops.local.fields;
  impl_->bound = true;
}

WindowSums::~WindowSums() = default;

void WindowSums::bind(const Grid& window, int fields) {
  Impl& I = *impl_;
  if (fields != I.grid.fields())
    throw UsageError("WindowSums: operators of " + std::to_string(fields) +
                     " velocity fields on a distributed grid of " +
                     std::to_string(I.grid.fields()));
  const bool same = I.bound && window == I.window && fields == I.fields;
  // Every rank takes its new window's rows (the application ordering) and remakes its scatters
  // (collective) when any rank's window changed.
  if (!I.agree({0, same ? 0 : 1})[1])
    return;
  I.window = window;
  I.fields = fields;
  I.bound = true;
  I.buffers.clear();
  const Index ng = window.num_nodes();
  std::vector<PetscInt> nodes(static_cast<size_t>(ng)), rows;
  for (Index i = 0; i < ng; ++i)
    nodes[size_t(i)] = PetscInt(window.whole_node(i));
  I.rows.resize(size_t(ng * fields));
  for (int a = 0; a < fields; ++a) {
    I.grid.petsc_rows(nodes, a, rows);
    std::copy(rows.begin(), rows.end(), I.rows.begin() + a * ng);
  }
  const PetscInt first = I.grid.first_row(), end = first + I.grid.owned_rows();
  I.remote_rows = Index(std::count_if(I.rows.begin(), I.rows.end(),
                                      [&](PetscInt r) { return r < first || r >= end; }));
}

void WindowSums::add(Field& window) const {
  // The window's partial sums added into the owners' rows by the scatter's reverse (ADD_VALUES),
  // the totals sent back forward: two neighbour exchanges on the scatter's fixed pattern.
  impl_->agree({0, 0});
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecSet(b.global, 0.0));
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, b.global, ADD_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, b.global, ADD_VALUES, SCATTER_REVERSE));
  impl_->count(window.cols());
  to_window(b.global, window);
}

void WindowSums::to_global(const Field& window, Vec global) const {
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, global, INSERT_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, global, INSERT_VALUES, SCATTER_REVERSE));
  impl_->count(window.cols());
}

void WindowSums::to_window(Vec global, Field& window) const {
  window.resize(Index(impl_->rows.size()), window.cols());
  Impl::Buffers& b = impl_->for_components(window.cols());
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, global, b.local, INSERT_VALUES, SCATTER_FORWARD));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, global, b.local, INSERT_VALUES, SCATTER_FORWARD));
  impl_->count(window.cols());
  const PetscScalar* t = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(b.local, &t));
  std::copy(t, t + window.size(), window.data());
  SMPM_PETSC_CALL(VecRestoreArrayRead(b.local, &t));
}

const std::vector<PetscInt>& WindowSums::rows() const {
  return impl_->rows;
}

double WindowSums::communicated_bytes() const {
  return impl_->communicated;
}

double WindowSums::maximum(double value) const {
  impl_->agree({0, 0});
  double out = value;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, impl_->grid.comm());
  return out;
}

void WindowSums::sum(double* values, int count) const {
  impl_->agree({0, 0});
  if (count > 0)
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, impl_->grid.comm());
}

void WindowSums::sum_rows(const Field& window, double* totals) const {
  impl_->agree({0, 0});
  const Index c = window.cols();
  if (c == 0)
    return;
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecSet(b.global, 0.0));
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, b.global, INSERT_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, b.global, INSERT_VALUES, SCATTER_REVERSE));
  impl_->count(c);
  std::vector<double> owned(size_t(c), 0.0); // this rank's owned rows, column by column
  PetscInt n = 0;
  SMPM_PETSC_CALL(VecGetLocalSize(b.global, &n));
  const PetscScalar* g = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(b.global, &g));
  for (PetscInt k = 0; k < n; ++k)
    owned[size_t(k % c)] += g[k];
  SMPM_PETSC_CALL(VecRestoreArrayRead(b.global, &g));
  MPI_Allreduce(owned.data(), totals, int(c), MPI_DOUBLE, MPI_SUM, impl_->grid.comm());
}

void WindowSums::fail() const {
  impl_->agree({1, 0});
}

} // namespace smpm::petsc
