// SPDX-License-Identifier: BSD-3-Clause
// Node fields between this rank's Eigen storage and PETSc's: new node vectors, the owned rows of
// a vector in and out, and the whole vector or matrix gathered (the serial layout, for tests and
// small problems).

#include "sparsempm/petsc.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>

namespace smpm::petsc {

OwnedVec node_vector(const DistributedGrid& grid, int components) {
  OwnedVec x;
  SMPM_PETSC_CALL(
      VecCreateMPI(grid.comm(), grid.owned_rows() * components, PETSC_DETERMINE, x.out()));
  SMPM_PETSC_CALL(VecSetBlockSize(x, components));
  SMPM_PETSC_CALL(VecSet(x, 0.0));
  return x;
}

void get_owned(const DistributedGrid& grid, Vec x, int components, Field& out) {
  const Index no = grid.owned().num_nodes();
  const int fields = grid.fields();
  out.resize(no * fields, components);
  const PetscScalar* a = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(x, &a));
  // The DMDA's local rows: the owned box in natural order, the fields of a node together.
  for (Index i = 0; i < no; ++i)
    for (int f = 0; f < fields; ++f)
      for (int c = 0; c < components; ++c)
        out(f * no + i, c) = a[(i * fields + f) * components + c];
  SMPM_PETSC_CALL(VecRestoreArrayRead(x, &a));
}

void set_owned(const DistributedGrid& grid, const Field& in, Vec x) {
  const Index no = grid.owned().num_nodes();
  const int fields = grid.fields();
  const Index components = in.cols();
  PetscScalar* a = nullptr;
  SMPM_PETSC_CALL(VecGetArray(x, &a));
  for (Index i = 0; i < no; ++i)
    for (int f = 0; f < fields; ++f)
      for (Index c = 0; c < components; ++c)
        a[(i * fields + f) * components + c] = in(f * no + i, c);
  SMPM_PETSC_CALL(VecRestoreArray(x, &a));
}

Field gather(const DistributedGrid& grid, Vec x, int components) {
  const bool root = grid.rank() == 0;
  const Index ng = grid.grid().whole_num_nodes();
  const int fields = grid.fields();
  // On rank 0, the PETSc entry of every serial row α n_g + i and component.
  std::vector<PetscInt> nodes, rows, from;
  if (root) {
    nodes.resize(size_t(ng));
    for (Index i = 0; i < ng; ++i)
      nodes[size_t(i)] = PetscInt(i);
  }
  for (int f = 0; f < fields; ++f) {
    grid.petsc_rows(nodes, f, rows);
    for (PetscInt r : rows)
      for (int c = 0; c < components; ++c)
        from.push_back(r * components + c);
  }
  OwnedIS is;
  SMPM_PETSC_CALL(ISCreateGeneral(PETSC_COMM_SELF, PetscInt(from.size()), from.data(),
                                  PETSC_COPY_VALUES, is.out()));
  OwnedVec y;
  SMPM_PETSC_CALL(VecCreateSeq(PETSC_COMM_SELF, PetscInt(from.size()), y.out()));
  OwnedScatter scatter;
  SMPM_PETSC_CALL(VecScatterCreate(x, is, y, nullptr, scatter.out()));
  SMPM_PETSC_CALL(VecScatterBegin(scatter, x, y, INSERT_VALUES, SCATTER_FORWARD));
  SMPM_PETSC_CALL(VecScatterEnd(scatter, x, y, INSERT_VALUES, SCATTER_FORWARD));
  Field out;
  if (root) {
    out.resize(ng * fields, components);
    const PetscScalar* a = nullptr;
    SMPM_PETSC_CALL(VecGetArrayRead(y, &a));
    std::copy(a, a + out.size(), out.data());
    SMPM_PETSC_CALL(VecRestoreArrayRead(y, &a));
  }
  return out;
}

SparseMatrix gather(const DistributedGrid& grid, Mat a) {
  const bool root = grid.rank() == 0;
  const PetscInt N = grid.global_rows();
  OwnedIS all;
  SMPM_PETSC_CALL(ISCreateStride(PETSC_COMM_SELF, root ? N : 0, 0, 1, all.out()));
  Mat* sub = nullptr;
  IS rows = all;
  SMPM_PETSC_CALL(MatCreateSubMatrices(a, 1, &rows, &rows, MAT_INITIAL_MATRIX, &sub));
  // The serial index α n_g + i of PETSc row r: AO⁻¹(r) = i · fields + α.
  std::vector<PetscInt> serial;
  if (root) {
    serial.resize(size_t(N));
    for (PetscInt r = 0; r < N; ++r)
      serial[size_t(r)] = r;
  }
  AO ao = nullptr; // the DMDA's application ordering: the natural (serial) numbering
  SMPM_PETSC_CALL(DMDAGetAO(grid.dm(), &ao));
  SMPM_PETSC_CALL(
      AOPetscToApplication(ao, PetscInt(serial.size()), serial.empty() ? nullptr : serial.data()));
  const PetscInt ng = PetscInt(grid.grid().whole_num_nodes());
  const int fields = grid.fields();
  for (PetscInt& s : serial)
    s = (s % fields) * ng + s / fields;
  SparseMatrix out;
  if (root) {
    std::vector<Eigen::Triplet<double, int>> entries;
    for (PetscInt r = 0; r < N; ++r) {
      PetscInt nnz = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      SMPM_PETSC_CALL(MatGetRow(sub[0], r, &nnz, &cols, &vals));
      for (PetscInt k = 0; k < nnz; ++k)
        entries.emplace_back(int(serial[size_t(r)]), int(serial[size_t(cols[k])]), vals[k]);
      SMPM_PETSC_CALL(MatRestoreRow(sub[0], r, &nnz, &cols, &vals));
    }
    out.resize(int(N), int(N));
    out.setFromTriplets(entries.begin(), entries.end());
  }
  SMPM_PETSC_CALL(MatDestroySubMatrices(1, &sub));
  return out;
}

} // namespace smpm::petsc
