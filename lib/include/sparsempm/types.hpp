// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file types.hpp
/// Matrix types shared by the library.

#include <Eigen/Core>
#include <Eigen/SparseCore>

/// Every public name of sparsempm and of its components (exact, analysis, io): the MPM
/// operators as explicit sparse matrices, the step made of them, its analysis, input and output.
namespace smpm {

/// Eigen's signed index type (std::ptrdiff_t): counts and indices of particles, nodes and
/// matrix entries.
using Index = Eigen::Index;

/// A dense field with one row per particle (N × d, N × d²) or per node (n × d). Row-major,
/// so that one sparse product S x moves all d components in a single pass over S and each
/// particle's tensor is contiguous.
using Field = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A writable view of a field or of a block of its rows (row-major rows, any row stride): the
/// kernels take particle fields this way, so that one material's rows can be passed.
using FieldRef = Eigen::Ref<Field>;
/// A read-only view of a field or of a block of its rows.
using ConstFieldRef = Eigen::Ref<const Field>;
/// A read-only view of a per-particle or per-node vector.
using ConstVectorRef = Eigen::Ref<const Eigen::VectorXd>;

/// N × n sparse matrix with one row per particle (row-major: a particle's nodes are contiguous).
using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
/// n × n (or n × N) sparse matrix, column-major.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

} // namespace smpm
