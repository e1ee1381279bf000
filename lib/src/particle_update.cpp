// SPDX-License-Identifier: BSD-3-Clause
// The grid-to-particle updates of a step (FMPM 2026 task 4, Eqs. 8-9): positions and velocities
// from S (FLIP and PIC), the velocity gradient L = Σ_i v_i ⊗ G_qi and the deformation gradient
// from the G_b, each a gather over the particle's row, one range of particles per thread.

#include "kernels.hpp"
#include "parallel.hpp"
#include "particle_rows.hpp"

#include "sparsempm/stages.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>

namespace smpm {

namespace {

using detail::bad_particle;
using detail::by_dim;
using detail::check_node_field;
using detail::det;
using detail::Rows;

// Row q of a row-major field with any row stride.
template <class Ref>
auto* row(Ref& A, Index q) {
  return A.data() + q * A.outerStride();
}

// A node's or a particle's D components as one value: Eigen packs a 2-vector into one SSE2
// register, so that a 2D entry's two components take one multiply and one add (in the
// gathers over a particle's row; the node sums' scatter is as short with scalar stores). Each
// component is the same operation as on its own (no fused multiply-add on the baseline x86-64), so
// the bits are those of a loop over the components.
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using ConstVecMap = Eigen::Map<const Vec<D>>;

// L = Σ_i v_i ⊗ G_qi of particle q (row-major D × D): L[a D + b] = Σ_i G_b(q, i) v(i, a).
// Inlined into each per-particle loop that calls it (left to itself, GCC may call it per particle).
template <int D>
[[gnu::always_inline]] inline void particle_gradient(const Rows<D>& r, Index q, const double* v,
                                                     double* L) {
  Eigen::Matrix<double, D, D> Lc = Eigen::Matrix<double, D, D>::Zero(); // column b: Σ_i v_i G_b
  for (int k = r.outer[q]; k < r.outer[q + 1]; ++k) {
    const ConstVecMap<D> vi(v + Index(r.inner[k]) * D);
    for (int b = 0; b < D; ++b)
      Lc.col(b) += vi * r.G[b][k];
  }
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      L[a * D + b] = Lc(a, b);
}

// Whether the D values at x and at v are all finite, by one test: x − x is 0 for a finite x and
// NaN for an infinite or NaN one.
template <int D>
[[gnu::always_inline]] inline bool all_finite(const double* x, const double* v) {
  double probe = 0;
  for (int b = 0; b < D; ++b)
    probe += (x[b] - x[b]) + (v[b] - v[b]);
  return probe == 0;
}

// Throws for the first non-finite component of particle q's position or velocity.
template <int D>
[[noreturn, gnu::noinline]] void bad_motion(Index q, const double* x, const double* v) {
  for (int b = 0; b < D; ++b)
    if (!std::isfinite(x[b]) || !std::isfinite(v[b]))
      bad_particle(q, "a non-finite position or velocity", v[b]);
  bad_particle(q, "a non-finite position or velocity", v[0]);
}

} // namespace

void update_particles_flip(const ParticleOperators& op, const Field& v_plus, const Field& a,
                           double dt, double alpha, FieldRef X, FieldRef V) {
  check_node_field(op, v_plus, "update_particles_flip");
  check_node_field(op, a, "update_particles_flip");
  // One pass over S: (S v⁺)_p and (S a)_p, then V += Δt S a, X += Δt S v⁺ − (1 − α) Δt² S a.
  by_dim(op.dim, [&]<int D>() {
    const double c = (1 - alpha) * dt * dt;
    detail::parallel_segments(op.rows, [&](Index q0, Index count) {
      const Rows<D> r(op);
      const double *vp = v_plus.data(), *ag = a.data();
      double *Xd = X.data(), *Vd = V.data();
      const Index xs = X.outerStride(), vs = V.outerStride();
      const double h = dt, cc = c;
      for (Index q = q0; q < q0 + count; ++q) {
        Vec<D> sv = Vec<D>::Zero(), sa = Vec<D>::Zero();
        for (int k = r.outer[q]; k < r.outer[q + 1]; ++k) {
          const Index i = r.inner[k];
          sv += r.S[k] * ConstVecMap<D>(vp + i * D);
          sa += r.S[k] * ConstVecMap<D>(ag + i * D);
        }
        double* x = Xd + q * xs;
        double* v = Vd + q * vs;
        for (int b = 0; b < D; ++b) {
          x[b] += h * sv[b] - cc * sa[b];
          v[b] += h * sa[b];
        }
        if (!all_finite<D>(x, v)) [[unlikely]]
          bad_motion<D>(q, x, v);
      }
    });
  });
}

void update_particles_pic(const ParticleOperators& op, const Field& vg, double dt, double alpha,
                          FieldRef X, FieldRef V) {
  check_node_field(op, vg, "update_particles_pic");
  // One pass over S: V' = (S v)_p, X += (α V' + (1 − α) V) Δt, V = V'.
  by_dim(op.dim, [&]<int D>() {
    detail::parallel_segments(op.rows, [&](Index q0, Index count) {
      const Rows<D> r(op);
      const double* vd = vg.data();
      double *Xd = X.data(), *Vd = V.data();
      const Index xs = X.outerStride(), vs = V.outerStride();
      const double h = dt, al = alpha;
      for (Index q = q0; q < q0 + count; ++q) {
        Vec<D> sv = Vec<D>::Zero();
        for (int k = r.outer[q]; k < r.outer[q + 1]; ++k)
          sv += r.S[k] * ConstVecMap<D>(vd + Index(r.inner[k]) * D);
        double* x = Xd + q * xs;
        double* v = Vd + q * vs;
        for (int b = 0; b < D; ++b) {
          x[b] += (al * sv[b] + (1 - al) * v[b]) * h;
          v[b] = sv[b];
        }
        if (!all_finite<D>(x, v)) [[unlikely]]
          bad_motion<D>(q, x, v);
      }
    });
  });
}

void velocity_gradient(const ParticleOperators& op, const Field& v, FieldRef L) {
  check_node_field(op, v, "velocity_gradient");
  SMPM_VERIFY(L.rows() == op.rows && L.cols() == op.dim * op.dim,
              "velocity_gradient: L must be N x d^2");
  by_dim(op.dim, [&]<int D>() {
    detail::parallel_segments(op.rows, [&](Index q0, Index count) {
      const Rows<D> r(op);
      for (Index q = q0; q < q0 + count; ++q)
        particle_gradient<D>(r, q, v.data(), row(L, q));
    });
  });
}

namespace {
// F ← (I + L Δt) F (Linear) or exp(L Δt) F for every particle of the block.
template <int D, bool Exponential>
void deformation_rows(const ParticleOperators& op, const Field& v, double dt, FieldRef& F) {
  using Mat = Eigen::Matrix<double, D, D, Eigen::RowMajor>;
  detail::parallel_segments(op.rows, [&](Index q0, Index count) {
    const Rows<D> r(op);
    const double* vd = v.data();
    double* Fd = F.data();
    const Index fs = F.outerStride();
    const double h = dt;
    for (Index q = q0; q < q0 + count; ++q) {
      double L[D * D];
      particle_gradient<D>(r, q, vd, L);
      double* f = Fd + q * fs;
      double Fn[D * D];
      if constexpr (Exponential) {
        const Mat expL = (h * Eigen::Map<const Mat>(L)).exp();
        Eigen::Map<Mat> out(Fn);
        out.noalias() = expL * Eigen::Map<const Mat>(f);
      } else {
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) {
            double sum = f[a * D + b];
            for (int c = 0; c < D; ++c)
              sum += h * L[a * D + c] * f[c * D + b];
            Fn[a * D + b] = sum;
          }
      }
      for (int c = 0; c < D * D; ++c)
        f[c] = Fn[c];
      const double J = det<D>(f);
      if (!(J > 0)) [[unlikely]]
        bad_particle(q, "det F <= 0", J);
    }
  });
}
} // namespace

void update_deformation(const ParticleOperators& op, const Field& v, double dt,
                        DeformationUpdate kind, FieldRef F) {
  check_node_field(op, v, "update_deformation");
  SMPM_VERIFY(F.rows() == op.rows && F.cols() == op.dim * op.dim,
              "update_deformation: F must be N x d^2");
  by_dim(op.dim, [&]<int D>() {
    if (kind == DeformationUpdate::Linear)
      deformation_rows<D, false>(op, v, dt, F);
    else
      deformation_rows<D, true>(op, v, dt, F);
  });
}

} // namespace smpm
