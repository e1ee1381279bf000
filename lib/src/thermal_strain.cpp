// SPDX-License-Identifier: BSD-3-Clause
// The thermodynamics of a strain update with heat transport (material.hpp): the couplings c of
// the particles' free energies, the isentropic temperature of a deformation, and the heat of
// dissipated work. The heat, shock and plasticity parts call them from their strain hooks.
#include "sparsempm/material.hpp"

#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <string>

namespace smpm {

namespace {
int dimension_of(const ConstFieldRef& F) {
  const int d2 = int(F.cols());
  return d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
}
} // namespace

void thermal_couplings(const std::vector<Material>& materials,
                       const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                       const Eigen::VectorXd& T, Eigen::VectorXd& c) {
  const int d = dimension_of(F);
  c.resize(F.rows());
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = materials[size_t(material[p])];
    c[p] = thermal_coupling(mat, d, embed_3d(F.data() + p * F.outerStride(), d), T[p]);
  });
}

// Newton's method from T₀ e^{−(c(F₁, T₀) − c(F₀, T₀))/(ρ₀ C_V)} (exact when c does not depend on
// T, as for the Grüneisen solid: T₁ = T₀ e^{−γ₀ ΔJ}), with ∂c/∂T by a central difference.
void isentropic_heating(const std::vector<Material>& materials,
                        const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                        const Eigen::VectorXd& c0, Eigen::VectorXd& T) {
  const int d = dimension_of(F);
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = materials[size_t(material[p])];
    const bool shock = mat.model == MaterialModel::MieGruneisen;
    if (mat.thermal_expansion == 0 && !shock)
      return;
    const Eigen::Matrix3d F1 = embed_3d(F.data() + p * F.outerStride(), d);
    const double rhoC = mat.density * mat.heat_capacity, T0 = T[p];
    auto c = [&](double temp) { return thermal_coupling(mat, d, F1, temp); };
    double T1 = T0 * std::exp(-(c(T0) - c0[p]) / rhoC);
    bool converged = shock;
    for (int k = 0; k < 8 && !converged && T1 > 0 && std::isfinite(T1); ++k) {
      const double g = rhoC * std::log(T1 / T0) + c(T1) - c0[p];
      const double h = 1e-6 * T1, dg = rhoC / T1 + (c(T1 + h) - c(T1 - h)) / (2 * h);
      if (!(dg > 0))
        break;
      const double step = g / dg;
      T1 -= step;
      converged = std::abs(step) <= 1e-13 * std::abs(T1);
    }
    if (!converged && T1 > 0 && std::isfinite(T1))
      throw NumericalError("particle " + std::to_string(p) +
                           ": its isentropic temperature did "
                           "not converge in 8 Newton steps from " +
                           number_text(T0) + " (at " + number_text(T1) + ")");
    if (!(T1 > 0) || !std::isfinite(T1))
      throw NumericalError("particle " + std::to_string(p) + " has temperature " + number_text(T1) +
                           " after its thermoelastic heating");
    T[p] = T1;
  });
}

void heat_of_work(const std::vector<Material>& materials,
                  const Eigen::Ref<const Eigen::VectorXi>& material,
                  const Eigen::Ref<const Eigen::VectorXd>& volume0, const Eigen::VectorXd& w,
                  Eigen::VectorXd& T) {
  detail::parallel_for(w.size(), [&](Index p) {
    const Material& mat = materials[size_t(material[p])];
    if (w[p] != 0)
      T[p] += w[p] / (mat.density * mat.heat_capacity * volume0[p]);
  });
}

} // namespace smpm
