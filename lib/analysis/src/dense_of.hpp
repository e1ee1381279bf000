// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The dense matrix of a linear operator given by its action (internal): what dense() of the
// linearised steps (stability.hpp, transport_stability.hpp) and the small ρ(A) of spectrum.cpp
// compute.

#include "sparsempm/types.hpp"

#include <Eigen/Core>

namespace smpm::detail {

/// The n × n matrix of T (n = T.rows()), column j = T e_j by one T.perform_op(x, y) per unit
/// vector e_j (raw arrays of n doubles, as Spectra's operator concept).
template <class Op>
Eigen::MatrixXd dense_of(const Op& T) {
  const Index n = T.rows();
  Eigen::MatrixXd D(n, n);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n), col(n);
  for (Index j = 0; j < n; ++j) {
    e[j] = 1;
    T.perform_op(e.data(), col.data());
    D.col(j) = col;
    e[j] = 0;
  }
  return D;
}

} // namespace smpm::detail
