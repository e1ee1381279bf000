// SPDX-License-Identifier: BSD-3-Clause
// The material laws over the particles: the stress update of every particle (update_stress),
// their strain energy and the largest wave speed they carry.

#include "sparsempm/material.hpp"

#include "material_laws.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/plasticity.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace smpm {

using detail::check_compression;
using detail::corotational_stress;
using detail::linear_stress_energy;
using detail::material_of;

namespace detail {
const Material& material_of(const std::vector<Material>& mats, int id, Index p) {
  if (id < 0 || id >= int(mats.size()))
    throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                     " but only " + std::to_string(mats.size()) + " materials are defined");
  return mats[size_t(id)];
}
} // namespace detail

namespace {
Eigen::Matrix3d particle_F(const Particles& P, Index p) {
  return embed_3d(P.F.row(p).data(), P.dim);
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
