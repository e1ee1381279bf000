// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal helpers of the single-pass kernels (stages.cpp, products.cpp).

#include "parallel.hpp"

#include "sparsempm/types.hpp"

#include <array>

namespace smpm::detail {

/// Throws NumericalError "particle p has what (value)" (stages.cpp): the one message of a kernel
/// that meets a bad particle.
[[noreturn]] void bad_particle(Index p, const char* what, double value);

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

/// Calls k.operator()<C0, C1, C2>() with the box of count[0] × count[1] × count[2] nodes as
/// compile-time sizes for the common boxes (2 or 3 nodes per axis: the hat, uGIMP and CPDI
/// boxes of 2D and 3D, whole or crossing cell lines), else k.operator()<0, 0, 0>() (sizes read
/// at run time). Box sizes are at most 12 per axis: one hexadecimal digit each.
template <class Kernel>
void dispatch_box(const std::array<int, 3>& count, Kernel&& k) {
  switch ((count[0] << 8) | (count[1] << 4) | count[2]) {
  case 0x221:
    return k.template operator()<2, 2, 1>();
  case 0x331:
    return k.template operator()<3, 3, 1>();
  case 0x231:
    return k.template operator()<2, 3, 1>();
  case 0x321:
    return k.template operator()<3, 2, 1>();
  case 0x222:
    return k.template operator()<2, 2, 2>();
  case 0x333:
    return k.template operator()<3, 3, 3>();
  case 0x322:
    return k.template operator()<3, 2, 2>();
  case 0x232:
    return k.template operator()<2, 3, 2>();
  case 0x223:
    return k.template operator()<2, 2, 3>();
  case 0x332:
    return k.template operator()<3, 3, 2>();
  case 0x323:
    return k.template operator()<3, 2, 3>();
  case 0x233:
    return k.template operator()<2, 3, 3>();
  default:
    return k.template operator()<0, 0, 0>();
  }
}

/// Node sums over the entries of an N × n operator (CSR outer, inner; span: each row's first and
/// last node, ColumnIndex::span), each node's terms added in ascending particle order:
/// begin(r0, r1) sets the nodes [r0, r1) of the output to their start (zero), then add(q, k0, k1)
/// is called for each particle q in order with the run of its entries [k0, k1) whose nodes
/// inner[k] are in [r0, r1) (the particle's values can be read once, into locals that the
/// output's stores cannot alias). Each thread owns a range of nodes (balanced by `col_outer`, the
/// entries of each node, or null) and reads every particle's span in order, taking the entries
/// of the rows that meet its range (a row's nodes ascend); a single range takes every row and
/// reads no span. A node's sum is then the same sequence
/// of additions as a serial loop over the particles, for any number of threads, and the rows of S
/// and the G_b stream from memory while the nodes written are those of neighbouring boxes (a
/// gather by columns reads each entry from a different particle's row). A thread reads only the
/// rows of its nodes, not every row's column indices: those stay in the cache of the thread
/// that writes them when the pattern changes (writing a line that another core has read costs
/// a round trip to take it back; with every row read by every thread, rewriting S's pattern on
/// two threads took longer than on one).
template <class Begin, class Add>
void scatter_to_nodes(const int* outer, const int* inner, const int* span, Index rows, Index nodes,
                      const int* col_outer, Begin&& begin, Add&& add) {
  parallel_ranges(nodes, rows, col_outer, [&](Index r0, Index r1) {
    begin(r0, r1);
    if (r0 == 0 && r1 == nodes) { // one range (one thread): every row, no span read
      for (Index q = 0; q < rows; ++q)
        add(q, outer[q], outer[q + 1]);
      return;
    }
    for (Index q = 0; q < rows; ++q) {
      if (span[2 * q] >= r1 || span[2 * q + 1] < r0)
        continue; // none of the row's nodes is in the range
      int k = outer[q], e = outer[q + 1];
      while (inner[k] < r0)
        ++k;
      while (inner[e - 1] >= r1)
        --e;
      add(q, k, e);
    }
  });
}

/// det of a row-major D × D matrix.
template <int D>
[[gnu::always_inline]] inline double det(const double* F) {
  if constexpr (D == 1)
    return F[0];
  else if constexpr (D == 2)
    return F[0] * F[3] - F[1] * F[2];
  else
    return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
           F[2] * (F[3] * F[7] - F[4] * F[6]);
}

} // namespace smpm::detail
