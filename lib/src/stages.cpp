#include "sparsempm/stages.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/products.hpp"

#include <cmath>
#include <sstream>

namespace smpm {

void map_momentum(const Operators& ops, const Particles& P, Field& p, StageWorkspace& w) {
  w.particle.noalias() = ops.M.asDiagonal() * P.V;
  multiply_transpose(ops.S, w.particle, p);
}

void internal_force(const Operators& ops, const Particles& P, Field& f, StageWorkspace& w) {
  P.jacobian(w.volume);
  w.volume.array() *= -P.volume0.array(); // −Ω J: −V_p^(0) det F_p
  w.tensor.noalias() = w.volume.asDiagonal() * P.stress;
  divergence_product(ops.G, P.dim, w.tensor, f); // f_ia = Σ_p Σ_b G_b(p,i) (−V_p σ_p,ab)
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
                           Particles& P, StageWorkspace& w) {
  const Index d = g.a.cols();
  w.node2.resize(g.a.rows(), 2 * d);
  w.node2.leftCols(d) = g.v_plus;
  w.node2.rightCols(d) = g.a;
  multiply(ops.S, w.node2, w.particle2); // [S v⁺  S a]
  P.X.noalias() += dt * w.particle2.leftCols(d);
  if (alpha != 1)
    P.X.noalias() -= ((1 - alpha) * dt * dt) * w.particle2.rightCols(d);
  P.V.noalias() += dt * w.particle2.rightCols(d);
}

void update_particles_pic(const Operators& ops, const Field& v_plus, double dt, double alpha,
                          Particles& P, StageWorkspace& w) {
  multiply(ops.S, v_plus, w.particle); // V' = S v⁺
  P.X.noalias() += (alpha * dt) * w.particle + ((1 - alpha) * dt) * P.V;
  P.V.swap(w.particle);
}

void velocity_gradient(const Operators& ops, const Field& v, Field& L) {
  gradient_product(ops.G, ops.dim, v, L); // (G_b v)_{pa} = ∂v_a/∂x_b at particle p
}

namespace {
template <int D>
void update_F(const Field& L, double dt, Field& F) {
  using Mat = Eigen::Matrix<double, D, D, Eigen::RowMajor>;
  for (Index p = 0; p < F.rows(); ++p) {
    Eigen::Map<Mat> Fp(F.row(p).data());
    const Mat Fn = (Mat::Identity() + dt * Eigen::Map<const Mat>(L.row(p).data())) * Fp;
    Fp = Fn;
  }
}
} // namespace

void update_deformation_gradient(const Field& L, double dt, Particles& P) {
  switch (P.dim) {
  case 1:
    P.F.col(0).array() *= 1 + dt * L.col(0).array();
    break;
  case 2:
    update_F<2>(L, dt, P.F);
    break;
  default:
    update_F<3>(L, dt, P.F);
    break;
  }
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
