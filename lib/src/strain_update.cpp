// SPDX-License-Identifier: BSD-3-Clause
// The simulation's strain update (scheme.hpp, MaterialStrainUpdate): F from the grid velocities,
// then each particle's stress by its material, with the states the parts of the step give it
// (shock physics, the thermal couplings of heat transport, the J2 return).
#include "sparsempm/scheme.hpp"

#include "parallel.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/transport.hpp"

#include <Eigen/LU>

namespace smpm {

// c of every particle at its F and temperature (thermal_coupling; 0 without a coupling).
void MaterialStrainUpdate::couplings(const ConstFieldRef& F, Eigen::VectorXd& c) const {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  const Eigen::VectorXd& T = *thermal_->temperature;
  c.resize(F.rows());
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = materials_[size_t(material_[p])];
    c[p] = thermal_coupling(mat, d, embed_3d(F.data() + p * F.outerStride(), d), T[p]);
  });
}

// The isentropic temperature of the step's deformation (FMPM 2026 §3.2.2's compressive heating;
// NairnMPM's dT_q0): the entropy ρ₀ C_V ln(T/T_ref) + c(F, T) of each coupled particle kept,
//     ρ₀ C_V ln(T₁/T₀) + c(F₁, T₁) − c(F₀, T₀) = 0,
// solved by Newton's method from T₀ e^{−(c(F₁, T₀) − c(F₀, T₀))/(ρ₀ C_V)} (exact when c does not
// depend on T, as for the Grüneisen solid: T₁ = T₀ e^{−γ₀ ΔJ}), with ∂c/∂T by a central
// difference; c(F₀, T₀) is thermal_->coupling.
void MaterialStrainUpdate::reversible_heating(const ConstFieldRef& F) const {
  const int d2 = int(F.cols()), d = d2 == 1 ? 1 : (d2 == 4 ? 2 : 3);
  Eigen::VectorXd& T = *thermal_->temperature;
  const Eigen::VectorXd& c0 = thermal_->coupling;
  detail::parallel_for(F.rows(), [&](Index p) {
    const Material& mat = materials_[size_t(material_[p])];
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

// The J2 return of the plastic particles from plastic_->F_old to F (after the elastic stress
// update and the shock's pressure), and the heat of their plastic work.
void MaterialStrainUpdate::plastic_update(const ParticleFields& fields) {
  plastic_->plastic_work += update_plastic_stress(materials_, material_, fields.F, fields.volume0,
                                                  shock_ ? &shock_->pressure : nullptr, *plastic_,
                                                  fields.stress, density_);
  if (thermal_) { // the plastic work is heat: ΔT = w / (M C_V) = w / (ρ₀ C_V Ω)
    Eigen::VectorXd& Tm = *thermal_->temperature;
    detail::parallel_for(fields.F.rows(), [&](Index p) {
      const Material& mat = materials_[size_t(material_[p])];
      if (plastic_->work[p] != 0)
        Tm[p] += plastic_->work[p] / (mat.density * mat.heat_capacity * fields.volume0[p]);
    });
  }
}

void MaterialStrainUpdate::update(const ParticleOperators& op, const Field& v, double dt,
                                  ParticleFields& fields) {
  const Eigen::VectorXd* T = thermal_ ? thermal_->temperature : nullptr;
  if (thermal_)
    couplings(fields.F, thermal_->coupling);
  if (plastic_)
    plastic_->F_old = fields.F; // storage reused from step to step
  if (!shock_) {
    update_deformation(op, v, dt, kind_, fields.F); // L, F, det F > 0
    if (thermal_)
      reversible_heating(fields.F);
    update_stress(materials_, material_, fields.F, fields.stress, density_, T);
    if (plastic_)
      plastic_update(fields);
    return;
  }
  // Mie–Grüneisen: J and p + q before the step, then the new F, the elastic stresses, and the
  // shock stresses and energies (contact 2020 Eqs. 51–52).
  ShockState& s = *shock_;
  const Index N = fields.F.rows();
  const int d = int(fields.X.cols());
  s.J_old.resize(N);
  s.p_old.resize(N);
  s.pressure.resize(N);
  detail::parallel_for(N, [&](Index p) {
    s.J_old[p] = embed_3d(fields.F.data() + p * fields.F.outerStride(), d).determinant();
  });
  shock_pressure(materials_, material_, fields.F, fields.stress, s.p_old);
  if (plastic_) // the shear term of a plastic particle is G dev(b̄ᵉ)/J
    plastic_shock_pressure(materials_, material_, fields.F, fields.stress,
                           *plastic_->elastic_cauchy_green, s.p_old);
  update_deformation(op, v, dt, kind_, fields.F);
  if (thermal_)
    reversible_heating(fields.F);
  update_stress(materials_, material_, fields.F, fields.stress, density_, T);
  s.viscous_work += update_shock_stress(materials_, material_, fields.F, fields.volume0, s.J_old,
                                        s.p_old, dt, s.dx, *s.energy, s.pressure, fields.stress,
                                        thermal_ ? &thermal_->viscous : nullptr);
  if (thermal_) { // the viscosity's work is heat: ΔT = w / (M C_V) = w / (ρ₀ C_V Ω)
    Eigen::VectorXd& Tm = *thermal_->temperature;
    detail::parallel_for(N, [&](Index p) {
      const Material& mat = materials_[size_t(material_[p])];
      if (thermal_->viscous[p] != 0)
        Tm[p] += thermal_->viscous[p] / (mat.density * mat.heat_capacity * fields.volume0[p]);
    });
  }
  if (plastic_)
    plastic_update(fields);
}

} // namespace smpm
