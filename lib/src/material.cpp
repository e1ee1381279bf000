// SPDX-License-Identifier: BSD-3-Clause
// The materials and their laws at one deformation gradient: the models' names, the checks of
// their parameters, σ(F) and W(F), and thermoelasticity. Over the particles: particle_stress.cpp;
// shock physics: mie_gruneisen.cpp.
#include "sparsempm/material.hpp"

#include "enum_names.hpp"
#include "material_laws.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace smpm {

using detail::corotational_stress;
using detail::isochoric_shear;
using detail::linear_stress_energy;

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

namespace detail {

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

} // namespace detail

namespace {
// The energy of the shear term (isochoric_shear): W = (G/2)(tr B̄ − 3).
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

} // namespace smpm
