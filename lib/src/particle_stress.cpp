// SPDX-License-Identifier: BSD-3-Clause
// The material laws over the particles: the stress update of every particle (update_stress),
// their strain energy and the largest wave speed they carry.

#include "sparsempm/material.hpp"

#include "kernels.hpp"
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
void throw_material_id(const std::vector<Material>& mats, int id, Index p) {
  throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                   " but only " + std::to_string(mats.size()) + " materials are defined");
}
} // namespace detail

namespace {
Eigen::Matrix3d particle_F(const Particles& P, Index p) {
  return embed_3d(P.F.row(p).data(), P.dim);
}

// σ (and W into `energy` when given) of particle p under any law but the linear one without
// thermal expansion: thermoelastic (with `temperature`), corotational, hyperelastic,
// Mie–Grüneisen.
void other_stress(const Material& mat, int d, const double* Fp, double* sigma, double* energy,
                  const double* temperature, Index p) {
  if (temperature && mat.thermal_expansion != 0) { // thermoelastic (heat transport)
    double W, c;
    const Eigen::Matrix3d s = thermoelastic_stress(mat, d, embed_3d(Fp, d), *temperature, W, c);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        sigma[a * d + b] = s(a, b);
    if (energy)
      *energy = W;
    return;
  }
  const Eigen::Matrix3d F3 = embed_3d(Fp, d);
  if (mat.model == MaterialModel::LinearCorotational && d > 1) { // one polar decomposition
    double W;
    const Eigen::Matrix3d s = corotational_stress(mat, F3, W);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        sigma[a * d + b] = s(a, b);
    if (energy)
      *energy = W;
    return;
  }
  if (mat.model == MaterialModel::MieGruneisen)
    check_compression(mat, F3.determinant(), p);
  const Eigen::Matrix3d s = cauchy_stress(mat, d, F3);
  for (int a = 0; a < d; ++a)
    for (int b = 0; b < d; ++b)
      sigma[a * d + b] = s(a, b);
  if (energy)
    *energy = strain_energy_density(mat, d, F3);
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
  // One range of particles per thread, its arrays in locals; the linear law's moduli are
  // computed once for each run of particles of one material.
  auto ranges = [&]<int D>() {
    detail::parallel_segments(F.rows(), [&](Index p0, Index count) {
      const double* Fd = F.data();
      double* Sd = stress.data();
      const Index fs = F.outerStride(), ss = stress.outerStride();
      double* W = density ? density->data() : nullptr;
      const int* id = material.data();
      int linear_id = -1;
      detail::LinearModuli linear;
      for (Index p = p0; p < p0 + count; ++p) {
        const Material& mat = material_of(materials, id[p], p);
        const double* Fp = Fd + p * fs;
        double* sigma = Sd + p * ss;
        if (mat.model == MaterialModel::Linear && !(temperature && mat.thermal_expansion != 0)) {
          if (id[p] != linear_id) {
            linear = detail::LinearModuli(mat);
            linear_id = id[p];
          }
          detail::linear_stress<D>(linear, Fp, sigma);
          if (W)
            W[p] = detail::linear_energy<D>(linear, Fp, sigma);
          continue;
        }
        other_stress(mat, D, Fp, sigma, W ? W + p : nullptr,
                     temperature ? temperature->data() + p : nullptr, p);
      }
    });
  };
  detail::by_dim(d, ranges);
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
