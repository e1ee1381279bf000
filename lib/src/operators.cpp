// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/operators.hpp"

#include "enum_names.hpp"
#include "kernels.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <string>

namespace smpm {

namespace {
constexpr detail::EnumNames<NodeRange, 2> kNodeRanges{
    {{NodeRange::Particles, "particles"}, {NodeRange::Grid, "grid"}}};
} // namespace

std::string_view to_string(NodeRange r) {
  return detail::enum_name(r, kNodeRanges);
}
NodeRange node_range_from_string(std::string_view name) {
  return detail::parse_enum(name, kNodeRanges, "node range");
}

namespace {

// The chunks of consecutive particles of the column index's counting sort, one per thread:
// chunk t holds the rows [begin(t), begin(t + 1)) and counts into its n entries of the work.
struct Chunks {
  Index N, n, count;
  Index begin(Index t) const { return t * N / count; }
  int* counts(ColumnIndex& c, Index t) const { return c.work.data() + t * n; }
};

// Each chunk counts its entries of each node, and stores the span of each of its rows.
void count_entries(const SparseRowMatrix& S, const Chunks& chunks, ColumnIndex& c) {
  const int* outer = S.outerIndexPtr();
  const int* inner = S.innerIndexPtr();
  detail::parallel_for(
      chunks.count,
      [&](Index t) {
        int* ct = chunks.counts(c, t);
        std::fill(ct, ct + chunks.n, 0); // zeroed by the thread that counts into it
        int* span = c.span.data();
        for (Index p = chunks.begin(t); p < chunks.begin(t + 1); ++p) {
          const int b = outer[p], e = outer[p + 1];
          // A row's nodes ascend. Stored only when changed: every thread of a node sum reads
          // every span, and a store to a line another core holds must first take it back.
          const int lo = b < e ? inner[b] : std::numeric_limits<int>::max(),
                    hi = b < e ? inner[e - 1] : -1;
          if (span[2 * p] != lo)
            span[2 * p] = lo;
          if (span[2 * p + 1] != hi)
            span[2 * p + 1] = hi;
          for (int k = b; k < e; ++k)
            ++ct[inner[k]];
        }
      },
      chunks.N);
}

// Column offsets, an exclusive prefix sum over the nodes in parallel blocks (parallel.hpp);
// each chunk's count becomes its start.
void column_offsets(const Chunks& chunks, ColumnIndex& c) {
  const Index n = chunks.n;
  c.outer.resize(size_t(n + 1));
  std::vector<Index> starts;
  detail::prefix_block_starts(n, starts, [&](Index i) {
    Index k = 0;
    for (Index t = 0; t < chunks.count; ++t)
      k += chunks.counts(c, t)[i];
    return k;
  });
  detail::for_prefix_blocks(n, starts, [&](Index begin, Index end, Index start) {
    int sum = int(start);
    for (Index i = begin; i < end; ++i) {
      c.outer[size_t(i)] = sum;
      for (Index t = 0; t < chunks.count; ++t) {
        const int k = chunks.counts(c, t)[i];
        chunks.counts(c, t)[i] = sum;
        sum += k;
      }
    }
  });
  c.outer[size_t(n)] = int(starts.back());
}

// The entry and the particle of each position of the columns: each chunk walks its particles in
// ascending order from its starts.
void fill_columns(const SparseRowMatrix& S, const Chunks& chunks, ColumnIndex& c) {
  const int* outer = S.outerIndexPtr();
  const int* inner = S.innerIndexPtr();
  c.entry.resize(size_t(S.nonZeros()));
  c.row.resize(size_t(S.nonZeros()));
  detail::parallel_for(
      chunks.count,
      [&](Index t) {
        int* next = chunks.counts(c, t);
        for (Index p = chunks.begin(t); p < chunks.begin(t + 1); ++p)
          for (int k = outer[p]; k < outer[p + 1]; ++k) {
            const int at = next[inner[k]]++;
            c.entry[size_t(at)] = k;
            c.row[size_t(at)] = int(p);
          }
      },
      chunks.N);
}

} // namespace

void build_column_index(const SparseRowMatrix& S, ColumnIndex& c, bool lists) {
  const Index N = S.rows(), n = S.cols();
  // A counting sort by node over chunks of consecutive particles, one chunk per thread: chunk t
  // counts its entries of each node, writes after those of the chunks before it, and walks its
  // particles in ascending order. Each column lists its particles in ascending order whatever
  // the chunks, so the index does not depend on the number of threads.
  const Chunks chunks{N, n, std::max<Index>(1, std::min<Index>(threads(), N))};
  c.work.resize(size_t(chunks.count * n));
  c.span.resize(size_t(2 * N));
  count_entries(S, chunks, c);
  column_offsets(chunks, c);
  c.nonzeros = S.nonZeros();
  c.lists = lists;
  if (!lists) {
    c.entry.clear();
    c.row.clear();
    return;
  }
  fill_columns(S, chunks, c);
}

namespace {

// m = Sᵀ M (FMPM 2026 §2.1), each node's sum in particle order (kernels.hpp), and the active nodes:
// m_i > kMassTolerance max m. Multimaterial: the tolerance of single material mode (relative to
// the largest total nodal mass Σ_α m^α_i), so that a field alone on a node is active exactly
// when the node is in single material mode and bonded contact reverts to it.
void lumped_mass_and_active(Operators& ops) {
  const Index n = ops.num_nodes();
  ops.m.resize(n);
  const double* sv = ops.S.valuePtr();
  double* m = ops.m.data();
  const int* inner = ops.S.innerIndexPtr();
  detail::scatter_to_nodes(
      ops.S.outerIndexPtr(), inner, ops.columns.span.data(), ops.S.rows(), n,
      ops.columns.outer.data(), [&](Index r0, Index r1) { std::fill(m + r0, m + r1, 0.0); },
      [&](Index q, int k0, int k1) {
        const double Mq = ops.M[q];
        for (int k = k0; k < k1; ++k)
          m[inner[k]] += sv[k] * Mq;
      });
  // The largest mass (a maximum: the same for any order of the nodes), then the active nodes
  // and m⁻¹, each in node ranges, vectorised.
  const Index ng = ops.fields == 1 ? n : ops.grid_node_count;
  double largest = 0;
  detail::ordered_reduce_blocks(
      ng, 1, 0.0, &largest,
      [&](Index begin, Index end, double* acc) {
        acc[0] = std::max(acc[0], largest_total_mass(ops.m, ops.fields, ng, begin, end));
      },
      [](double a, double b) { return std::max(a, b); });
  ops.active.resize(n);
  ops.m_inv.resize(n);
  detail::parallel_segments(n, [&](Index i0, Index count) {
    active_nodes_of(ops.m, largest, i0, i0 + count, ops.active, ops.m_inv);
  });
}

} // namespace

double largest_total_mass(const Eigen::Ref<const Eigen::VectorXd>& m, int fields, Index ng,
                          Index begin, Index end) {
  if (fields == 1)
    return end > begin ? m.segment(begin, end - begin).maxCoeff() : 0.0;
  double largest = 0;
  for (Index i = begin; i < end; ++i) {
    double total = 0;
    for (int f = 0; f < fields; ++f)
      total += m[f * ng + i];
    largest = std::max(largest, total);
  }
  return largest;
}

void active_nodes_of(const Eigen::Ref<const Eigen::VectorXd>& m, double largest, Index begin,
                     Index end, Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                     Eigen::VectorXd& m_inv) {
  const auto mass = m.segment(begin, end - begin).array();
  auto on = active.segment(begin, end - begin);
  on = mass > kMassTolerance * largest;
  m_inv.segment(begin, end - begin) = on.select(mass.inverse(), 0.0).matrix();
}

void assemble(const Grid& grid, const Particles& particles, Shape shape, Operators& ops, int fields,
              const Eigen::VectorXi* field) {
  SMPM_VERIFY(fields >= 1 && (fields == 1 || (field && field->size() == particles.size())),
              "assemble: " + std::to_string(fields) + " fields need one field per particle");
  SMPM_VERIFY(double(fields) * double(grid.num_nodes()) < double(std::numeric_limits<int>::max()),
              "assemble: " + std::to_string(fields) + " fields of " +
                  std::to_string(grid.num_nodes()) + " nodes exceed 32-bit node indices");
  const bool window = ops.node_range == NodeRange::Particles;
  // The pattern of S is kept or updated only on the same grid with the same particle fields
  // (a particle window of the same grid numbers the nodes as the last call did; the whole grid
  // is one such window).
  if (!ops.grid.same_whole_grid(grid) || (ops.grid.is_window() && !window) ||
      ops.fields != fields ||
      (fields > 1 && (ops.field.size() != field->size() || ops.field != *field))) {
    ops.support.clear();
    ops.grid = grid; // the whole grid until a window is chosen
    if (fields > 1)
      ops.field = *field;
  }
  ops.dim = grid.dim();
  ops.fields = fields;
  static std::atomic<long> versions{0}; // unique across all Operators objects
  if (assemble_shape(grid, particles, shape, ops.S, ops.G, ops.support, fields,
                     fields > 1 ? field->data() : nullptr, window ? &ops.grid : nullptr) ||
      ops.columns.nonzeros != ops.S.nonZeros() || ops.columns.lists != (fields > 1)) {
    ops.pattern_version = ++versions;
    build_column_index(ops.S, ops.columns, fields > 1);
  }
  ops.grid_node_count = ops.grid.num_nodes();
  ops.grid_nodes = {ops.grid.nodes(0), ops.grid.nodes(1), ops.grid.nodes(2)};
  ops.M.resize(particles.mass.size());
  detail::parallel_segments(ops.M.size(), [&](Index p0, Index count) {
    ops.M.segment(p0, count) = particles.mass.segment(p0, count);
  });
  lumped_mass_and_active(ops);
}

Operators assemble(const Grid& grid, const Particles& particles, Shape shape) {
  Operators ops;
  assemble(grid, particles, shape, ops);
  return ops;
}

Eigen::VectorXi active_nodes(const Operators& ops) {
  Eigen::VectorXi idx(ops.active.count());
  for (Index i = 0, k = 0; i < ops.active.size(); ++i)
    if (ops.active[i])
      idx[k++] = int(i);
  return idx;
}

SparseMatrix consistent_mass(const Operators& ops) {
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  SparseMatrix out(mt.matrix);
  out.prune(0.0);
  return out;
}

SparseMatrix S_plus(const Operators& ops) {
  SparseMatrix Sp = ops.m_inv.asDiagonal() * SparseMatrix(ops.S.transpose() * ops.M.asDiagonal());
  Sp.prune(0.0);
  return Sp;
}

SparseMatrix expansion_matrix(const Operators& ops) {
  SparseMatrix A = -(ops.m_inv.asDiagonal() * consistent_mass(ops));
  A.prune([&](Index i, Index j, double) { return ops.active[i] && ops.active[j]; });
  const Index n = ops.num_nodes();
  SparseMatrix I(n, n);
  I.reserve(Eigen::VectorXi::Constant(n, 1));
  for (Index i = 0; i < n; ++i)
    if (ops.active[i])
      I.insert(i, i) = 1.0;
  A += I;
  return A;
}

} // namespace smpm
