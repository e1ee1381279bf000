// SPDX-License-Identifier: BSD-3-Clause
#include "convert.hpp"

#include <sparsempm/errors.hpp>

#include <algorithm>
#include <stdexcept>

namespace smpm::python {

namespace {

template <class T>
py::array view(T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               py::handle owner, bool writeable) {
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides), data, owner);
  if (!writeable)
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i)
    s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

} // namespace

py::array field_view(Field& f, py::handle owner, bool writeable) {
  const auto w = py::ssize_t(sizeof(double));
  return view(f.data(), {f.rows(), f.cols()}, {f.cols() * w, w}, owner, writeable);
}

py::array vector_view(Eigen::VectorXd& v, py::handle owner, bool writeable) {
  return view(v.data(), {v.size()}, {py::ssize_t(sizeof(double))}, owner, writeable);
}

py::array vector_view(Eigen::VectorXi& v, py::handle owner, bool writeable) {
  return view(v.data(), {v.size()}, {py::ssize_t(sizeof(int))}, owner, writeable);
}

void assign_field(Field& f, const py::array_t<double, py::array::forcecast>& a, const char* name) {
  const bool column = a.ndim() == 1 && f.cols() == 1 && a.shape(0) == f.rows();
  if (!column && !(a.ndim() == 2 && a.shape(0) == f.rows() && a.shape(1) == f.cols()))
    throw std::invalid_argument(std::string(name) + ": expected shape (" +
                                std::to_string(f.rows()) + ", " + std::to_string(f.cols()) +
                                "), got " + shape_text(a) + " (the particle count is fixed)");
  f = to_field(a, f.rows(), name);
}

void assign_vector(Eigen::VectorXd& v, const py::array_t<double, py::array::forcecast>& a,
                   const char* name) {
  if (a.ndim() != 1 || a.shape(0) != v.size())
    throw std::invalid_argument(std::string(name) + ": expected shape (" +
                                std::to_string(v.size()) + ",), got " + shape_text(a));
  for (Index i = 0; i < v.size(); ++i)
    v[i] = a.at(i);
}

Eigen::VectorXd particle_vector(const py::array_t<double, py::array::forcecast>& a, Index N,
                                const char* name) {
  if (a.ndim() == 0)
    return Eigen::VectorXd::Constant(N, *a.data());
  if (a.ndim() != 1 || a.shape(0) != N)
    throw std::invalid_argument(std::string(name) + ": expected a number or shape (" +
                                std::to_string(N) + ",), got " + shape_text(a) +
                                " (one value per particle)");
  Eigen::VectorXd v(N);
  for (Index i = 0; i < N; ++i)
    v[i] = a.at(i);
  return v;
}

Field to_field(const py::array_t<double, py::array::forcecast>& a, Index rows, const char* name) {
  if ((a.ndim() != 1 && a.ndim() != 2) || (rows >= 0 && a.shape(0) != rows))
    throw std::invalid_argument(std::string(name) + ": expected " +
                                (rows >= 0 ? std::to_string(rows) : std::string("N")) +
                                " rows (shape (rows,) or (rows, d)), got shape " + shape_text(a));
  const Index n = a.shape(0), d = a.ndim() == 2 ? a.shape(1) : 1;
  Field f(n, d);
  const auto r = a.unchecked();
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < d; ++j)
      f(i, j) = a.ndim() == 2 ? r(i, j) : r(i);
  return f;
}

py::array from_field(Field f, bool as_vector) {
  auto* owned = new Field(std::move(f));
  py::capsule free(owned, [](void* p) { delete static_cast<Field*>(p); });
  if (as_vector && owned->cols() == 1)
    return view(owned->data(), {owned->rows()}, {py::ssize_t(sizeof(double))}, free, true);
  return field_view(*owned, free, true);
}

py::object csr_view(const SparseRowMatrix& A, py::handle owner, bool writeable) {
  SMPM_VERIFY(A.isCompressed(), "csr_view: the matrix must be compressed");
  auto* values = const_cast<double*>(A.valuePtr());
  auto* inner = const_cast<int*>(A.innerIndexPtr());
  auto* outer = const_cast<int*>(A.outerIndexPtr());
  const py::ssize_t nnz = A.nonZeros(), rows = A.rows();
  const auto data = view(values, {nnz}, {py::ssize_t(sizeof(double))}, owner, writeable);
  const auto indices = view(inner, {nnz}, {py::ssize_t(sizeof(int))}, owner, writeable);
  const auto indptr = view(outer, {rows + 1}, {py::ssize_t(sizeof(int))}, owner, writeable);
  const py::object csr = py::module_::import("scipy.sparse").attr("csr_matrix");
  return csr(py::make_tuple(data, indices, indptr),
             py::arg("shape") = py::make_tuple(rows, A.cols()), py::arg("copy") = false);
}

py::object csr_owned(SparseRowMatrix A) {
  A.makeCompressed();
  auto* owned = new SparseRowMatrix(std::move(A));
  py::capsule free(owned, [](void* p) { delete static_cast<SparseRowMatrix*>(p); });
  return csr_view(*owned, free, true);
}

void check_wall_nodes(const BoundaryConditions* bcs) {
  if (!bcs)
    return;
  for (const VelocityCondition& c : bcs->conditions)
    if (c.wall >= 0 && c.nodes.empty())
      throw InputError("bcs: the wall '" + c.label +
                       "' has no nodes selected (model.bcs as given); pass ops.bcs, the "
                       "conditions a step from this configuration uses, walls included");
}

std::array<double, 3> triple(const std::vector<double>& v, double fill, const char* name) {
  if (v.size() > 3)
    throw InputError(std::string(name) + ": at most 3 entries, got " + std::to_string(v.size()));
  std::array<double, 3> t{fill, fill, fill};
  std::copy(v.begin(), v.end(), t.begin());
  return t;
}

} // namespace smpm::python
