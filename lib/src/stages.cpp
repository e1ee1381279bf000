#include "sparsempm/stages.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <sstream>

namespace smpm {

void map_momentum(const Operators& ops, const Particles& P, Eigen::MatrixXd& p) {
  p.noalias() = ops.S.transpose() * (ops.M.asDiagonal() * P.V);
}

void internal_force(const Operators& ops, const Particles& P, Eigen::MatrixXd& f) {
  const int d = P.dim;
  const Eigen::VectorXd tau_volume = P.volume(); // Ω J: V_p^(0) det F_p
  f.setZero(ops.num_nodes(), d);
  for (int b = 0; b < d; ++b) // column a of stress.middleCols(b d, d) is σ_ba = σ_ab
    f.noalias() -= ops.G[b].transpose() * (tau_volume.asDiagonal() * P.stress.middleCols(b * d, d));
}

void add_body_force(const Operators& ops, const std::array<double, 3>& B, Eigen::MatrixXd& f) {
  for (int a = 0; a < f.cols(); ++a)
    if (B[a] != 0)
      f.col(a) += B[a] * ops.m;
}

void lumped_solve(const Operators& ops, const Eigen::MatrixXd& x, Eigen::MatrixXd& v) {
  v.noalias() = ops.m_inv.asDiagonal() * x;
}

void update_particles_flip(const Operators& ops, const GridState& g, double dt, double alpha,
                           Particles& P) {
  const Eigen::MatrixXd Sa = ops.S * g.a;
  P.X.noalias() += dt * (ops.S * g.v_plus);
  if (alpha != 1)
    P.X.noalias() -= ((1 - alpha) * dt * dt) * Sa;
  P.V.noalias() += dt * Sa;
}

void update_particles_pic(const Operators& ops, const Eigen::MatrixXd& v_plus, double dt,
                          double alpha, Particles& P) {
  const Eigen::MatrixXd V_new = ops.S * v_plus;
  P.X.noalias() += (alpha * dt) * V_new + ((1 - alpha) * dt) * P.V;
  P.V = V_new;
}

void velocity_gradient(const Operators& ops, const Eigen::MatrixXd& v, Eigen::MatrixXd& L) {
  const int d = ops.dim;
  L.resize(ops.num_particles(), d * d);
  Eigen::MatrixXd Gv(ops.num_particles(), d);
  for (int b = 0; b < d; ++b) {
    Gv.noalias() = ops.G[b] * v; // (G_b v)_{pa} = ∂v_a/∂x_b at particle p
    for (int a = 0; a < d; ++a)
      L.col(a * d + b) = Gv.col(a);
  }
}

namespace {
template <int D>
void update_F(const Eigen::MatrixXd& L, double dt, Eigen::MatrixXd& F) {
  using Mat = Eigen::Matrix<double, D, D, Eigen::RowMajor>;
  for (Index p = 0; p < F.rows(); ++p) {
    Mat Lp, Fp;
    for (int k = 0; k < D * D; ++k) {
      Lp.data()[k] = L(p, k);
      Fp.data()[k] = F(p, k);
    }
    const Mat Fn = (Mat::Identity() + dt * Lp) * Fp;
    for (int k = 0; k < D * D; ++k)
      F(p, k) = Fn.data()[k];
  }
}
} // namespace

void update_deformation_gradient(const Eigen::MatrixXd& L, double dt, Particles& P) {
  switch (P.dim) {
  case 1: P.F.col(0).array() *= 1 + dt * L.col(0).array(); break;
  case 2: update_F<2>(L, dt, P.F); break;
  default: update_F<3>(L, dt, P.F); break;
  }
}

void check_particles(const Particles& P) {
  const Eigen::VectorXd J = P.jacobian();
  for (Index p = 0; p < P.size(); ++p) {
    const char* what = nullptr;
    if (!P.X.row(p).allFinite())
      what = "a non-finite position";
    else if (!P.V.row(p).allFinite())
      what = "a non-finite velocity";
    else if (!P.stress.row(p).allFinite())
      what = "a non-finite stress";
    else if (!(J[p] > 0))
      what = "det F <= 0";
    if (what) {
      std::ostringstream os;
      os << "particle " << p << " has " << what << " (det F = " << J[p] << ")";
      throw NumericalError(os.str());
    }
  }
}

} // namespace smpm
