// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file shape.hpp
/// Shape functions: the weights S_pi and gradient weights G_pi of GIMP theory
/// (Buzzi et al., Eqs. 17–18), assembled as sparse N × n matrices.

#include "sparsempm/grid.hpp"
#include "sparsempm/particles.hpp"

#include <Eigen/SparseCore>
#include <array>
#include <string_view>
#include <vector>

namespace smpm {

/// Shape-function families. All are tensor products of a 1D grid function N on each axis.
enum class Shape {
  Linear,   ///< classic MPM: S_pi = N_i(X_p) with linear hat N (Sulsky et al. 1994)
  GIMP,     ///< uGIMP: N averaged over the undeformed axis-aligned domain X_p ± r⁰
  BSpline2, ///< quadratic B-spline N evaluated at X_p (support ±1.5 cells)
  CPDI,     ///< CPDI1: corner average over the parallelogram spanned by F r⁰, hat N
  B2CPDI    ///< CPDI1 corner rule with quadratic B-spline N
};

/// Name used in input files: linear | gimp | bspline2 | cpdi | b2cpdi.
std::string_view to_string(Shape s);
/// Inverse of to_string; throws InputError naming the valid choices.
Shape shape_from_string(std::string_view name);

/// Per-particle node box (first node and count per axis) that fixes the sparsity pattern.
struct ShapeSupport {
  std::array<int, 3> first{0, 0, 0}; ///< (i, j, k) of the box's first node in the whole grid
  std::array<int, 3> count{1, 1, 1}; ///< nodes of the box along each axis (1 for unused axes)
  /// The same box: a particle whose box is unchanged keeps its row of the pattern.
  bool operator==(const ShapeSupport&) const = default;
};

/// Assembles S (N × n) and G[a] = ∂S/∂x_a (N × n, a < d) in place.
///
/// S_pi = (1/V_p) ∫ N_i χ_p dV and G_pi = (1/V_p) ∫ ∇N_i χ_p dV (Buzzi Eqs. 17–18).
/// For CPDI/B2CPDI (Sadeghirad, Brannon & Burghardt 2011) the domain is X_p + R ξ,
/// ξ ∈ [−1, 1]^d, R = F_p diag(r⁰_p); N_i is replaced by its multilinear interpolant from
/// the 2^d corners x_c = X_p + R s_c (s_c ∈ {−1, 1}^d), giving
///     S_pi = 2^{-d} Σ_c N_i(x_c),    G_pi = 2^{-d} R^{-T} Σ_c s_c N_i(x_c).
/// In 1D: S_pi = ½(N_i(a) + N_i(b)), G_pi = (N_i(b) − N_i(a))/(b − a).
///
/// Each row holds the tensor box of nodes that can be non-zero (structural zeros allowed).
/// `support` is the workspace that records the boxes of the previous call, whose S and G must
/// be on the same grid with the same fields (an empty `support` starts afresh): when every box
/// is unchanged the index arrays are kept and only values are written (no allocation); the
/// rows of boxes that moved and kept their size are rewritten in place; when a box changed
/// size the pattern is built anew. Returns true when the pattern changed. Throws
/// NumericalError naming the particle when a support leaves the grid, and then leaves S, G
/// and `support` empty.
///
/// With `fields` > 1 velocity fields (multimaterial MPM, contact.hpp) S is N × (fields · n):
/// particle p's entries sit in the block of columns of its field, node i of field α being
/// column α·n + i (`field[p]` gives p's field; its values never change between calls).
///
/// With `window`, the columns are the nodes of a window of `grid` (Grid::window) that holds
/// every particle's box: their bounding box widened to multiples of kWindowBlock nodes from the
/// grid's first node (so that it changes only when the particles cross such a line, and is the
/// same for the same configuration), clipped to the grid. *window gives the window of the
/// previous call (the numbering of the kept pattern) and receives the new one.
bool assemble_shape(const Grid& grid, const Particles& particles, Shape shape, SparseRowMatrix& S,
                    std::array<SparseRowMatrix, 3>& G, std::vector<ShapeSupport>& support,
                    int fields = 1, const int* field = nullptr, Grid* window = nullptr);

/// Nodes per block of a particle window along each axis (assemble_shape).
inline constexpr int kWindowBlock = 8;

} // namespace smpm
