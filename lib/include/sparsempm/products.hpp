#pragma once
/// \file products.hpp
/// Sparse × dense products of the step, as single passes over the CSR arrays of S and G.
///
/// Each function is the matrix expression in its comment; Eigen evaluates the same
/// expressions one column of the dense operand at a time, which for the n × d and N × d
/// fields of MPM costs several passes over S. The tests check every kernel against Eigen.

#include "sparsempm/types.hpp"

#include <array>

namespace smpm {

/// Y = A X for A (N × n, row-major) and X (n × c); Y is resized to N × c.
void multiply(const SparseRowMatrix& A, const Field& X, Field& Y);
/// Y = Aᵀ X for A (N × n, row-major) and X (N × c); Y is resized to n × c.
void multiply_transpose(const SparseRowMatrix& A, const Field& X, Field& Y);

/// Velocity gradient L_p = Σ_i v_i ⊗ G_pi: L(p, a d + b) = Σ_i G_b(p, i) v(i, a), i.e. column
/// a d + b of L (N × d²) is (G_b v)_{·a}. The d matrices G_b must share one sparsity pattern.
void gradient_product(const std::array<SparseRowMatrix, 3>& G, int d, const Field& v, Field& L);
/// Divergence-type product f(i, a) = Σ_p Σ_b G_b(p, i) T(p, a d + b), i.e.
/// f = Σ_b G_bᵀ T_{·(a, b)} for a tensor field T (N × d²); f is resized to n × d.
/// With T = −Ω J σ this is the internal force of FMPM 2026 task 2.
void divergence_product(const std::array<SparseRowMatrix, 3>& G, int d, const Field& T, Field& f);

} // namespace smpm
