// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file convert.hpp
/// Eigen fields and sparse matrices to numpy arrays and scipy.sparse.csr_matrix, and back.

#include <sparsempm/boundary.hpp>
#include <sparsempm/types.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <string>
#include <vector>

namespace smpm::python {

namespace py = pybind11;

/// A numpy view of a row-major field (rows × cols) that keeps `owner` alive.
py::array field_view(Field& f, py::handle owner, bool writeable = true);
/// A numpy view of a vector (length n) that keeps `owner` alive.
py::array vector_view(Eigen::VectorXd& v, py::handle owner, bool writeable = true);
py::array vector_view(Eigen::VectorXi& v, py::handle owner, bool writeable = true);

/// Copies `a` into `f` when the shapes agree (a vector of length rows is taken as rows × 1);
/// throws std::invalid_argument (ValueError) naming `name` and both shapes otherwise.
void assign_field(Field& f, const py::array_t<double, py::array::forcecast>& a, const char* name);
void assign_vector(Eigen::VectorXd& v, const py::array_t<double, py::array::forcecast>& a,
                   const char* name);

/// An optional per-particle vector (Particles::temperature, heat_source: empty when absent) set
/// from a number (every particle) or an array of shape (N,): sized N (storage kept when it has
/// N entries already). Throws std::invalid_argument naming `name` and both shapes otherwise.
Eigen::VectorXd particle_vector(const py::array_t<double, py::array::forcecast>& a, Index N,
                                const char* name);

/// Conditions of moving walls hold the nodes a step selects (prepare_step): the model's own
/// BCs (model.bcs) hold none. Refuses those (InputError), which would silently leave the
/// walls out.
void check_wall_nodes(const BoundaryConditions* bcs);

/// A node or particle field from an array of shape (rows,) or (rows, cols); `rows` < 0
/// accepts any number of rows. Throws std::invalid_argument naming `name` otherwise.
Field to_field(const py::array_t<double, py::array::forcecast>& a, Index rows, const char* name);
/// The field as an array: shape (rows,) when `as_vector` (one column), else (rows, cols).
py::array from_field(Field f, bool as_vector);

/// A scipy.sparse.csr_matrix sharing the CSR arrays of `A` (compressed), which keeps `owner`
/// alive (zero-copy); read-only unless `writeable`.
py::object csr_view(const SparseRowMatrix& A, py::handle owner, bool writeable = false);
/// A scipy.sparse.csr_matrix that owns `A` (its arrays are A's, moved into a capsule).
py::object csr_owned(SparseRowMatrix A);

/// A 3-vector from at most three entries, `fill` for the missing ones; throws InputError naming
/// `name` for more than three.
std::array<double, 3> triple(const std::vector<double>& v, double fill, const char* name);

} // namespace smpm::python
