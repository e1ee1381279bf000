// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The equations of the exact solve without their factorisation (internal to sparsempm_exact):
// m̃_FF v_F = p_F − m̃_FC v_C of FMPM 2026 §3.1 (k → ∞), F grouped by component, m̃_FF blended
// with m as of §3.3 and stored for a sparse factorisation (exact.cpp).

#include "sparsempm/operators.hpp"
#include "sparsempm/step_options.hpp"

#include <string>
#include <utility>
#include <vector>

namespace smpm::detail {

/// m̃ restricted to one set F of free active nodes: the rows of F in CSR, which is the CSC of
/// the restricted matrix's transpose (and of the matrix itself when m̃ is symmetric).
struct Restricted {
  std::vector<int> free;           ///< local → node
  std::vector<int> colptr, rowind; ///< pattern of the restricted matrix
  std::vector<double> values;      ///< its values, as rowind
  std::vector<int> comps;          ///< the velocity components solved with this factor
};

/// Components grouped by their free set F (active nodes whose component is not prescribed, NaN
/// in `prescribed`): components with the same F share one factorisation. Pairs (F, components).
std::vector<std::pair<std::vector<int>, std::vector<int>>> free_groups(const Operators& ops,
                                                                       const Field& prescribed);

/// The blended matrix (1 − ε) m̃_FF + ε m_F of F into `f` (ε = `regularization`): its rows in
/// CSR, stored as the CSC of the transpose (for a symmetric m̃ the CSC of the matrix: row j is
/// column j); `local` maps node → position in F (−1 outside). Returns whether the pattern equals
/// the one already factorised (`factored`: a factor of the old pattern exists).
bool restrict_matrix(const Operators& ops, const SparseRowMatrix& mt, double regularization,
                     const std::vector<int>& local, Restricted& f, const std::vector<int>& F,
                     bool factored);

/// Right-hand sides b = p_F − blend m̃_FC v_C of a symmetric m̃ (column by column: m̃_lc = m̃_cl),
/// one column per component of `comps`, blend = 1 − ε; sets v_C in v.
Eigen::MatrixXd symmetric_right_hand_sides(const Operators& ops, const SparseRowMatrix& mt,
                                           double blend, const Field& p, const Field& prescribed,
                                           const std::vector<int>& F, const std::vector<int>& local,
                                           const std::vector<int>& comps, Field& v);

/// Right-hand sides b = p_F − blend m̃_FC v_C of a general m̃ (row by row: m̃_lc ≠ m̃_cl), one
/// column per component of `comps`; sets v_C in v.
Eigen::MatrixXd general_right_hand_sides(const SparseRowMatrix& mt, double blend, const Field& p,
                                         const Field& prescribed, const std::vector<int>& F,
                                         const std::vector<int>& comps, Field& v);

/// The nodes of smallest lumped mass (or capacity: ops.m of `system`) among `free`, for the
/// messages of a failed factorisation: "smallest lumped masses: node 3 (m = 0.1), ...".
std::string lightest_nodes(const Operators& ops, const std::vector<int>& free, NodalSystem system);

/// The end of those messages: the two remedies (ExactOptions), in the words of `system`.
std::string remedies(NodalSystem system);

} // namespace smpm::detail
