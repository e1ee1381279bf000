// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/plasticity.hpp"

#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/LU>
#include <cmath>

namespace smpm {

namespace {
const Eigen::Matrix3d kI = Eigen::Matrix3d::Identity();
const double kSqrt23 = std::sqrt(2.0 / 3.0);

Eigen::Matrix3d dev(const Eigen::Matrix3d& a) {
  return a - (a.trace() / 3) * kI;
}
} // namespace

J2Return j2_return(const Material& mat, const Eigen::Matrix3d& f, const Eigen::Matrix3d& be_n,
                   double ep_n) {
  const double G = mat.shear_modulus(), H = mat.hardening;
  // Simo & Hughes Box 9.1, step 2: the elastic predictor on the isochoric part of f.
  const Eigen::Matrix3d fbar = std::cbrt(1 / f.determinant()) * f;
  const Eigen::Matrix3d be_tr = fbar * be_n * fbar.transpose();
  const Eigen::Matrix3d s_tr = G * dev(be_tr);
  const double norm = s_tr.norm(); // ‖s‖ = √(s : s) (Frobenius)
  const double f_tr = norm - kSqrt23 * (mat.yield_stress + H * ep_n);
  J2Return r{s_tr, be_tr, ep_n, 0.0, f_tr};
  if (f_tr <= 0)
    return r;
  // Step 4: the radial return with Ḡ = G Ī_e, Ī_e = tr(b̄ᵉ_tr)/3 (linear hardening: Δγ exact).
  const double Ie = be_tr.trace() / 3, Gbar = G * Ie;
  const double dgamma = f_tr / (2 * Gbar + (2.0 / 3.0) * H);
  const Eigen::Matrix3d n = s_tr / norm;
  r.s = s_tr - 2 * Gbar * dgamma * n;
  r.plastic_strain = ep_n + kSqrt23 * dgamma;
  // Step 5: b̄ᵉ = s/G + Ī_e I, with Ī_e corrected so that det b̄ᵉ = 1 (Simo & Hughes §9.3: the
  // return keeps tr b̄ᵉ_tr, so det b̄ᵉ drifts from 1 and (G/2)(tr b̄ᵉ − 3) would store part of the
  // plastic work). With A = s/G (tr A = 0), det(A + x I) = x³ − ½ tr(A²) x + det A = 1 is solved
  // by Newton's method from x = Ī_e (one or two iterations: the root is within O(Δγ²) of it).
  const Eigen::Matrix3d A = r.s / G;
  const double a2 = 0.5 * (A * A).trace(), a3 = A.determinant();
  double x = Ie;
  for (int it = 0; it < 20; ++it) {
    const double g = x * x * x - a2 * x + a3 - 1, dg = 3 * x * x - a2;
    const double step = g / dg;
    x -= step;
    if (std::abs(step) <= 1e-15 * x)
      break;
  }
  r.be = A + x * kI;
  r.work = r.s.norm() * dgamma;
  r.yield = r.s.norm() - kSqrt23 * (mat.yield_stress + H * r.plastic_strain);
  return r;
}

bool uses_plasticity(const std::vector<Material>& materials) {
  for (const Material& m : materials)
    if (m.plastic())
      return true;
  return false;
}

double plastic_strain_energy_density(const Material& mat, const double* be, double J) {
  double W = 0.5 * mat.shear_modulus() * (be[0] + be[4] + be[8] - 3);
  if (mat.model == MaterialModel::Hyperelastic)
    W += 0.5 * mat.bulk_modulus() * (0.5 * (J * J - 1) - std::log(J));
  return W;
}

Field elastic_state_of(const ConstFieldRef& F, int dim) {
  Field B(F.rows(), 9);
  for (Index p = 0; p < F.rows(); ++p) {
    const Eigen::Matrix3d F3 = embed_3d(F.data() + p * F.outerStride(), dim);
    const double J = F3.determinant();
    const Eigen::Matrix3d b = std::cbrt(1 / (J * J)) * F3 * F3.transpose();
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        B(p, 3 * a + c) = b(a, c);
  }
  return B;
}

Eigen::Matrix3d elastic_state_stress(const Material& mat, const Eigen::Matrix3d& F,
                                     const Eigen::Matrix3d& be) {
  const double J = F.determinant();
  const double vol = mat.model == MaterialModel::MieGruneisen
                         ? -mie_gruneisen_pressure(mat, J, 0)
                         : 0.5 * mat.bulk_modulus() * (J * J - 1) / J;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  return (mat.shear_modulus() / J) * (be - (be.trace() / 3) * I) + vol * I;
}

void initial_plastic_state(Particles& P) {
  const Index N = P.size();
  if (P.elastic_cauchy_green.rows() == N && P.elastic_cauchy_green.cols() == 9 &&
      P.plastic_strain.size() == N)
    return;
  P.elastic_cauchy_green = elastic_state_of(P.F, P.dim);
  P.plastic_strain.setZero(N);
}

double update_plastic_stress(const std::vector<Material>& materials,
                             const Eigen::Ref<const Eigen::VectorXi>& material,
                             const ConstFieldRef& F,
                             const Eigen::Ref<const Eigen::VectorXd>& volume0,
                             const Eigen::VectorXd* pressure, PlasticState& state, FieldRef stress,
                             Eigen::VectorXd* density) {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  Field& B = *state.elastic_cauchy_green;
  Eigen::VectorXd& ep = *state.plastic_strain;
  SMPM_VERIFY(B.rows() == F.rows() && B.cols() == 9 && ep.size() == F.rows() &&
                  state.F_old.rows() == F.rows() && state.F_old.cols() == d2,
              "update_plastic_stress: b̄ᵉ must be N x 9, ε̄ᵖ and F_old of N rows");
  state.work.setZero(F.rows());
  return detail::ordered_sum(F.rows(), [&](Index p) {
    const Material& mat = materials[size_t(material[p])];
    if (!mat.plastic())
      return 0.0;
    const Eigen::Matrix3d F1 = embed_3d(F.data() + p * F.outerStride(), d);
    const Eigen::Matrix3d F0 = embed_3d(state.F_old.data() + p * state.F_old.outerStride(), d);
    Eigen::Matrix3d be_n;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        be_n(a, c) = B(p, 3 * a + c);
    const J2Return r = j2_return(mat, F1 * F0.inverse(), be_n, ep[p]);
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        B(p, 3 * a + c) = r.be(a, c);
    ep[p] = r.plastic_strain;
    // σ = s/J + the volumetric term of the elastic law.
    const double J = F1.determinant();
    const double vol = mat.model == MaterialModel::MieGruneisen
                           ? -(pressure ? (*pressure)[p] : mie_gruneisen_pressure(mat, J, 0))
                           : 0.5 * mat.bulk_modulus() * (J * J - 1) / J;
    double* sigma = stress.data() + p * stress.outerStride();
    for (int a = 0; a < d; ++a)
      for (int c = 0; c < d; ++c)
        sigma[a * d + c] = r.s(a, c) / J + (a == c ? vol : 0.0);
    if (density)
      (*density)[p] = plastic_strain_energy_density(mat, B.row(p).data(), J);
    state.work[p] = volume0[p] * r.work;
    return state.work[p];
  });
}

void plastic_shock_pressure(const std::vector<Material>& materials,
                            const Eigen::Ref<const Eigen::VectorXi>& material,
                            const ConstFieldRef& F, const ConstFieldRef& stress,
                            const Field& elastic_cauchy_green,
                            Eigen::Ref<Eigen::VectorXd> pressure) {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = materials[size_t(material[p])];
    if (!mat.plastic() || mat.model != MaterialModel::MieGruneisen)
      return;
    const double J = embed_3d(F.data() + p * F.outerStride(), d).determinant();
    const double* be = elastic_cauchy_green.data() + p * elastic_cauchy_green.outerStride();
    const double G = mat.shear_modulus(), mean = (be[0] + be[4] + be[8]) / 3;
    double sum = 0;
    for (int a = 0; a < d; ++a)
      sum += stress(p, a * d + a) - G * (be[4 * a] - mean) / J;
    pressure[p] = -sum / d;
  });
}

} // namespace smpm
