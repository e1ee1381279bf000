// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/stages.hpp"

#include "kernels.hpp"
#include "parallel.hpp"
#include "particle_rows.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace smpm {

namespace detail {
[[noreturn]] void bad_particle(Index p, const char* what, double value) {
  std::ostringstream os;
  os << "particle " << p << " has " << what << " (" << value << ")";
  throw NumericalError(os.str());
}
} // namespace detail

namespace {

using detail::bad_particle;

using detail::by_dim;
using detail::check_node_field;
using detail::det;
using detail::Rows;

// out_i = Σ_q of particle q's terms on node i, in ascending particle order (the same bits for
// any number of threads): particle(q, k0, k1, o) adds the terms of q's entries [k0, k1) to the
// rows of the row-major n × D field `out` at o. A scatter by node ranges (kernels.hpp) that
// reads S and the G_b row by row.
template <int D, class Particle>
void node_sums(const ParticleOperators& op, Field& out, Particle&& particle) {
  out.resize(op.nodes, D);
  double* o = out.data();
  detail::scatter_to_nodes(
      op.outer, op.inner, op.span, op.rows, op.nodes, op.col_outer,
      [&](Index r0, Index r1) { std::fill(o + r0 * D, o + r1 * D, 0.0); },
      [&](Index q, int k0, int k1) { particle(q, k0, k1, o); });
}

} // namespace

ParticleOperators ParticleOperators::block(Index first, Index count) const {
  SMPM_VERIFY(first >= 0 && count >= 0 && first + count <= rows,
              "ParticleOperators::block: rows out of range");
  ParticleOperators b = *this;
  b.rows = count;
  b.first = this->first + first;
  b.outer = outer + first;
  b.span = span + 2 * first;
  b.M = M + first;
  return b;
}

ParticleOperators particle_operators(const Operators& ops) {
  ParticleOperators op;
  op.dim = ops.dim;
  op.rows = ops.num_particles();
  op.nodes = ops.num_nodes();
  op.outer = ops.S.outerIndexPtr();
  op.inner = ops.S.innerIndexPtr();
  op.S = ops.S.valuePtr();
  for (int b = 0; b < ops.dim; ++b) {
    SMPM_VERIFY(ops.G[size_t(b)].nonZeros() == ops.S.nonZeros(),
                "particle_operators: G_b must share the pattern of S");
    op.G[size_t(b)] = ops.G[size_t(b)].valuePtr();
  }
  op.M = ops.M.data();
  SMPM_VERIFY(ops.columns.nonzeros == ops.S.nonZeros() &&
                  ops.columns.outer.size() == size_t(op.nodes + 1) &&
                  ops.columns.span.size() == size_t(2 * op.rows),
              "particle_operators: the column index must match S (see assemble)");
  op.span = ops.columns.span.data();
  op.col_outer = ops.columns.outer.data();
  op.col_entry = ops.columns.lists ? ops.columns.entry.data() : nullptr;
  op.col_row = ops.columns.lists ? ops.columns.row.data() : nullptr;
  op.first = 0;
  return op;
}

void affine_offsets(const ParticleOperators& op, const Grid& grid, const ConstFieldRef& X,
                    AffineOffsets& offsets) {
  SMPM_VERIFY(X.rows() == op.rows && X.cols() == op.dim, "affine_offsets: X must be N x d");
  const Index ng = grid.num_nodes();
  SMPM_VERIFY(ng > 0 && op.nodes % ng == 0,
              "affine_offsets: the grid must be that of the operators' nodes");
  for (int b = 0; b < op.dim; ++b)
    offsets.delta[size_t(b)].resize(size_t(op.outer[op.rows])); // indexed as S (absolute)
  detail::parallel_for(op.rows, [&](Index q) {
    for (int k = op.outer[q]; k < op.outer[q + 1]; ++k) {
      const Eigen::Vector3d xi = grid.node_position(op.inner[k] % ng);
      for (int b = 0; b < op.dim; ++b)
        offsets.delta[size_t(b)][size_t(k)] = xi[b] - X(q, b); // Δ_pi,b = x_ib − X_pb
    }
  });
}

void map_momentum(const ParticleOperators& op, const ConstFieldRef& V, Field& p,
                  const AffineMomentum* affine) {
  SMPM_VERIFY(V.rows() == op.rows && V.cols() == op.dim, "map_momentum: V must be N x d");
  if (affine) {
    SMPM_VERIFY(affine->offsets && affine->L && affine->L->rows() == op.rows &&
                    affine->L->cols() == op.dim * op.dim,
                "map_momentum: the affine term needs its offsets and L (N x d^2)");
    for (int b = 0; b < op.dim; ++b)
      SMPM_VERIFY(affine->offsets->delta[size_t(b)].size() >= size_t(op.outer[op.rows]),
                  "map_momentum: the affine offsets must be those of the operators");
  }
  by_dim(op.dim, [&]<int D>() {
    if (!affine) {
      // p_i = Σ_q S_qi M_q V_q (FMPM 2026 task 1)
      const Rows<D> r(op);
      const double* M = op.M;
      const double* Vd = V.data();
      const Index vs = V.outerStride();
      node_sums<D>(op, p, [&](Index q, int k0, int k1, double* o) {
        double mv[D];
        for (int a = 0; a < D; ++a)
          mv[a] = M[q] * Vd[q * vs + a];
        for (int k = k0; k < k1; ++k) {
          double* pi = o + Index(r.inner[k]) * D;
          for (int a = 0; a < D; ++a)
            pi[a] += r.S[k] * mv[a];
        }
      });
      return;
    }
    // p_i = Σ_q S_qi M_q (V_q + L_q Δ_qi)
    const Field& L = *affine->L;
    const std::array<std::vector<double>, 3>& delta = affine->offsets->delta;
    node_sums<D>(op, p, [&](Index q, int k0, int k1, double* o) {
      for (int k = k0; k < k1; ++k) {
        double* pi = o + Index(op.inner[k]) * D;
        for (int a = 0; a < D; ++a) {
          double v = V(q, a);
          for (int b = 0; b < D; ++b)
            v += L(q, a * D + b) * delta[size_t(b)][size_t(k)];
          pi[a] += op.S[k] * (op.M[q] * v);
        }
      }
    });
  });
}

void volume_gradient(const ParticleOperators& op, const ConstVectorRef& volume, Field& g) {
  SMPM_VERIFY(volume.size() == op.rows, "volume_gradient: one volume per particle");
  by_dim(op.dim, [&]<int D>() {
    // g_i = Σ_q G_qi V_q (contact 2020 Eq. 11)
    node_sums<D>(op, g, [&](Index q, int k0, int k1, double* o) {
      const double vq = volume[q];
      for (int k = k0; k < k1; ++k) {
        double* gi = o + Index(op.inner[k]) * D;
        for (int b = 0; b < D; ++b)
          gi[b] += op.G[size_t(b)][k] * vq;
      }
    });
  });
}

void internal_force(const ParticleOperators& op, const ConstVectorRef& volume0,
                    const ConstFieldRef& F, const ConstFieldRef& stress, Field& f) {
  const int d2 = op.dim * op.dim;
  SMPM_VERIFY(volume0.size() == op.rows && F.rows() == op.rows && F.cols() == d2 &&
                  stress.rows() == op.rows && stress.cols() == d2,
              "internal_force: volume0, F and stress must have one row per particle");
  by_dim(op.dim, [&]<int D>() {
    const double *v0 = volume0.data(), *Fd = F.data(), *sd = stress.data();
    const Index fs = F.outerStride(), ss = stress.outerStride();
    const Rows<D> r(op);
    // f_i = Σ_q Σ_b τ_q,·b G_b(q, i) (Buzzi Eq. 15), τ_q = −Ω_q J_q σ_q computed as the particle's
    // row is met (a row shared by two threads' node ranges is computed by both, the same bits).
    node_sums<D>(op, f, [&](Index q, int k0, int k1, double* o) {
      const double* sq = sd + q * ss;
      const double vol = -v0[q] * det<D>(Fd + q * fs); // −Ω J
      double tq[D * D];
      for (int c = 0; c < D * D; ++c)
        tq[c] = vol * sq[c];
      for (int k = k0; k < k1; ++k) {
        double* fi = o + Index(r.inner[k]) * D;
        for (int a = 0; a < D; ++a) {
          double sum = 0;
          for (int b = 0; b < D; ++b)
            sum += tq[a * D + b] * r.G[b][k];
          fi[a] += sum;
        }
      }
    });
  });
}

void add_gravity(const Eigen::VectorXd& m, const std::array<double, 3>& B, Field& f) {
  for (int a = 0; a < f.cols(); ++a)
    if (B[size_t(a)] != 0)
      f.col(a) += B[size_t(a)] * m;
}

void add_external_forces(const ParticleOperators& op, const Grid& grid, const ExternalForces& loads,
                         Field& f) {
  check_node_field(op, f, "add_external_forces");
  if (loads.any_body_force) {
    const Field& forces = loads.particle;
    SMPM_VERIFY(forces.rows() == op.rows && forces.cols() == op.dim,
                "add_external_forces: the body forces must be N x d");
    by_dim(op.dim, [&]<int D>() { // f_i += Σ_q S_qi F_q, the sum first
      thread_local Field sums;    // kept between steps: a step allocates nothing
      node_sums<D>(op, sums, [&](Index q, int k0, int k1, double* o) {
        double fq[D];
        for (int a = 0; a < D; ++a)
          fq[a] = forces(q, a);
        for (int k = k0; k < k1; ++k)
          for (int a = 0; a < D; ++a)
            o[Index(op.inner[k]) * D + a] += op.S[k] * fq[a];
      });
      f += sums;
    });
  }
  // The tractions: few points, in their order (the same bits for any number of threads).
  const Index ng = grid.num_nodes();
  for (const PointForce& pf : loads.points) {
    const Index q = pf.particle - op.first;
    SMPM_VERIFY(q >= 0 && q < op.rows,
                "add_external_forces: a traction's particle is not in the operators' rows");
    const int begin = op.outer[q], end = op.outer[q + 1];
    auto hat = [&](int k) { // N_i(x_c), the grid's hat function of the entry's node
      const Eigen::Vector3d xi = grid.node_position(op.inner[k] % ng);
      double w = 1;
      for (int a = 0; a < op.dim; ++a)
        w *= std::max(0.0, 1 - std::abs(pf.x[a] - xi[a]) / grid.cell_size(a));
      return w;
    };
    double total = 0;
    for (int k = begin; k < end; ++k)
      total += hat(k);
    for (int k = begin; k < end; ++k) {
      const double w = total > 0 ? hat(k) / total : op.S[k];
      for (int a = 0; a < op.dim; ++a)
        f(op.inner[k], a) += w * pf.force[a];
    }
  }
}

void lumped_solve(const Eigen::VectorXd& m_inv, const Field& x, Field& v) {
  SMPM_VERIFY(x.rows() == m_inv.size(), "lumped_solve: x must have a row per node");
  // One multiply per entry, vectorised, in node ranges: on two threads each range mostly reads
  // the nodes its own thread summed (scatter_to_nodes), not lines held in the other core's cache.
  v.resize(x.rows(), x.cols());
  detail::parallel_segments(x.rows(), [&](Index r0, Index m) {
    v.middleRows(r0, m).noalias() = m_inv.segment(r0, m).asDiagonal() * x.middleRows(r0, m);
  });
}

} // namespace smpm
