// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The pieces of the material laws shared by their sources (internal to sparsempm): material.cpp
// (the laws at one deformation gradient), particle_stress.cpp (the laws over the particles) and
// mie_gruneisen.cpp (the shock physics).

#include "sparsempm/material.hpp"

#include <Eigen/Core>

namespace smpm::detail {

// Linear elasticity written out for dimension D (the common case, kept cheap on the hot path):
// The moduli of the linear law: E, λ and 2G, computed once for a run of particles of one
// material (each is two divisions).
struct LinearModuli {
  double youngs = 0, lam = 0, G2 = 0;
  LinearModuli() = default;
  explicit LinearModuli(const Material& m)
      : youngs(m.youngs), lam(m.lame_lambda()), G2(2 * m.shear_modulus()) {}
};

// σ = λ tr(ε) I + 2Gε with ε = sym(F) − I (D ≥ 2), σ = E (F − 1) in 1D.
template <int D>
[[gnu::always_inline]] inline void linear_stress(const LinearModuli& m, const double* F,
                                                 double* sigma) {
  if constexpr (D == 1) {
    sigma[0] = m.youngs * (F[0] - 1);
  } else {
    const double lam = m.lam, G2 = m.G2;
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
[[gnu::always_inline]] inline double linear_energy(const LinearModuli& m, const double* F,
                                                   const double* sigma) {
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
inline void linear_stress_energy(const Material& m, int d, const double* F, double* sigma,
                                 double* energy) {
  const LinearModuli moduli(m);
  auto run = [&]<int D>() {
    linear_stress<D>(moduli, F, sigma);
    if (energy)
      *energy = linear_energy<D>(moduli, F, sigma);
  };
  if (d == 1)
    run.template operator()<1>();
  else if (d == 2)
    run.template operator()<2>();
  else
    run.template operator()<3>();
}

// The corotational law (MaterialModel::LinearCorotational) in 3D (2D: plane strain, F₃₃ = 1):
// F = R U with U = (FᵀF)^½ from the eigen decomposition of FᵀF, the Biot strain ε = U − I and
// T = λ tr(ε) I + 2Gε; returns σ = R (T U) Rᵀ / J and sets W = ½ T : ε.
Eigen::Matrix3d corotational_stress(const Material& m, const Eigen::Matrix3d& F, double& W);

// The shear term of the hyperelastic and Mie–Grüneisen laws (contact 2020 Eqs. 18, 51):
// σ_shear = (G/J) dev(B̄), B̄ = J^{−2/3} F Fᵀ.
Eigen::Matrix3d isochoric_shear(double G, const Eigen::Matrix3d& F, double J);

// Throws InputError: particle p's material id names no material.
[[noreturn]] void throw_material_id(const std::vector<Material>& mats, int id, Index p);

// The material of particle p by its id; InputError when no material has the id. Inline: it is
// called once per particle of every stress update.
inline const Material& material_of(const std::vector<Material>& mats, int id, Index p) {
  if (unsigned(id) >= mats.size()) [[unlikely]]
    throw_material_id(mats, id, p);
  return mats[size_t(id)];
}

// Throws NumericalError naming particle p when its compression is beyond the Mie–Grüneisen
// law's limit 1 − J < 1/S₁ (the law's pressure diverges there).
void check_compression(const Material& mat, double J, Index p);

} // namespace smpm::detail
