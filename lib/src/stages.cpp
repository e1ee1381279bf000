#include "sparsempm/stages.hpp"

#include "kernels.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/products.hpp"

#include <cmath>
#include <sstream>

namespace smpm {

namespace {

using detail::by_dim;
using detail::Csr;
using detail::det;

[[noreturn]] void bad_particle(Index p, const char* what, double value) {
  std::ostringstream os;
  os << "particle " << p << " has " << what << " (" << value << ")";
  throw NumericalError(os.str());
}

} // namespace

void map_momentum(const Operators& ops, const Particles& P, Field& p, StageWorkspace&) {
  // p = Sᵀ (M ∘ V): one pass over the rows of S.
  const Csr S(ops.S);
  p.setZero(ops.num_nodes(), P.dim);
  by_dim(P.dim, [&]<int D>() {
    for (Index q = 0; q < P.size(); ++q) {
      double mv[D];
      for (int a = 0; a < D; ++a)
        mv[a] = ops.M[q] * P.V(q, a);
      for (int k = S.outer[q]; k < S.outer[q + 1]; ++k) {
        double* pi = p.data() + Index(S.inner[k]) * D;
        for (int a = 0; a < D; ++a)
          pi[a] += S.val[k] * mv[a];
      }
    }
  });
}

void internal_force(const Operators& ops, const Particles& P, Field& f, StageWorkspace&) {
  // f_ia = −Σ_p Σ_b G_b(p, i) V_p^(0) J_p σ_p,ab: one pass over the rows of the G_b.
  const Csr G0(ops.G[0]);
  const double* g[3] = {ops.G[0].valuePtr(), P.dim > 1 ? ops.G[1].valuePtr() : nullptr,
                        P.dim > 2 ? ops.G[2].valuePtr() : nullptr};
  f.setZero(ops.num_nodes(), P.dim);
  by_dim(P.dim, [&]<int D>() {
    for (Index q = 0; q < P.size(); ++q) {
      const double vol = -P.volume0[q] * det<D>(P.F.data() + q * D * D); // −Ω J
      double tau[D * D];
      for (int c = 0; c < D * D; ++c)
        tau[c] = vol * P.stress.data()[q * D * D + c];
      for (int k = G0.outer[q]; k < G0.outer[q + 1]; ++k) {
        double* fi = f.data() + Index(G0.inner[k]) * D;
        for (int a = 0; a < D; ++a) {
          double sum = 0;
          for (int b = 0; b < D; ++b)
            sum += tau[a * D + b] * g[b][k];
          fi[a] += sum;
        }
      }
    }
  });
}

void add_body_force(const Operators& ops, const std::array<double, 3>& B, Field& f) {
  for (int a = 0; a < f.cols(); ++a)
    if (B[a] != 0)
      f.col(a) += B[a] * ops.m;
}

void lumped_solve(const Operators& ops, const Field& x, Field& v) {
  v.noalias() = ops.m_inv.asDiagonal() * x;
}

void update_particles_flip(const Operators& ops, const GridState& g, double dt, double alpha,
                           Particles& P, StageWorkspace&) {
  // One pass over S: (S v⁺)_p and (S a)_p, then V += Δt S a, X += Δt S v⁺ − (1 − α) Δt² S a.
  const Csr S(ops.S);
  by_dim(P.dim, [&]<int D>() {
    const double c = (1 - alpha) * dt * dt;
    for (Index q = 0; q < P.size(); ++q) {
      double sv[D] = {}, sa[D] = {};
      for (int k = S.outer[q]; k < S.outer[q + 1]; ++k) {
        const Index i = S.inner[k];
        for (int a = 0; a < D; ++a) {
          sv[a] += S.val[k] * g.v_plus.data()[i * D + a];
          sa[a] += S.val[k] * g.a.data()[i * D + a];
        }
      }
      for (int a = 0; a < D; ++a) {
        double& x = P.X.data()[q * D + a];
        double& v = P.V.data()[q * D + a];
        x += dt * sv[a] - c * sa[a];
        v += dt * sa[a];
        if (!std::isfinite(x) || !std::isfinite(v))
          bad_particle(q, "a non-finite position or velocity", v);
      }
    }
  });
}

void update_particles_pic(const Operators& ops, const Field& v_plus, double dt, double alpha,
                          Particles& P, StageWorkspace&) {
  // One pass over S: V' = (S v⁺)_p, X += (α V' + (1 − α) V) Δt, V = V'.
  const Csr S(ops.S);
  by_dim(P.dim, [&]<int D>() {
    for (Index q = 0; q < P.size(); ++q) {
      double sv[D] = {};
      for (int k = S.outer[q]; k < S.outer[q + 1]; ++k)
        for (int a = 0; a < D; ++a)
          sv[a] += S.val[k] * v_plus.data()[Index(S.inner[k]) * D + a];
      for (int a = 0; a < D; ++a) {
        double& x = P.X.data()[q * D + a];
        double& v = P.V.data()[q * D + a];
        x += (alpha * sv[a] + (1 - alpha) * v) * dt;
        v = sv[a];
        if (!std::isfinite(x) || !std::isfinite(v))
          bad_particle(q, "a non-finite position or velocity", v);
      }
    }
  });
}

void velocity_gradient(const Operators& ops, const Field& v, Field& L) {
  gradient_product(ops.G, ops.dim, v, L); // (G_b v)_{pa} = ∂v_a/∂x_b at particle p
}

void update_deformation_gradient(const Field& L, double dt, Particles& P) {
  by_dim(P.dim, [&]<int D>() {
    using Mat = Eigen::Matrix<double, D, D, Eigen::RowMajor>;
    for (Index q = 0; q < P.size(); ++q) {
      Eigen::Map<Mat> Fq(P.F.row(q).data());
      const Mat Fn = (Mat::Identity() + dt * Eigen::Map<const Mat>(L.row(q).data())) * Fq;
      Fq = Fn;
    }
  });
}

void update_deformation_from_velocity(const Operators& ops, const Field& v, double dt,
                                      Particles& P) {
  // One pass over the G_b: L_p = Σ_i v_i ⊗ G_pi, F_p ← (I + L_p Δt) F_p, det F_p > 0.
  const Csr G0(ops.G[0]);
  const double* g[3] = {ops.G[0].valuePtr(), P.dim > 1 ? ops.G[1].valuePtr() : nullptr,
                        P.dim > 2 ? ops.G[2].valuePtr() : nullptr};
  by_dim(P.dim, [&]<int D>() {
    for (Index q = 0; q < P.size(); ++q) {
      double L[D * D] = {};
      for (int k = G0.outer[q]; k < G0.outer[q + 1]; ++k) {
        const double* vi = v.data() + Index(G0.inner[k]) * D;
        for (int b = 0; b < D; ++b)
          for (int a = 0; a < D; ++a)
            L[a * D + b] += vi[a] * g[b][k];
      }
      double* F = P.F.data() + q * D * D;
      double Fn[D * D];
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          double sum = F[a * D + b];
          for (int c = 0; c < D; ++c)
            sum += dt * L[a * D + c] * F[c * D + b];
          Fn[a * D + b] = sum;
        }
      for (int c = 0; c < D * D; ++c)
        F[c] = Fn[c];
      const double J = det<D>(F);
      if (!(J > 0))
        bad_particle(q, "det F <= 0", J);
    }
  });
}

void check_particles(const Particles& P) {
  for (Index p = 0; p < P.size(); ++p) {
    const double J = P.det_F(p);
    const char* what = nullptr;
    if (!P.X.row(p).allFinite())
      what = "a non-finite position";
    else if (!P.V.row(p).allFinite())
      what = "a non-finite velocity";
    else if (!P.stress.row(p).allFinite())
      what = "a non-finite stress";
    else if (!(J > 0))
      what = "det F <= 0";
    if (what) {
      std::ostringstream os;
      os << "particle " << p << " has " << what << " (det F = " << J << ")";
      throw NumericalError(os.str());
    }
  }
}

} // namespace smpm
