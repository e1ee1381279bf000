// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/material.hpp"

#include "enum_names.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/plasticity.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace smpm {

namespace {
constexpr detail::EnumNames<MaterialModel, 6> kModels{
    {{MaterialModel::Linear, "linear"},
     {MaterialModel::LinearCorotational, "linear-corotational"},
     {MaterialModel::NeoHookean, "neo-hookean"},
     {MaterialModel::Hyperelastic, "hyperelastic"},
     {MaterialModel::MieGruneisen, "mie-gruneisen"},
     {MaterialModel::Rigid, "rigid"}}};
} // namespace

std::string_view to_string(MaterialModel m) {
  return detail::enum_name(m, kModels);
}
MaterialModel material_model_from_string(std::string_view name) {
  return detail::parse_enum(name, kModels, "material model");
}

double Material::wave_speed(int dim) const {
  if (model == MaterialModel::Rigid) // no elastic waves: its nodes' velocity is prescribed
    return 0;
  if ((model == MaterialModel::Linear || model == MaterialModel::LinearCorotational) && dim == 1)
    return std::sqrt(youngs / density);
  return std::sqrt((lame_lambda() + 2 * shear_modulus()) / density);
}

void validate(const Material& mat) {
  const std::string who = "material '" + mat.name + "': ";
  if (!(mat.density > 0) || !std::isfinite(mat.density))
    throw InputError(who + "density must be positive, got " + std::to_string(mat.density));
  if (!(mat.yield_stress >= 0) || !std::isfinite(mat.yield_stress))
    throw InputError(who + "yield_stress must be non-negative (0: elastic), got " +
                     number_text(mat.yield_stress));
  if (!(mat.hardening >= 0) || !std::isfinite(mat.hardening))
    throw InputError(who + "hardening must be non-negative, got " + number_text(mat.hardening));
  if (mat.plastic() && mat.model != MaterialModel::Hyperelastic &&
      mat.model != MaterialModel::MieGruneisen)
    throw InputError(who +
                     "yield_stress (J2 plasticity) is for the hyperelastic and "
                     "mie-gruneisen models, not " +
                     std::string(to_string(mat.model)));
  if (mat.plastic() && mat.thermal_expansion != 0)
    throw InputError(who + "yield_stress and thermal_expansion cannot be combined");
  if (mat.plastic() && mat.model == MaterialModel::MieGruneisen && !(mat.shear > 0))
    throw InputError(who + "yield_stress needs a positive shear modulus");
  if (mat.model == MaterialModel::MieGruneisen) {
    if (!(mat.bulk > 0) || !std::isfinite(mat.bulk))
      throw InputError(who + "bulk must be positive, got " + std::to_string(mat.bulk));
    const std::pair<const char*, double> nonnegative[] = {{"shear", mat.shear},
                                                          {"gruneisen", mat.gruneisen},
                                                          {"s1", mat.hugoniot_slope},
                                                          {"viscosity A1", mat.av_linear},
                                                          {"viscosity A2", mat.av_quadratic}};
    for (const auto& [key, value] : nonnegative)
      if (!(value >= 0) || !std::isfinite(value))
        throw InputError(who + key + " must be non-negative, got " + std::to_string(value));
    if (mat.thermal_expansion != 0)
      throw InputError(who + "thermal_expansion is not for mie-gruneisen (its thermal pressure "
                             "is gruneisen rho0 U)");
    return;
  }
  if (mat.model == MaterialModel::Rigid) {
    if (mat.thermal_expansion != 0)
      throw InputError(who + "thermal_expansion is not for a rigid material");
    return;
  }
  if (!std::isfinite(mat.thermal_expansion))
    throw InputError(who + "thermal_expansion must be finite, got " +
                     std::to_string(mat.thermal_expansion));
  if (!(mat.youngs > 0) || !std::isfinite(mat.youngs))
    throw InputError(who + "youngs must be positive, got " + std::to_string(mat.youngs));
  if (!(mat.poisson > -1 && mat.poisson < 0.5))
    throw InputError(who + "poisson must lie in (-1, 0.5), got " + std::to_string(mat.poisson));
}

namespace {
// Linear elasticity written out for dimension D (the common case, kept cheap on the hot path):
// σ = λ tr(ε) I + 2Gε with ε = sym(F) − I (D ≥ 2), σ = E (F − 1) in 1D.
template <int D>
void linear_stress(const Material& m, const double* F, double* sigma) {
  if constexpr (D == 1) {
    sigma[0] = m.youngs * (F[0] - 1);
  } else {
    const double lam = m.lame_lambda(), G2 = 2 * m.shear_modulus();
    double tr = 0;
    for (int a = 0; a < D; ++a)
      tr += F[a * D + a] - 1;
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) {
        const double eps = 0.5 * (F[a * D + b] + F[b * D + a]) - (a == b ? 1.0 : 0.0);
        sigma[a * D + b] = G2 * eps + (a == b ? lam * tr : 0.0);
      }
  }
}

// W = ½ σ : ε of linear elasticity from F and its σ (linear_stress), dimension D.
template <int D>
double linear_energy(const Material& m, const double* F, const double* sigma) {
  if constexpr (D == 1) {
    return 0.5 * m.youngs * (F[0] - 1) * (F[0] - 1);
  } else {
    double W = 0;
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b)
        W += sigma[a * D + b] * (0.5 * (F[a * D + b] + F[b * D + a]) - (a == b ? 1.0 : 0.0));
    return 0.5 * W;
  }
}

// σ and W of linear elasticity in dimension d (1, 2 or 3); W only with `energy`.
void linear_stress_energy(const Material& m, int d, const double* F, double* sigma,
                          double* energy) {
  auto run = [&]<int D>() {
    linear_stress<D>(m, F, sigma);
    if (energy)
      *energy = linear_energy<D>(m, F, sigma);
  };
  if (d == 1)
    run.template operator()<1>();
  else if (d == 2)
    run.template operator()<2>();
  else
    run.template operator()<3>();
}

// The shear term of the hyperelastic and Mie–Grüneisen laws (contact 2020 Eqs. 18, 51):
// σ_shear = (G/J) dev(B̄), B̄ = J^{−2/3} F Fᵀ, and its energy W = (G/2)(tr B̄ − 3).
// The corotational law (MaterialModel::LinearCorotational) in 3D (2D: plane strain, F₃₃ = 1):
// F = R U with U = (FᵀF)^½ from the eigen decomposition of FᵀF, the Biot strain ε = U − I and
// T = λ tr(ε) I + 2Gε; returns σ = R (T U) Rᵀ / J and sets W = ½ T : ε.
Eigen::Matrix3d corotational_stress(const Material& m, const Eigen::Matrix3d& F, double& W) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(F.transpose() * F);
  const Eigen::Vector3d stretch = eig.eigenvalues().cwiseSqrt();
  const Eigen::Matrix3d& Q = eig.eigenvectors();
  const Eigen::Matrix3d U = Q * stretch.asDiagonal() * Q.transpose();
  const Eigen::Matrix3d R = F * (Q * stretch.cwiseInverse().asDiagonal() * Q.transpose());
  const Eigen::Matrix3d eps = U - Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d T =
      m.lame_lambda() * eps.trace() * Eigen::Matrix3d::Identity() + 2 * m.shear_modulus() * eps;
  W = 0.5 * (T.array() * eps.array()).sum();
  return R * (T * U) * R.transpose() / F.determinant();
}

Eigen::Matrix3d isochoric_shear(double G, const Eigen::Matrix3d& F, double J) {
  const Eigen::Matrix3d Bbar = std::pow(J, -2.0 / 3.0) * F * F.transpose();
  return (G / J) * (Bbar - (Bbar.trace() / 3.0) * Eigen::Matrix3d::Identity());
}
double isochoric_shear_energy(double G, const Eigen::Matrix3d& F, double J) {
  const double I1 = (F.transpose() * F).trace();
  return 0.5 * G * (I1 * std::pow(J, -2.0 / 3.0) - 3);
}

} // namespace

Eigen::Matrix3d cauchy_stress(const Material& mat, int dim, const Eigen::Matrix3d& F) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double G = mat.shear_modulus();
  switch (mat.model) {
  case MaterialModel::Linear: { // linear_stress; in 2D plane strain, the 3D law at F₃₃ = 1
    const int d = dim == 1 ? 1 : 3;
    double Fd[9], sigma[9];
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        Fd[a * d + b] = F(a, b);
    linear_stress_energy(mat, d, Fd, sigma, nullptr);
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        s(a, b) = sigma[a * d + b];
    return s;
  }
  case MaterialModel::LinearCorotational: {
    if (dim == 1) { // uniaxial stress, as Linear: no rotation in 1D
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      s(0, 0) = mat.youngs * (F(0, 0) - 1);
      return s;
    }
    double W;
    return corotational_stress(mat, F, W);
  }
  case MaterialModel::NeoHookean: { // FMPM 2026 Eq. (14)
    const double J = F.determinant();
    return 0.5 * mat.lame_lambda() * (J - 1 / J) * I + (G / J) * (F * F.transpose() - I);
  }
  case MaterialModel::Hyperelastic: { // contact 2020 Eq. (18): σ = (G/J) dev(B̄) + (K/2J)(J² − 1) I
    const double J = F.determinant();
    return isochoric_shear(G, F, J) + (0.5 * mat.bulk_modulus() * (J * J - 1) / J) * I;
  }
  case MaterialModel::MieGruneisen: { // U = 0, q = 0: the cold curve with the shear term
    const double J = F.determinant();
    return isochoric_shear(G, F, J) - mie_gruneisen_pressure(mat, J, 0) * I;
  }
  case MaterialModel::Rigid:
    return Eigen::Matrix3d::Zero();
  }
  return Eigen::Matrix3d::Zero();
}

double strain_energy_density(const Material& mat, int dim, const Eigen::Matrix3d& F) {
  const double G = mat.shear_modulus();
  switch (mat.model) {
  case MaterialModel::Linear: { // as update_stress computes it: the same bits
    double Fd[9], sigma[9], W = 0;
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b)
        Fd[a * dim + b] = F(a, b);
    linear_stress_energy(mat, dim, Fd, sigma, &W);
    return W;
  }
  case MaterialModel::LinearCorotational: {
    if (dim == 1)
      return 0.5 * mat.youngs * (F(0, 0) - 1) * (F(0, 0) - 1);
    double W;
    (void)corotational_stress(mat, F, W);
    return W;
  }
  case MaterialModel::NeoHookean: {
    // W = (G/2)(I₁ − 3 − 2 ln J) + (λ/4)(J² − 1 − 2 ln J) gives Eq. (14) through τ = (∂W/∂F) Fᵀ.
    const double J = F.determinant(), I1 = (F.transpose() * F).trace();
    return 0.5 * G * (I1 - 3 - 2 * std::log(J)) +
           0.25 * mat.lame_lambda() * (J * J - 1 - 2 * std::log(J));
  }
  case MaterialModel::Hyperelastic: {
    const double J = F.determinant();
    return isochoric_shear_energy(G, F, J) +
           0.5 * mat.bulk_modulus() * (0.5 * (J * J - 1) - std::log(J));
  }
  case MaterialModel::MieGruneisen: // the shear term only: the rest is the energy U
    return isochoric_shear_energy(G, F, F.determinant());
  case MaterialModel::Rigid:
    return 0;
  }
  return 0;
}

double mie_gruneisen_pressure(const Material& mat, double J, double U) {
  const double eta = 1 - J;
  if (eta <= 0)
    return mat.bulk * eta;
  const double den = 1 - mat.hugoniot_slope * eta;
  if (!(den > 0))
    throw NumericalError("material '" + mat.name + "': compression 1 - J = " + std::to_string(eta) +
                         " beyond the Mie-Gruneisen limit 1/S1");
  return mat.bulk * eta * (1 - 0.5 * mat.gruneisen * eta) / (den * den) +
         mat.density * mat.gruneisen * U;
}

double mie_gruneisen_tangent(const Material& mat, double J, double U) {
  const double eta = 1 - J;
  if (eta <= 0)
    return J * mat.bulk;
  const double g = mat.gruneisen, s = mat.hugoniot_slope, den = 1 - s * eta;
  // d/dη [η (1 − γ₀η/2) / (1 − S₁η)²] = ((1 − γ₀η)(1 − S₁η) + 2S₁η(1 − γ₀η/2)) / (1 − S₁η)³
  const double dp =
      mat.bulk * ((1 - g * eta) * den + 2 * s * eta * (1 - 0.5 * g * eta)) / (den * den * den);
  return J * (dp + g * mie_gruneisen_pressure(mat, J, U));
}

double artificial_viscosity(const Material& mat, double rho, double C, double dx, double Dkk) {
  if (!(Dkk < 0))
    return 0;
  const double d = std::abs(Dkk);
  return rho * dx * d * (mat.av_linear * C + mat.av_quadratic * dx * d);
}

Eigen::Matrix3d thermoelastic_stress(const Material& mat, int dim, const Eigen::Matrix3d& F,
                                     double T, double& W, double& c) {
  const double alpha = mat.thermal_expansion, dT = T - mat.reference_temperature;
  if (alpha == 0 || mat.model == MaterialModel::MieGruneisen) {
    W = strain_energy_density(mat, dim, F);
    c = 0;
    return cauchy_stress(mat, dim, F);
  }
  if (mat.model == MaterialModel::Linear ||
      (mat.model == MaterialModel::LinearCorotational && dim == 1)) { // ε_e = ε − αΔT I
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    if (dim == 1) { // the bar in uniaxial stress
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      const double strain = F(0, 0) - 1 - alpha * dT;
      s(0, 0) = mat.youngs * strain;
      W = 0.5 * s(0, 0) * strain;
      c = alpha * s(0, 0);
      return s;
    }
    const Eigen::Matrix3d eps = 0.5 * (F + F.transpose()) - I - alpha * dT * I; // F₃₃ = 1
    const Eigen::Matrix3d s = mat.lame_lambda() * eps.trace() * I + 2 * mat.shear_modulus() * eps;
    W = 0.5 * (s.array() * eps.array()).sum();
    c = alpha * s.trace();
    return s;
  }
  const double theta = std::exp(alpha * dT), JT = theta * theta * theta; // F_T = θ I
  const Eigen::Matrix3d Fe = F / theta;
  const Eigen::Matrix3d s = cauchy_stress(mat, dim, Fe);
  const double We = strain_energy_density(mat, dim, Fe);
  W = JT * We;
  c = alpha * JT * (Fe.determinant() * s.trace() - 3 * We);
  return s;
}

double thermal_coupling(const Material& mat, int dim, const Eigen::Matrix3d& F, double T) {
  if (mat.model == MaterialModel::MieGruneisen)
    return mat.density * mat.heat_capacity * mat.gruneisen * (F.determinant() - 1);
  if (mat.thermal_expansion == 0)
    return 0;
  double W, c;
  (void)thermoelastic_stress(mat, dim, F, T, W, c);
  return c;
}

Eigen::Matrix3d embed_3d(const double* F, int d) {
  Eigen::Matrix3d F3 = Eigen::Matrix3d::Identity();
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b)
      F3(a, b) = F[a * d + b];
  return F3;
}

namespace {
Eigen::Matrix3d particle_F(const Particles& P, Index p) {
  return embed_3d(P.F.row(p).data(), P.dim);
}
const Material& material_of(const std::vector<Material>& mats, int id, Index p) {
  if (id < 0 || id >= int(mats.size()))
    throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                     " but only " + std::to_string(mats.size()) + " materials are defined");
  return mats[size_t(id)];
}
// Throws NumericalError naming particle p when its compression is beyond the Mie–Grüneisen
// law's limit 1 − J < 1/S₁ (the law's pressure diverges there).
void check_compression(const Material& mat, double J, Index p) {
  if (!(mat.hugoniot_slope * (1 - J) < 1))
    throw NumericalError("particle " + std::to_string(p) + " (material '" + mat.name +
                         "'): compression 1 - J = " + std::to_string(1 - J) +
                         " beyond the Mie-Gruneisen limit 1/S1");
}
} // namespace

void update_stress(const std::vector<Material>& materials,
                   const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                   FieldRef stress, Eigen::VectorXd* density, const Eigen::VectorXd* temperature) {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  SMPM_VERIFY(d * d == d2 && stress.cols() == d2 && stress.rows() == F.rows() &&
                  material.size() == F.rows(),
              "update_stress: F and stress must be N x d^2 and material of size N");
  if (density)
    density->resize(F.rows());
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = material_of(materials, material[p], p);
    const double* Fp = F.data() + p * F.outerStride();
    double* sigma = stress.data() + p * stress.outerStride();
    if (temperature && mat.thermal_expansion != 0) { // thermoelastic (heat transport)
      double W, c;
      const Eigen::Matrix3d s =
          thermoelastic_stress(mat, d, embed_3d(Fp, d), (*temperature)[p], W, c);
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b)
          sigma[a * d + b] = s(a, b);
      if (density)
        (*density)[p] = W;
      return;
    }
    if (mat.model == MaterialModel::Linear) {
      linear_stress_energy(mat, d, Fp, sigma, density ? density->data() + p : nullptr);
      return;
    }
    const Eigen::Matrix3d F3 = embed_3d(Fp, d);
    if (mat.model == MaterialModel::LinearCorotational && d > 1) { // one polar decomposition
      double W;
      const Eigen::Matrix3d s = corotational_stress(mat, F3, W);
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b)
          sigma[a * d + b] = s(a, b);
      if (density)
        (*density)[p] = W;
      return;
    }
    if (mat.model == MaterialModel::MieGruneisen)
      check_compression(mat, F3.determinant(), p);
    const Eigen::Matrix3d s = cauchy_stress(mat, d, F3);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        sigma[a * d + b] = s(a, b);
    if (density)
      (*density)[p] = strain_energy_density(mat, d, F3);
  });
}

namespace {
// Ω_p W(F_p), plus M_p U_p for a Mie–Grüneisen particle; W(F_p) from `density` when given.
double particle_strain_energy(const std::vector<Material>& materials, const Particles& P, Index p,
                              const Eigen::VectorXd* density) {
  const Material& mat = material_of(materials, P.material[p], p);
  double w = 0;
  if (density) {
    w = (*density)[p];
  } else if (mat.plastic() && P.elastic_cauchy_green.rows() == P.size()) {
    w = plastic_strain_energy_density(mat, P.elastic_cauchy_green.row(p).data(), P.det_F(p));
  } else if (mat.thermal_expansion != 0 && P.temperature.size() == P.size()) {
    double c; // Ψ_e(F, T) of the thermoelastic law, as the stress update stores it
    (void)thermoelastic_stress(mat, P.dim, particle_F(P, p), P.temperature[p], w, c);
  } else {
    w = strain_energy_density(mat, P.dim, particle_F(P, p));
  }
  double W = P.volume0[p] * w;
  if (mat.model == MaterialModel::MieGruneisen)
    W += P.mass[p] * P.energy[p];
  return W;
}
} // namespace

double strain_energy(const std::vector<Material>& materials, const Particles& P,
                     const Eigen::VectorXd* density) {
  SMPM_VERIFY(!density || density->size() == P.size(),
              "strain_energy: one strain energy density per particle");
  if (density && !uses_shock_physics(materials)) // Σ_p V_p^(0) W(F_p): the stress update
    return detail::ordered_sum(                  // checked the material ids
        P.size(), [&](Index p) { return P.volume0[p] * (*density)[p]; });
  return detail::ordered_sum(
      P.size(), [&](Index p) { return particle_strain_energy(materials, P, p, density); });
}

bool uses_shock_physics(const std::vector<Material>& materials) {
  for (const Material& m : materials)
    if (m.model == MaterialModel::MieGruneisen)
      return true;
  return false;
}

namespace {
// The shear term of a Mie–Grüneisen particle (none for a fluid, G = 0).
Eigen::Matrix3d shear_term(const Material& mat, const Eigen::Matrix3d& F, double J) {
  return mat.shear == 0 ? Eigen::Matrix3d::Zero() : isochoric_shear(mat.shear, F, J);
}
} // namespace

void shock_pressure(const std::vector<Material>& materials,
                    const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                    const ConstFieldRef& stress, Eigen::Ref<Eigen::VectorXd> pressure) {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = material_of(materials, material[p], p);
    pressure[p] = 0;
    if (mat.model != MaterialModel::MieGruneisen)
      return;
    const Eigen::Matrix3d F3 = embed_3d(F.data() + p * F.outerStride(), d);
    const Eigen::Matrix3d s = shear_term(mat, F3, F3.determinant());
    double sum = 0;
    for (int a = 0; a < d; ++a)
      sum += stress(p, a * d + a) - s(a, a);
    pressure[p] = -sum / d;
  });
}

double update_shock_stress(const std::vector<Material>& materials,
                           const Eigen::Ref<const Eigen::VectorXi>& material,
                           const ConstFieldRef& F, const Eigen::Ref<const Eigen::VectorXd>& volume0,
                           const Eigen::Ref<const Eigen::VectorXd>& J_old,
                           const Eigen::Ref<const Eigen::VectorXd>& p_old, double dt, double dx,
                           Eigen::Ref<Eigen::VectorXd> energy, Eigen::Ref<Eigen::VectorXd> pressure,
                           FieldRef stress, Eigen::VectorXd* work) {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  if (work)
    work->setZero(F.rows());
  // The viscous work −Σ_p q ΔJ Ω_p, summed in the fixed order of ordered_sum.
  return detail::ordered_sum(F.rows(), [&](Index p) {
    const Material& mat = material_of(materials, material[p], p);
    if (mat.model != MaterialModel::MieGruneisen)
      return 0.0;
    const Eigen::Matrix3d F3 = embed_3d(F.data() + p * F.outerStride(), d);
    const double J = F3.determinant();
    check_compression(mat, J, p);
    const double rho = mat.density / J;
    const double C = std::sqrt(std::max(0.0, mie_gruneisen_tangent(mat, J, energy[p])) / rho);
    const double q = artificial_viscosity(mat, rho, C, dx, (1 - J_old[p] / J) / dt);
    // The work of pressure and viscosity per unit mass, dU = −p̄ ΔJ/ρ₀ with p̄ the mean of the
    // pressures before and after (trapezoidal). p = p_c(J) + ρ₀γ₀U is linear in U, so the
    // implicit rule is solved exactly:  U (1 + γ₀ΔJ/2) = U_old − (p_old + p_c + q) ΔJ/(2ρ₀).
    const double dJ = J - J_old[p];
    const double pc = mie_gruneisen_pressure(mat, J, 0);
    const double g = J < 1 ? mat.gruneisen : 0.0; // the energy term acts in compression only
    energy[p] = (energy[p] - 0.5 * (p_old[p] + pc + q) * dJ / mat.density) / (1 + 0.5 * g * dJ);
    const double P = pc + mat.density * g * energy[p];
    pressure[p] = P + q;
    const Eigen::Matrix3d s = shear_term(mat, F3, J);
    double* sigma = stress.data() + p * stress.outerStride();
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        sigma[a * d + b] = s(a, b) - (a == b ? P + q : 0.0);
    if (work)
      (*work)[p] = -q * dJ * volume0[p];
    return -q * dJ * volume0[p];
  });
}

double max_wave_speed(const std::vector<Material>& materials, const Particles& P) {
  double c = 0;
  std::vector<char> used(materials.size(), 0);
  for (Index p = 0; p < P.size(); ++p) {
    (void)material_of(materials, P.material[p], p); // validates the id
    used[size_t(P.material[p])] = 1;
  }
  for (size_t i = 0; i < materials.size(); ++i)
    if (used[i])
      c = std::max(c, materials[i].wave_speed(P.dim));
  if (!uses_shock_physics(materials))
    return c;
  double shock = 0; // the largest Mie–Grüneisen speed, blocks in a fixed order
  detail::ordered_reduce(
      P.size(), 1, 0.0, &shock,
      [&](Index p, double* acc) {
        const Material& mat = materials[size_t(P.material[p])];
        if (mat.model != MaterialModel::MieGruneisen)
          return;
        const double J = P.det_F(p), rho = mat.density / J;
        check_compression(mat, J, p);
        const double Kt = std::max(0.0, mie_gruneisen_tangent(mat, J, P.energy[p]));
        acc[0] = std::max(acc[0], std::sqrt((Kt + 4 * mat.shear / 3) / rho));
      },
      [](double a, double b) { return std::max(a, b); });
  return std::max(c, shock);
}

} // namespace smpm
