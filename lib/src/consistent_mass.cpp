// SPDX-License-Identifier: BSD-3-Clause
// The consistent mass m̃ = Sᵀ diag(M) S (FMPM 2026 §2.1) written directly into its stencil
// pattern, reused from step to step (operators.hpp, assemble_consistent_mass), and the consistent
// capacity c̃ = Sᵀ diag(M C_V) S of heat transport on the grid's nodes (transport.hpp), the same
// product with other particle weights and the velocity fields folded.

#include "sparsempm/operators.hpp"
#include "sparsempm/transport.hpp"

#include "kernels.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

namespace smpm {

namespace {
// First node and width of row i's stencil along an axis.
inline void stencil(int i, int w, int nodes, int& lo, int& count) {
  lo = std::max(0, i - w);
  count = std::min(nodes - 1, i + w) - lo + 1;
}
} // namespace

namespace {
// The product Sᵀ diag(w) S of one assembly: the operators' S, the particle weights w (M for m̃,
// M C_V for c̃) and its rows: every column of S (n), or with `fold` the n_g grid nodes, column
// α n_g + i of field α adding into node i (c̃ = Σ_α c̃^α).
struct StencilProduct {
  const Operators& ops;
  const double* weight; // N
  bool fold;
  // An affine transfer's mass (assemble_affine_mass): the particles' positions (N × d), null
  // for Sᵀ diag(w) S, and the gradient weights g_b over S's entries (∇S for m̃_L, APIC's Ĝ).
  const ConstFieldRef* X = nullptr;
  std::array<const double*, 3> gradient{};
  Index rows() const { return fold ? ops.grid_node_count : ops.num_nodes(); }
  // The rows of a product with several fields repeat per field block (m̃ is block diagonal).
  Index block() const { return ops.grid_node_count; }
  // Row of entry k of particle p's row of S.
  Index row(int column) const { return fold ? column % ops.grid_node_count : column; }
};

// Whether the stencil pattern can be kept: the same operators with the same pattern of S, or
// the same stencil half-width, nodes per axis and touched nodes. Records the new width and touched
// set. Both come from what the assembly already holds: the boxes (a reduction over the
// particles) and the column index of S (a column with entries is a touched node), not a pass
// over the entries of S.
bool keep_stencil_pattern(const StencilProduct& product, ConsistentMass& mt) {
  const Operators& ops = product.ops;
  const Index n = product.rows();
  if (mt.source == &ops && mt.source_version == ops.pattern_version && mt.matrix.rows() == n)
    return true;
  double widest[3];
  detail::ordered_reduce(
      Index(ops.support.size()), 3, 0.0, widest,
      [&](Index p, double* acc) {
        const ShapeSupport& s = ops.support[size_t(p)];
        for (int a = 0; a < 3; ++a)
          acc[a] = std::max(acc[a], double(s.count[size_t(a)] - 1));
      },
      [](double a, double b) { return std::max(a, b); });
  const std::array<int, 3> w{int(widest[0]), int(widest[1]), int(widest[2])};
  const std::vector<int>& col = ops.columns.outer;
  SMPM_VERIFY(col.size() == size_t(ops.S.cols() + 1) && ops.columns.nonzeros == ops.S.nonZeros(),
              "assemble_consistent_mass: the column index of S is not that of its pattern");
  std::vector<char> touched(size_t(n), 0);
  if (product.fold) { // several columns (one per field) fold onto a row
    for (Index c = 0; c < ops.S.cols(); ++c)
      if (col[size_t(c + 1)] > col[size_t(c)])
        touched[size_t(product.row(int(c)))] = 1;
  } else {
    detail::parallel_for(
        n, [&](Index i) { touched[size_t(i)] = col[size_t(i + 1)] > col[size_t(i)]; });
  }
  // The same numbers of rows can be a window of another shape (8 × 16 and 16 × 8 nodes).
  const bool keep = w == mt.half_width && ops.grid_nodes == mt.grid_nodes &&
                    touched == mt.touched && mt.matrix.rows() == n;
  mt.half_width = w;
  mt.grid_nodes = ops.grid_nodes;
  mt.touched.swap(touched);
  mt.source = &ops;
  mt.source_version = ops.pattern_version;
  return keep;
}

// The stencil pattern: row i of a touched node holds every node within the half-width. The row
// lengths, then (after their prefix sum) the rows are written in parallel.
void build_stencil_pattern(const StencilProduct& product, ConsistentMass& mt) {
  const Operators& ops = product.ops;
  const Index n = product.rows(), ng = product.block();
  const auto& nodes = ops.grid_nodes;
  const auto& w = mt.half_width;
  // Row i of field α (i = α n_g + j) couples j to its stencil within the same field: m̃ is
  // block diagonal (FMPM 2026 Eq. 15).
  auto box = [&](Index i, int lo[3], int c[3]) {
    const Index j = i % ng;
    const int ijk[3] = {int(j % nodes[0]), int((j / nodes[0]) % nodes[1]),
                        int(j / (Index(nodes[0]) * nodes[1]))};
    for (int a = 0; a < 3; ++a)
      stencil(ijk[a], w[size_t(a)], nodes[size_t(a)], lo[a], c[a]);
  };
  SparseRowMatrix& A = mt.matrix;
  A.resize(n, n);
  int* ro = A.outerIndexPtr();
  detail::parallel_for(n, [&](Index i) {
    int lo[3], c[3];
    box(i, lo, c);
    ro[i + 1] = mt.touched[size_t(i)] ? c[0] * c[1] * c[2] : 0;
  });
  ro[0] = 0;
  Index nnz = 0;
  for (Index i = 1; i <= n; ++i) {
    nnz += ro[i];
    if (nnz > std::numeric_limits<int>::max()) {
      // As S's pattern (assemble_shape): nothing stale is kept, the next call starts afresh.
      mt.source = nullptr;
      A.resize(0, 0);
      throw NumericalError("m~ would hold at least " + std::to_string(nnz) +
                           " nonzeros, more than its 32-bit indices allow");
    }
    ro[i] = int(nnz);
  }
  A.resizeNonZeros(nnz);
  int* ri = A.innerIndexPtr();
  detail::parallel_for(n, [&](Index i) {
    if (!mt.touched[size_t(i)])
      return;
    int lo[3], c[3];
    box(i, lo, c);
    const Index block = i - i % ng;
    int* row = ri + ro[i];
    for (int k2 = 0; k2 < c[2]; ++k2)
      for (int k1 = 0; k1 < c[1]; ++k1) {
        const int line =
            int(block + lo[0] + Index(nodes[0]) * ((lo[1] + k1) + Index(nodes[1]) * (lo[2] + k2)));
        for (int k0 = 0; k0 < c[0]; ++k0)
          *row++ = line + k0;
      }
  });
}

// The most entries of a row of S: a box of up to 12 nodes per axis (shape_functions.hpp).
constexpr size_t kMaxRowEntries = 12 * 12 * 12;

// Adds particle p's M_p S_pa c_b (a, b in its box) to the rows of the box's nodes in [r0, r1),
// c = columns(i) the row's column values (S_p for m̃; transfer_row for m̃_L). place(i, a0, a1,
// a2, stride) returns where p's box starts in row i (its node a) and sets the row's strides
// along y and z. Box sizes C0 × C1 × C2 are compile-time constants when nonzero. `off` is
// subtracted from the columns of S to give rows (a field's block folded onto the grid).
template <int C0, int C1, int C2, class Place, class Columns>
inline void scatter_box(const std::array<int, 3>& count, const double* sb, const int* ib, double M,
                        Index off, Index r0, Index r1, Place&& place, Columns&& columns) {
  const int c0 = C0 ? C0 : count[0], c1 = C1 ? C1 : count[1], c2 = C2 ? C2 : count[2];
  int qa = 0;
  for (int a2 = 0; a2 < c2; ++a2)
    for (int a1 = 0; a1 < c1; ++a1)
      for (int a0 = 0; a0 < c0; ++a0, ++qa) {
        const Index i = ib[qa] - off;
        const double wa = M * sb[qa];
        if (i < r0 || i >= r1 || wa == 0)
          continue;
        int stride[2];
        double* r = place(i, a0, a1, a2, stride);
        const double* sq = columns(i);
        for (int b2 = 0; b2 < c2; ++b2)
          for (int b1 = 0; b1 < c1; ++b1) {
            double* rb = r + b2 * stride[1] + b1 * stride[0];
            for (int b0 = 0; b0 < c0; ++b0)
              rb[b0] += wa * *sq++;
          }
      }
}

// The scatter of m̃ = Σ_p M_p S_pᵀ S_p into its stencil pattern, one particle at a time, the
// rows [r0, r1) of one thread.
struct StencilScatter {
  const StencilProduct& product;
  const Operators& ops;
  const std::array<int, 3>& w; // stencil half-widths
  const int* ro;               // row offsets of m̃
  double* val;                 // values of m̃
  std::array<int, 3> full;     // full stencil widths 2w + 1
  std::array<int, 3> origin;   // first node of ops.grid in the whole grid

  // The common box sizes at compile time (kernels.hpp dispatch_box).
  template <class Place, class Columns>
  static void interior(const ShapeSupport& s, const double* sb, const int* ib, double M, Index off,
                       Index r0, Index r1, Place&& place, Columns&& columns) {
    auto kernel = [&]<int C0, int C1, int C2>() {
      scatter_box<C0, C1, C2>(s.count, sb, ib, M, off, r0, r1, place, columns);
    };
    detail::dispatch_box(s.count, kernel);
  }

  void particle(Index p, Index r0, Index r1) const {
    if (product.X)
      return scatter_particle(p, r0, r1, [&](const double* sb, int begin, int count) {
        return TransferRow(*this, p, sb, begin, count);
      });
    scatter_particle(p, r0, r1,
                     [](const double* sb, int, int) { return [sb](Index) { return sb; }; });
  }

  // The column values of an affine transfer's row i for particle p: S_pj + (x_i − X_p) · g_pj
  // over p's box (the P2G of L_p = Σ_j v_j ⊗ g_pj; see assemble_affine_mass).
  struct TransferRow {
    TransferRow(const StencilScatter& s_, Index p_, const double* sb_, int begin_, int count_)
        : s(s_), p(p_), sb(sb_), begin(begin_), count(count_) {}
    const StencilScatter& s;
    Index p;
    const double* sb;
    int begin, count;
    mutable std::array<double, kMaxRowEntries> c; // written before it is read
    const double* operator()(Index i) const {
      const Operators& ops = s.ops;
      const int d = ops.grid.dim();
      const Eigen::Vector3d xi = ops.grid.node_position(i % ops.grid_node_count);
      double dx[3] = {0, 0, 0};
      for (int b = 0; b < d; ++b)
        dx[b] = xi[b] - (*s.product.X)(p, b);
      for (int k = 0; k < count; ++k) {
        double v = sb[k];
        for (int b = 0; b < d; ++b)
          v += dx[b] * s.product.gradient[size_t(b)][begin + k];
        c[size_t(k)] = v;
      }
      return c.data();
    }
  };

  template <class MakeColumns>
  void scatter_particle(Index p, Index r0, Index r1, MakeColumns&& make_columns) const {
    const int* outer = ops.S.outerIndexPtr();
    const int begin = outer[p], end = outer[p + 1];
    const int* ib = ops.S.innerIndexPtr() + begin;
    if (begin == end)
      return;
    Index off = 0;
    if (r0 > 0 || r1 < product.rows()) {
      // Several ranges: the row's first and last column (ColumnIndex::span; not S's column
      // indices, which then stay in the cache of the thread that writes them, kernels.hpp
      // scatter_to_nodes). Folded: the columns of p's field block minus the block's first
      // column are rows.
      const int lo = ops.columns.span[size_t(2 * p)], hi = ops.columns.span[size_t(2 * p + 1)];
      off = product.fold ? lo - product.row(lo) : 0;
      if (lo - off >= r1 || hi - off < r0)
        return; // no row of p's box is in this range (columns ascend along a row of S)
    } else if (product.fold) {
      off = ib[0] - product.row(ib[0]);
    }
    const ShapeSupport& s = ops.support[size_t(p)];
    const double *sb = ops.S.valuePtr() + begin, M = product.weight[p];
    const auto columns = make_columns(sb, begin, end - begin);
    const auto& nodes = ops.grid_nodes;
    // The box's first node in the numbering of ops.grid (a window starts at `origin`).
    const int first[3] = {s.first[0] - origin[0], s.first[1] - origin[1], s.first[2] - origin[2]};
    bool inside = true;
    for (size_t d = 0; d < 3; ++d)
      inside = inside && first[d] >= w[d] && first[d] + s.count[d] - 1 + w[d] < nodes[d];
    if (inside) { // row a's full stencil starts w before node a: the box sits at w − a
      interior(
          s, sb, ib, M, off, r0, r1,
          [&](Index i, int a0, int a1, int a2, int stride[2]) {
            stride[0] = full[0];
            stride[1] = full[0] * full[1];
            return val + ro[i] + ((w[2] - a2) * full[1] + (w[1] - a1)) * full[0] + (w[0] - a0);
          },
          columns);
      return;
    }
    // Near the grid's edges: each row's stencil is clipped to the grid.
    scatter_box<0, 0, 0>(
        s.count, sb, ib, M, off, r0, r1,
        [&](Index i, int a0, int a1, int a2, int stride[2]) {
          const int ijk[3] = {first[0] + a0, first[1] + a1, first[2] + a2};
          int lo[3], c[3];
          for (int d = 0; d < 3; ++d)
            stencil(ijk[d], w[size_t(d)], nodes[size_t(d)], lo[d], c[d]);
          stride[0] = c[0];
          stride[1] = c[0] * c[1];
          return val + ro[i] + ((first[2] - lo[2]) * c[1] + (first[1] - lo[1])) * c[0] +
                 (first[0] - lo[0]);
        },
        columns);
  }
};

// Values: m̃_ij = Σ_p M_p S_pi S_pj (FMPM 2026 §2.1), scattered from the particles in particle
// order. Each thread owns a range of rows and takes from every particle the rows of its box in
// that range, so every entry sums its particles in ascending order whatever the number of
// threads (the same bits as a serial loop). The particles are read in order (S, M and the boxes
// stream from memory); the rows they write are those of neighbouring nodes. A box whose nodes
// all have unclipped stencils (away from the grid's edges) lies at a fixed offset in each row,
// and the common box sizes have compile-time loops.
void gather_stencil_product(const StencilProduct& product, ConsistentMass& mt) {
  const Operators& ops = product.ops;
  SMPM_VERIFY(ops.columns.span.size() == size_t(2 * ops.S.rows()),
              "assemble_consistent_mass: the row spans of S are not those of its pattern");
  const auto& w = mt.half_width;
  SparseRowMatrix& A = mt.matrix;
  const StencilScatter scatter{
      product,
      ops,
      w,
      A.outerIndexPtr(),
      A.valuePtr(),
      {2 * w[0] + 1, 2 * w[1] + 1, 2 * w[2] + 1},
      {ops.grid.first_node(0), ops.grid.first_node(1), ops.grid.first_node(2)}};
  const Index n = product.rows(), N = ops.S.rows();
  detail::parallel_ranges(n, N, nullptr, [&](Index r0, Index r1) {
    std::fill(scatter.val + scatter.ro[r0], scatter.val + scatter.ro[r1], 0.0);
    for (Index p = 0; p < N; ++p)
      scatter.particle(p, r0, r1);
  });
}

void assemble_stencil_product(const StencilProduct& product, ConsistentMass& mt) {
  mt.pattern_reused = keep_stencil_pattern(product, mt);
  if (!mt.pattern_reused)
    build_stencil_pattern(product, mt);
  gather_stencil_product(product, mt);
}
} // namespace

void assemble_consistent_mass(const Operators& ops, ConsistentMass& mt) {
  assemble_stencil_product({ops, ops.M.data(), false}, mt);
}

void assemble_affine_mass(const Operators& ops, const ConstFieldRef& X,
                          const std::array<const double*, 3>& gradient, ConsistentMass& mt) {
  SMPM_VERIFY(X.rows() == ops.num_particles() && X.cols() == ops.grid.dim(),
              "assemble_affine_mass: one position (N x d) per particle");
  for (int b = 0; b < ops.grid.dim(); ++b)
    SMPM_VERIFY(gradient[size_t(b)] != nullptr, "assemble_affine_mass: a weight array per axis");
  StencilProduct product{ops, ops.M.data(), false};
  product.X = &X;
  product.gradient = gradient;
  assemble_stencil_product(product, mt);
}

void assemble_transfer_mass(const Operators& ops, const ConstFieldRef& X, ConsistentMass& mt) {
  std::array<const double*, 3> gradient{};
  for (int b = 0; b < ops.grid.dim(); ++b)
    gradient[size_t(b)] = ops.G[size_t(b)].valuePtr();
  assemble_affine_mass(ops, X, gradient, mt);
}

void assemble_consistent_capacity(const Operators& ops, const Eigen::VectorXd& capacity,
                                  ConsistentMass& ct) {
  SMPM_VERIFY(capacity.size() == ops.num_particles(),
              "assemble_consistent_capacity: one capacity per particle");
  assemble_stencil_product({ops, capacity.data(), ops.fields > 1}, ct);
}

} // namespace smpm
