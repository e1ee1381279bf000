// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal helpers of the single-pass kernels (stages.cpp, products.cpp).

#include "sparsempm/types.hpp"

namespace smpm::detail {

/// The CSR arrays of an N × n operator.
struct Csr {
  const int* outer;
  const int* inner;
  const double* val;
  explicit Csr(const SparseRowMatrix& A)
      : outer(A.outerIndexPtr()), inner(A.innerIndexPtr()), val(A.valuePtr()) {}
};

/// Calls k.operator()<N>() for the first N of Ns equal to v; returns false when none is.
template <int... Ns, class Kernel>
bool dispatch_int(int v, Kernel&& k) {
  return ((v == Ns ? (k.template operator()<Ns>(), true) : false) || ...);
}

/// Calls k.operator()<D>() with the dimension d ∈ {1, 2, 3} as a compile-time constant.
template <class Kernel>
void by_dim(int d, Kernel&& k) {
  if (!dispatch_int<1, 2>(d, k))
    k.template operator()<3>();
}

/// det of a row-major D × D matrix.
template <int D>
double det(const double* F) {
  if constexpr (D == 1)
    return F[0];
  else if constexpr (D == 2)
    return F[0] * F[3] - F[1] * F[2];
  else
    return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
           F[2] * (F[3] * F[7] - F[4] * F[6]);
}

} // namespace smpm::detail
