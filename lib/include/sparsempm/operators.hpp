// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file operators.hpp
/// The operators of one MPM time step as explicit sparse matrices (FMPM 2026 §2.1):
///     p = Sᵀ M V,   m = Sᵀ M,   m̃ = Sᵀ M S,   S⁺ = m⁻¹ Sᵀ M,   A = I − S⁺ S = I − m⁻¹ m̃.

#include "sparsempm/grid.hpp"
#include "sparsempm/particles.hpp"
#include "sparsempm/shape.hpp"

#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace smpm {

/// Relative tolerance of an active node: m_i > kMassTolerance · max_j m_j (Buzzi §4.4 M_TOL).
inline constexpr double kMassTolerance = 1e-10;

/// The pattern of an N × n operator by columns (a transpose index of S): node i has
/// outer[i + 1] − outer[i] entries; with `lists`, they are entry[outer[i]] … entry[outer[i + 1] −
/// 1] (positions in S's CSR arrays) of the particles row[outer[i]] …, in ascending particle order.
/// The node sums of a step (p = Sᵀ M V, m = Sᵀ M, f, m̃) scatter the rows of S by node ranges
/// (balanced by `outer`), each range taking the rows whose `span` meets it; the lists serve what
/// needs a node's particles (the point clouds and volumes of multimaterial contact), and are
/// built for operators of several velocity fields.
struct ColumnIndex {
  std::vector<int> outer; ///< n + 1 offsets
  /// 2N: the first and last node of each row of S (an empty row: INT_MAX, −1). The threads of a
  /// node sum each read the spans of every row, not S's column indices, so that those stay in
  /// the cache of the thread that writes them when the pattern changes (a line another core
  /// has read must be taken back from it before it is written).
  std::vector<int> span;
  std::vector<int> entry; ///< nnz positions in S's arrays (with `lists`, else empty)
  std::vector<int> row;   ///< nnz particles (with `lists`, else empty)
  std::vector<int> work;  ///< workspace of the build: per-chunk counts and positions
  bool lists = false;     ///< whether entry and row are built
  Index nonzeros = -1;    ///< S's nonzeros when the index was built (−1: never)
};

/// Builds the column index of S (rows: particles, columns: nodes): the offsets, the row spans,
/// and with `lists` the entries and particles of each column.
void build_column_index(const SparseRowMatrix& S, ColumnIndex& columns, bool lists = true);

/// The nodes the columns of S number.
enum class NodeRange {
  Grid,     ///< every node of the grid
  Particles ///< the window of the grid around the particles' boxes (assemble_shape), so that
            ///< the nodal fields and their storage follow the particles, not the grid
};

/// Names of StepOptions::nodes: particles | grid.
std::string_view to_string(NodeRange r);
/// The node range named `name`; throws InputError naming the valid choices.
NodeRange node_range_from_string(std::string_view name);

/// Everything a time step needs from the particle configuration, assembled once per step.
///
/// Multimaterial MPM (contact.hpp) keeps one S with the velocity fields as blocks of columns:
/// n = fields · n_g, node i of field α is column α·n_g + i, and a particle's row has entries
/// only in its field's block. Then p, m, m_inv, active and m̃ hold every field (m̃ block
/// diagonal: m̃ = Σ_α m̃^α, FMPM 2026 Eq. 15) and each kernel of the step serves all fields in
/// one pass; with one field n = n_g and nothing changes.
///
/// With NodeRange::Particles the nodes are those of `grid`, a window of the model's grid
/// (Grid::window): node i of the operators is node grid.whole_node(i) of the model's grid, and
/// every function given node fields takes `grid` with them.
struct Operators {
  NodeRange node_range = NodeRange::Grid; ///< chosen by the caller before assembling
  Grid grid;                              ///< the grid whose nodes the columns are
  /// d, the grid's dimension.
  int dim = 1;
  int fields = 1;                   ///< velocity fields (blocks of columns)
  Index grid_node_count{};          ///< n_g, nodes of `grid`
  SparseRowMatrix S;                ///< N × n shape-function weights S_pi
  std::array<SparseRowMatrix, 3> G; ///< G[a]: N × n gradient weights ∂S_pi/∂x_a (a < d)
  Eigen::VectorXd M;                ///< N particle masses (the diagonal of 𝗠)
  Eigen::VectorXd m;                ///< n lumped nodal masses m = Sᵀ M
  /// n: m_i > kMassTolerance · max m; with several fields, m^α_i > kMassTolerance times the
  /// largest total nodal mass Σ_α m^α_i (the tolerance of single material mode)
  Eigen::Array<bool, Eigen::Dynamic, 1> active;
  Eigen::VectorXd m_inv;                  ///< n: 1/m_i on active nodes, 0 elsewhere
  std::vector<ShapeSupport> support;      ///< workspace: the pattern of S and G
  Eigen::VectorXi field;                  ///< the particle fields of the pattern (fields > 1)
  ColumnIndex columns;                    ///< S's pattern by columns
  std::array<int, 3> grid_nodes{1, 1, 1}; ///< nodes per axis of `grid`
  long pattern_version = 0; ///< a new process-unique number whenever S's pattern changes
  /// N, the rows of S (one per particle).
  Index num_particles() const { return S.rows(); }
  /// n = fields · n_g, the columns of S (one per node of each velocity field).
  Index num_nodes() const { return S.cols(); }
  /// The index of column c in the numbering of the whole grid (α n_g + i for node i of field α,
  /// n_g the grid's nodes): what files and messages name.
  Index whole_node(Index c) const {
    return (c / grid_node_count) * grid.whole_num_nodes() + grid.whole_node(c % grid_node_count);
  }
  /// Column c as a message names it: "node i" of the whole grid, with " of velocity field α"
  /// when there are several fields (whose columns α n_g + i are not nodes of the grid).
  std::string node_text(Index c) const {
    const std::string node = "node " + std::to_string(grid.whole_node(c % grid_node_count));
    return fields > 1 ? node + " of velocity field " + std::to_string(c / grid_node_count) : node;
  }
};

/// Assembles S, G, M, m and the active set for the current configuration, reusing the
/// sparsity pattern (and all storage) when no particle changed its node box. With `field`
/// (one entry per particle, values in [0, fields)) the fields are blocks of columns. The
/// columns are the nodes of `grid` or of the particles' window of it (ops.node_range).
void assemble(const Grid& grid, const Particles& particles, Shape shape, Operators& ops,
              int fields = 1, const Eigen::VectorXi* field = nullptr);
/// Convenience form returning fresh operators.
Operators assemble(const Grid& grid, const Particles& particles, Shape shape);

/// The largest total nodal mass max_i Σ_α m^α_i of the node masses m (`fields` blocks of `ng`
/// rows: field α's mass at node i in row α ng + i) over the nodes [begin, end) of a block: this
/// process's share of the reference of the active-node rule (active_nodes_of).
double largest_total_mass(const Eigen::Ref<const Eigen::VectorXd>& m, int fields, Index ng,
                          Index begin, Index end);
/// The active-node rule (Buzzi §4.4 M_TOL), the one rule of the assembly, of the analysis across
/// processes and of the PETSc operators: row i of m is active when m_i > kMassTolerance ·
/// `largest`, the largest total nodal mass (largest_total_mass, over every process), and
/// m⁻¹_i = 1/m_i on active rows, 0 elsewhere. Multimaterial: a field alone on a node is then
/// active exactly when the node is in single material mode. Writes the rows [begin, end) of
/// `active` and `m_inv`, which must have m's size.
void active_nodes_of(const Eigen::Ref<const Eigen::VectorXd>& m, double largest, Index begin,
                     Index end, Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                     Eigen::VectorXd& m_inv);

/// Indices of the active nodes, ascending.
Eigen::VectorXi active_nodes(const Operators& ops);

/// Consistent (full) mass matrix m̃ = Sᵀ diag(M) S, n × n, symmetric positive
/// semidefinite; its row sums are the lumped masses (FMPM 2026 §2.1). Exact zeros pruned.
SparseMatrix consistent_mass(const Operators& ops);

/// Storage of m̃ in its stencil pattern, reused from step to step: row i holds every node
/// within the stencil half-width w_a = max_p (box_a − 1) of node i along each axis (structural
/// zeros allowed); rows of nodes no particle touches are empty.
struct ConsistentMass {
  SparseRowMatrix matrix;                    ///< n × n (symmetric for m̃, c̃)
  std::array<int, 3> half_width{-1, -1, -1}; ///< stencil half-width of the pattern
  std::array<int, 3> grid_nodes{0, 0, 0};    ///< nodes per axis of the pattern's grid
  std::vector<char> touched;                 ///< n: node in some particle's box
  bool pattern_reused = false;               ///< the last assembly kept the pattern
  const Operators* source = nullptr;         ///< the operators of the last assembly ...
  long source_version = -1;                  ///< ... and their pattern version
};
/// m̃_ij = Σ_p M_p S_pi S_pj written directly into the stencil pattern (no sparse × sparse
/// product): the particles in order scatter their boxes' products into the rows, each thread
/// owning a range of rows, so each entry sums its particles in ascending order on any number of
/// threads; the pattern is rebuilt only when the stencil width or the touched set changes.
void assemble_consistent_mass(const Operators& ops, ConsistentMass& mt);
/// The mass operator of the velocity-gradient transfer (Transfer::VelocityGradient), in m̃'s
/// stencil storage: m̃_L = Sᵀ M S + Σ_b D_bᵀ M G_b, D_b = S ∘ (x_ib − X_pb), that is
/// (m̃_L)_ij = Σ_p M_p S_pi (S_pj + (x_i − X_p) · ∇S_pj): the P2G of the transfer (p_i =
/// Σ_p S_pi M_p (V_p + L_p (x_i − X_p))) applied to the G2P of a grid velocity v (V_p = S v,
/// L_p = G v). It takes the place of m̃ in the FMPM loop, XPIC and the exact update with that
/// transfer, so that they see the transfer's own reverse map: m̃_L v = m v for every affine v
/// (I − m⁻¹ m̃_L annihilates affine fields). Not symmetric. X: the particles' positions (N × d)
/// of `ops`' assembly; the rows are `ops`' columns, nodes of ops.grid.
void assemble_transfer_mass(const Operators& ops, const ConstFieldRef& X, ConsistentMass& mt);
/// The mass operator of an affine transfer whose G2P takes L_p = Σ_j v_j ⊗ g_pj, with the
/// weights g_b (one array per direction b < d over S's entries, in S's order) in place of ∇S:
/// (m̃)_ij = Σ_p M_p S_pi (S_pj + (x_i − X_p) · g_pj), in m̃'s stencil storage.
/// assemble_transfer_mass is g = ∇S (m̃_L); with APIC's weights Ĝ_pj = D_p⁻¹ S_pj Δ_pj
/// (stages.hpp, apic_weights) it is m̃_A, (m̃_A)_ij = Σ_p M_p S_pi S_pj (1 + Δ_piᵀ D_p⁻¹ Δ_pj):
/// symmetric, rows summing to m, m̃_A v = m v for every affine v, and m̃ ≤ m̃_A ≤ m (vᵀ m̃_A v =
/// Σ_p M_p (V_p² + tr(C_p D_p C_pᵀ)), APIC's kinetic energy, and C_p D_p C_pᵀ is the weighted
/// least-squares part of Σ_i S_pi (v_i − V_p)², the rest of vᵀ m v). X: as assemble_transfer_mass.
void assemble_affine_mass(const Operators& ops, const ConstFieldRef& X,
                          const std::array<const double*, 3>& gradient, ConsistentMass& mt);
/// Lumped reverse map S⁺ = m⁻¹ Sᵀ M, n × N; rows of inactive nodes are zero (FMPM 2026 §2.1).
SparseMatrix S_plus(const Operators& ops);
/// Expansion matrix A = I − m⁻¹ m̃ = I − S⁺ S (FMPM 2026 Eq. 1), n × n, restricted to the
/// active nodes: rows and columns of inactive nodes are zero.
SparseMatrix expansion_matrix(const Operators& ops);

} // namespace smpm
