// SPDX-License-Identifier: BSD-3-Clause
// Shock physics (contact 2020 Eqs. 51–52): the Mie–Grüneisen pressure and its tangent, the
// artificial viscosity, and the strain update of the Mie–Grüneisen particles with their energy.

#include "sparsempm/material.hpp"

#include "material_laws.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace smpm {

using detail::check_compression;
using detail::isochoric_shear;
using detail::material_of;

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

namespace detail {
void check_compression(const Material& mat, double J, Index p) {
  if (!(mat.hugoniot_slope * (1 - J) < 1))
    throw NumericalError("particle " + std::to_string(p) + " (material '" + mat.name +
                         "'): compression 1 - J = " + std::to_string(1 - J) +
                         " beyond the Mie-Gruneisen limit 1/S1");
}
} // namespace detail

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
} // namespace smpm
