// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal helpers of the kernels over a particle's row of S and the G_b (stages.cpp,
// particle_update.cpp).

#include "sparsempm/errors.hpp"
#include "sparsempm/stages.hpp"

#include <string>

namespace smpm::detail {

// The CSR arrays of S and the G_b and a node field's data, copied into locals by each range of
// particles of a kernel: its loop then keeps them in registers (read through `op` and the
// Eigen objects, they are loaded again after each store to a particle's row, which the compiler
// cannot prove does not alias them).
template <int D>
struct Rows {
  const int* outer;
  const int* inner;
  const double* S;
  const double* G[D];
  explicit Rows(const ParticleOperators& op) : outer(op.outer), inner(op.inner), S(op.S) {
    for (int b = 0; b < D; ++b)
      G[b] = op.G[size_t(b)];
  }
};

// Checks that v is a node field of the operators (n × d).
inline void check_node_field(const ParticleOperators& op, const Field& v, const char* who) {
  SMPM_VERIFY(v.rows() == op.nodes && v.cols() == op.dim,
              std::string(who) + ": the node field must be n x d");
}

} // namespace smpm::detail
