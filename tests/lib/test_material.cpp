// Materials: closed forms of FMPM 2026 Eq. (14) and contact 2020 Eq. (18), hyperelastic
// consistency τ = (∂W/∂F) Fᵀ by central differences, and the small-strain limit.

#include "support.hpp"

#include <Eigen/Dense>
#include <random>

using namespace smpm;
using smpm::test::approx;

namespace {
Material make(MaterialModel model, double E = 3.0, double nu = 0.3) {
  Material m;
  m.name = "test";
  m.model = model;
  m.density = 2.0;
  m.youngs = E;
  m.poisson = nu;
  return m;
}

Eigen::Matrix3d embed(const Eigen::MatrixXd& Fd) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F.topLeftCorner(Fd.rows(), Fd.cols()) = Fd;
  return F;
}
} // namespace

TEST_CASE("neo-Hookean stress is FMPM 2026 Eq. (14) in uniaxial stretch", "[material]") {
  const Material m = make(MaterialModel::NeoHookean);
  const double lam = m.lame_lambda(), G = m.shear_modulus(), s = 1.3;
  const Eigen::Matrix3d sig = cauchy_stress(m, 3, Eigen::Vector3d(s, 1, 1).asDiagonal());
  // σ11 = λ/2 (J − 1/J) + G/J (s² − 1), σ22 = λ/2 (J − 1/J) with J = s.
  CHECK(sig(0, 0) == approx(0.5 * lam * (s - 1 / s) + G / s * (s * s - 1), 1e-14));
  CHECK(sig(1, 1) == approx(0.5 * lam * (s - 1 / s), 1e-14));
  CHECK(sig(0, 1) == approx(0.0, 1e-15));
}

TEST_CASE("linear elastic stress: uniaxial stress bar in 1D, plane strain in 2D", "[material]") {
  const Material m = make(MaterialModel::Linear);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 0) = 1.01;
  CHECK(cauchy_stress(m, 1, F)(0, 0) == approx(3.0 * 0.01, 1e-15)); // σ = E (F − 1)
  const Eigen::Matrix3d s2 = cauchy_stress(m, 2, F);
  CHECK(s2(0, 0) == approx((m.lame_lambda() + 2 * m.shear_modulus()) * 0.01, 1e-15));
  CHECK(s2(1, 1) == approx(m.lame_lambda() * 0.01, 1e-15));
  CHECK(m.wave_speed(1) == approx(std::sqrt(3.0 / 2.0), 1e-15));
}

TEST_CASE("large-strain models satisfy tau = (dW/dF) F^T", "[material]") {
  // Central differences with step 1e-6 have truncation error O(1e-12) and round-off
  // O(1e-10) on W ~ 1: tolerance 1e-7 relative to the stress scale E.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  for (auto model : {MaterialModel::NeoHookean, MaterialModel::Hyperelastic})
    for (int dim = 1; dim <= 3; ++dim) {
      CAPTURE(to_string(model), dim);
      const Material m = make(model);
      Eigen::MatrixXd Fd = Eigen::MatrixXd::Identity(dim, dim);
      for (int k = 0; k < dim * dim; ++k)
        Fd.data()[k] += u(rng);
      const Eigen::Matrix3d F = embed(Fd);
      const double eps = 1e-6;
      Eigen::Matrix3d P = Eigen::Matrix3d::Zero(); // ∂W/∂F on the in-plane block
      for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b) {
          Eigen::Matrix3d Fp = F, Fm = F;
          Fp(a, b) += eps;
          Fm(a, b) -= eps;
          P(a, b) =
              (strain_energy_density(m, dim, Fp) - strain_energy_density(m, dim, Fm)) / (2 * eps);
        }
      const Eigen::Matrix3d tau = F.determinant() * cauchy_stress(m, dim, F);
      const Eigen::Matrix3d PFt = P * F.transpose();
      for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
          CHECK(tau(a, b) == approx(PFt(a, b), 1e-7 * m.youngs));
    }
}

TEST_CASE("large-strain models reduce to linear elasticity at small strain", "[material]") {
  // σ(I + H) = C : sym(H) + O(|H|²): with |H| = 1e-6 the difference is ~1e-11 with E = 3 and |H_ij|
  // < 1: tolerance 1e-10.
  Eigen::Matrix3d H;
  H << 0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.7, 0.3, 0.1;
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + 1e-6 * H;
  const Eigen::Matrix3d lin = cauchy_stress(make(MaterialModel::Linear), 3, F);
  for (auto model : {MaterialModel::NeoHookean, MaterialModel::Hyperelastic}) {
    const Eigen::Matrix3d s = cauchy_stress(make(model), 3, F);
    CHECK((s - lin).cwiseAbs().maxCoeff() < 1e-10);
    CHECK(lin.cwiseAbs().maxCoeff() > 1e-6); // the comparison is not vacuous
  }
}

TEST_CASE("materials reject non-physical parameters", "[material]") {
  Material m = make(MaterialModel::Linear);
  m.density = 0;
  CHECK_THROWS_WITH(validate(m), Catch::Contains("density"));
  m = make(MaterialModel::Linear, -1.0);
  CHECK_THROWS_WITH(validate(m), Catch::Contains("youngs"));
  m = make(MaterialModel::Linear, 1.0, 0.5);
  CHECK_THROWS_WITH(validate(m), Catch::Contains("poisson"));
  CHECK_THROWS_WITH(material_model_from_string("mooney"), Catch::Contains("neo-hookean"));
}
