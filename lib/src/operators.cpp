#include "sparsempm/operators.hpp"

#include "enum_names.hpp"
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

void build_column_index(const SparseRowMatrix& S, ColumnIndex& c) {
  const Index N = S.rows(), n = S.cols(), nnz = S.nonZeros();
  const int* outer = S.outerIndexPtr();
  const int* inner = S.innerIndexPtr();
  // A counting sort by node over chunks of consecutive particles, one chunk per thread: chunk t
  // counts its entries of each node, writes after those of the chunks before it, and walks its
  // particles in ascending order. Each column lists its particles in ascending order whatever
  // the chunks, so the index does not depend on the number of threads.
  const Index chunks = std::max<Index>(1, std::min<Index>(threads(), N));
  auto chunk_begin = [&](Index t) { return t * N / chunks; };
  c.work.assign(size_t(chunks * n), 0);
  auto count = [&](Index t) { return c.work.data() + t * n; };
  detail::parallel_for(
      chunks,
      [&](Index t) {
        int* ct = count(t);
        for (int k = outer[chunk_begin(t)]; k < outer[chunk_begin(t + 1)]; ++k)
          ++ct[inner[k]];
      },
      N);
  c.outer.resize(size_t(n + 1));
  int sum = 0;
  for (Index i = 0; i < n; ++i) { // column offsets; each chunk's count becomes its start
    c.outer[size_t(i)] = sum;
    for (Index t = 0; t < chunks; ++t) {
      const int k = count(t)[i];
      count(t)[i] = sum;
      sum += k;
    }
  }
  c.outer[size_t(n)] = sum;
  c.entry.resize(size_t(nnz));
  c.row.resize(size_t(nnz));
  detail::parallel_for(
      chunks,
      [&](Index t) {
        int* next = count(t);
        for (Index p = chunk_begin(t); p < chunk_begin(t + 1); ++p)
          for (int k = outer[p]; k < outer[p + 1]; ++k) {
            const int at = next[inner[k]]++;
            c.entry[size_t(at)] = k;
            c.row[size_t(at)] = int(p);
          }
      },
      N);
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
      ops.columns.entry.size() != size_t(ops.S.nonZeros())) {
    ops.pattern_version = ++versions;
    build_column_index(ops.S, ops.columns);
  }
  ops.grid_node_count = ops.grid.num_nodes();
  ops.grid_nodes = {ops.grid.nodes(0), ops.grid.nodes(1), ops.grid.nodes(2)};
  ops.M = particles.mass;
  // m = Sᵀ M (FMPM 2026 §2.1), gathered node by node in particle order.
  const Index n = ops.num_nodes();
  ops.m.resize(n);
  const ColumnIndex& cols = ops.columns;
  const double* sv = ops.S.valuePtr();
  detail::parallel_for(n, [&](Index i) {
    double sum = 0;
    for (int t = cols.outer[size_t(i)]; t < cols.outer[size_t(i + 1)]; ++t)
      sum += sv[cols.entry[size_t(t)]] * ops.M[cols.row[size_t(t)]];
    ops.m[i] = sum;
  });
  if (fields == 1) {
    const double tol = kMassTolerance * (ops.m.size() ? ops.m.maxCoeff() : 0.0);
    ops.active = ops.m.array() > tol;
  } else {
    // Multimaterial: the tolerance of single material mode (relative to the largest total
    // nodal mass Σ_α m^α_i), so that a field alone on a node is active exactly when the node
    // is in single material mode and bonded contact reverts to it.
    const Index ng = ops.grid_node_count;
    double largest = 0;
    for (Index i = 0; i < ng; ++i) {
      double total = 0;
      for (int f = 0; f < fields; ++f)
        total += ops.m[f * ng + i];
      largest = std::max(largest, total);
    }
    ops.active = ops.m.array() > kMassTolerance * largest;
  }
  ops.m_inv = ops.active.select(ops.m.array().inverse(), 0.0).matrix();
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

namespace {
// First node and width of row i's stencil along an axis.
inline void stencil(int i, int w, int nodes, int& lo, int& count) {
  lo = std::max(0, i - w);
  count = std::min(nodes - 1, i + w) - lo + 1;
}
} // namespace

namespace {
// Whether m̃'s stencil pattern can be kept: the same operators with the same pattern of S, or
// the same stencil half-width, nodes per axis and touched nodes. Records the new width and touched
// set.
bool keep_stencil_pattern(const Operators& ops, ConsistentMass& mt) {
  const Index n = ops.num_nodes();
  if (mt.source == &ops && mt.source_version == ops.pattern_version && mt.matrix.rows() == n)
    return true;
  std::array<int, 3> w{0, 0, 0};
  for (const ShapeSupport& s : ops.support)
    for (int a = 0; a < 3; ++a)
      w[size_t(a)] = std::max(w[size_t(a)], s.count[size_t(a)] - 1);
  std::vector<char> touched(size_t(n), 0);
  const int* inner = ops.S.innerIndexPtr();
  for (Index k = 0; k < ops.S.nonZeros(); ++k)
    touched[size_t(inner[k])] = 1;
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

// The stencil pattern: row i of a touched node holds every node within the half-width.
void build_stencil_pattern(const Operators& ops, ConsistentMass& mt) {
  const Index n = ops.num_nodes(), ng = ops.grid_node_count;
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
  Index nnz = 0;
  for (Index i = 0; i < n; ++i)
    if (mt.touched[size_t(i)]) {
      int lo[3], c[3];
      box(i, lo, c);
      nnz += Index(c[0]) * c[1] * c[2];
    }
  SparseRowMatrix& A = mt.matrix;
  A.resize(n, n);
  A.resizeNonZeros(nnz);
  int* ro = A.outerIndexPtr();
  int* ri = A.innerIndexPtr();
  Index pos = 0;
  for (Index i = 0; i < n; ++i) {
    ro[i] = int(pos);
    if (!mt.touched[size_t(i)])
      continue;
    int lo[3], c[3];
    box(i, lo, c);
    const Index block = i - i % ng;
    for (int k2 = 0; k2 < c[2]; ++k2)
      for (int k1 = 0; k1 < c[1]; ++k1)
        for (int k0 = 0; k0 < c[0]; ++k0)
          ri[pos++] = int(block + (lo[0] + k0) +
                          Index(nodes[0]) * ((lo[1] + k1) + Index(nodes[1]) * (lo[2] + k2)));
  }
  ro[n] = int(pos);
}

// Adds particle p's M_p S_pa S_pb (a, b in its box) to the rows of the box's nodes in [r0, r1).
// place(i, a0, a1, a2, stride) returns where p's box starts in row i (its node a) and sets the
// row's strides along y and z. Box sizes C0 × C1 × C2 are compile-time constants when nonzero.
template <int C0, int C1, int C2, class Place>
inline void scatter_box(const std::array<int, 3>& count, const double* sb, const int* ib, double M,
                        Index r0, Index r1, Place&& place) {
  const int c0 = C0 ? C0 : count[0], c1 = C1 ? C1 : count[1], c2 = C2 ? C2 : count[2];
  int qa = 0;
  for (int a2 = 0; a2 < c2; ++a2)
    for (int a1 = 0; a1 < c1; ++a1)
      for (int a0 = 0; a0 < c0; ++a0, ++qa) {
        const Index i = ib[qa];
        const double wa = M * sb[qa];
        if (i < r0 || i >= r1 || wa == 0)
          continue;
        int stride[2];
        double* r = place(i, a0, a1, a2, stride);
        const double* sq = sb;
        for (int b2 = 0; b2 < c2; ++b2)
          for (int b1 = 0; b1 < c1; ++b1) {
            double* rb = r + b2 * stride[1] + b1 * stride[0];
            for (int b0 = 0; b0 < c0; ++b0)
              rb[b0] += wa * *sq++;
          }
      }
}

// Values: m̃_ij = Σ_p M_p S_pi S_pj (FMPM 2026 §2.1), scattered from the particles in particle
// order. Each thread owns a range of rows and takes from every particle the rows of its box in
// that range, so every entry sums its particles in ascending order whatever the number of
// threads (the same bits as a serial loop). The particles are read in order (S, M and the boxes
// stream from memory); the rows they write are those of neighbouring nodes. A box whose nodes
// all have unclipped stencils (away from the grid's edges) lies at a fixed offset in each row,
// and the common box sizes have compile-time loops.
void gather_consistent_mass(const Operators& ops, ConsistentMass& mt) {
  const auto& nodes = ops.grid_nodes;
  const auto& w = mt.half_width;
  const int* outer = ops.S.outerIndexPtr();
  const int* inner = ops.S.innerIndexPtr();
  SparseRowMatrix& A = mt.matrix;
  const int* ro = A.outerIndexPtr();
  double* val = A.valuePtr();
  const double* sv = ops.S.valuePtr();
  const Index n = ops.num_nodes(), N = ops.S.rows();
  const int full[3] = {2 * w[0] + 1, 2 * w[1] + 1, 2 * w[2] + 1};
  const int origin[3] = {ops.grid.first_node(0), ops.grid.first_node(1), ops.grid.first_node(2)};
  const Index parts = std::max<Index>(1, std::min<Index>(threads(), n));
  detail::parallel_for(
      parts,
      [&](Index t) {
        const Index r0 = t * n / parts, r1 = (t + 1) * n / parts;
        std::fill(val + ro[r0], val + ro[r1], 0.0);
        for (Index p = 0; p < N; ++p) {
          const int begin = outer[p], end = outer[p + 1];
          if (begin == end || inner[begin] >= r1 || inner[end - 1] < r0)
            continue; // no row of p's box is in this range (columns ascend along a row of S)
          const ShapeSupport& s = ops.support[size_t(p)];
          const double *sb = sv + begin, M = ops.M[p];
          const int* ib = inner + begin;
          // The box's first node in the numbering of ops.grid (a window starts at `origin`).
          const int first[3] = {s.first[0] - origin[0], s.first[1] - origin[1],
                                s.first[2] - origin[2]};
          bool interior = true;
          for (size_t d = 0; d < 3; ++d)
            interior = interior && first[d] >= w[d] && first[d] + s.count[d] - 1 + w[d] < nodes[d];
          if (!interior) { // near the grid's edges: each row's stencil is clipped to the grid
            scatter_box<0, 0, 0>(
                s.count, sb, ib, M, r0, r1, [&](Index i, int a0, int a1, int a2, int stride[2]) {
                  const int ijk[3] = {first[0] + a0, first[1] + a1, first[2] + a2};
                  int lo[3], c[3];
                  for (int d = 0; d < 3; ++d)
                    stencil(ijk[d], w[size_t(d)], nodes[size_t(d)], lo[d], c[d]);
                  stride[0] = c[0];
                  stride[1] = c[0] * c[1];
                  return val + ro[i] + ((first[2] - lo[2]) * c[1] + (first[1] - lo[1])) * c[0] +
                         (first[0] - lo[0]);
                });
            continue;
          }
          // Row a's full stencil starts w before node a: the box sits at w − a.
          auto place = [&](Index i, int a0, int a1, int a2, int stride[2]) {
            stride[0] = full[0];
            stride[1] = full[0] * full[1];
            return val + ro[i] + ((w[2] - a2) * full[1] + (w[1] - a1)) * full[0] + (w[0] - a0);
          };
          auto kernel = [&]<int C0, int C1, int C2>() {
            scatter_box<C0, C1, C2>(s.count, sb, ib, M, r0, r1, place);
          };
          // Box sizes up to kMaxBox = 12 per axis: one hexadecimal digit each.
          switch ((s.count[0] << 8) | (s.count[1] << 4) | s.count[2]) {
          case 0x221:
            kernel.template operator()<2, 2, 1>();
            break;
          case 0x331:
            kernel.template operator()<3, 3, 1>();
            break;
          case 0x231:
            kernel.template operator()<2, 3, 1>();
            break;
          case 0x321:
            kernel.template operator()<3, 2, 1>();
            break;
          case 0x222:
            kernel.template operator()<2, 2, 2>();
            break;
          case 0x333:
            kernel.template operator()<3, 3, 3>();
            break;
          default:
            kernel.template operator()<0, 0, 0>();
          }
        }
      },
      N);
}
} // namespace

void assemble_consistent_mass(const Operators& ops, ConsistentMass& mt) {
  mt.pattern_reused = keep_stencil_pattern(ops, mt);
  if (!mt.pattern_reused)
    build_stencil_pattern(ops, mt);
  gather_consistent_mass(ops, mt);
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
