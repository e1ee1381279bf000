// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file plasticity.hpp
/// Finite-strain J2 plasticity with linear isotropic hardening (Simo 1988; Simo & Hughes 1998,
/// Box 9.1; NairnMPM's HEIsotropic and HEMGEOSMaterial): the multiplicative split F = Fᵉ Fᵖ,
/// the isochoric elastic left Cauchy–Green tensor b̄ᵉ = J^{−2/3} Fᵉ Fᵉᵀ as the particle's state,
/// the Kirchhoff stress τ = J p I + s with s = G dev(b̄ᵉ), and the yield condition
///     f(s, ε̄ᵖ) = ‖s‖ − √(2/3) (σ_y + H ε̄ᵖ) ≤ 0,
/// with σ_y the initial yield stress, H the hardening modulus and ε̄ᵖ the equivalent plastic
/// strain. The return is radial in the current configuration (Box 9.1):
///     b̄ᵉ_tr = f̄ b̄ᵉ_n f̄ᵀ,  f̄ = det(f)^{−1/3} f,  f = F_{n+1} F_n⁻¹,  s_tr = G dev(b̄ᵉ_tr);
///     if f(s_tr, ε̄ᵖ_n) > 0:  Ḡ = G tr(b̄ᵉ_tr)/3,  Δγ = f_tr / (2Ḡ + (2/3) H),
///     s = s_tr − 2Ḡ Δγ n̂,  ε̄ᵖ += √(2/3) Δγ,  b̄ᵉ = s/G + Ī I,
/// with Ī the root of det(s/G + Ī I) = 1 nearest tr(b̄ᵉ_tr)/3 (Simo & Hughes §9.3's correction:
/// b̄ᵉ stays isochoric, so the stored energy (G/2)(tr b̄ᵉ − 3) holds no plastic work).
/// The volumetric part is the material's elastic one: (K/2)(J² − 1) for `hyperelastic`
/// (contact 2020 Eq. 18), −J(p + q) for `mie-gruneisen` (Eqs. 51–52), so a plastic particle's
/// Cauchy stress is σ = s/J + (the elastic law's pressure term). The plastic work per unit
/// reference volume of a step is ‖s‖ Δγ (τ : dᵖ Δt; ‖s‖ on the yield surface), which the run
/// reports as the `plastic` series and heat transport turns into heat.

#include "sparsempm/material.hpp"
#include "sparsempm/particles.hpp"

#include <Eigen/Core>
#include <vector>

namespace smpm {

/// One radial return (Simo & Hughes Box 9.1) from the state (b̄ᵉ_n, ε̄ᵖ_n) under the relative
/// deformation gradient f = F_{n+1} F_n⁻¹ (3 × 3).
struct J2Return {
  Eigen::Matrix3d s;     ///< the deviatoric Kirchhoff stress s = G dev(b̄ᵉ) after the return
  Eigen::Matrix3d be;    ///< b̄ᵉ_{n+1}
  double plastic_strain; ///< ε̄ᵖ_{n+1}
  double work;           ///< the plastic work per unit reference volume of the step, ‖s‖ Δγ
  double yield;          ///< f(s, ε̄ᵖ_{n+1}) after the return (≤ 0 to round-off)
};

/// The return of the material `mat` (yield_stress > 0; shear modulus G, hardening H).
J2Return j2_return(const Material& mat, const Eigen::Matrix3d& f, const Eigen::Matrix3d& be_n,
                   double plastic_strain_n);

/// The Cauchy stress of a particle of the plastic material `mat` at the total deformation F
/// (3 × 3) in the elastic state b̄ᵉ: σ = G dev(b̄ᵉ)/J + the elastic law's volumetric term at
/// J = det F (Mie–Grüneisen at U = 0, as cauchy_stress), the stress of the return when it does
/// not yield. With b̄ᵉ = J^{−2/3} F Fᵀ (no plastic flow) this is cauchy_stress(mat, F).
Eigen::Matrix3d elastic_state_stress(const Material& mat, const Eigen::Matrix3d& F,
                                     const Eigen::Matrix3d& be);

/// Whether a material of the list is elastic–plastic (Material::plastic).
bool uses_plasticity(const std::vector<Material>& materials);

/// The particles' plastic state and its update (MaterialStrainUpdate): b̄ᵉ (N × 9, row-major
/// 3 × 3; in 2D plane strain and 1D uniaxial strain the out-of-plane entries evolve too) and ε̄ᵖ
/// (N), with the scratch of the step.
struct PlasticState {
  Field* elastic_cauchy_green = nullptr;     ///< N × 9: b̄ᵉ of every particle (updated)
  Eigen::VectorXd* plastic_strain = nullptr; ///< N: ε̄ᵖ of every particle (updated)
  Field F_old;                               ///< scratch: F before the strain update
  Eigen::VectorXd work;                      ///< N: each particle's plastic work of the update
  double plastic_work = 0; ///< Σ_p Ω_p ‖s‖ Δγ of the step's updates (the Stepper zeroes it)
};

/// After the elastic stress update of a step (update_stress, and update_shock_stress for
/// Mie–Grüneisen particles, whose p + q is `pressure`), the return of every particle of a
/// plastic material from F_old to F (N × d²): its b̄ᵉ and ε̄ᵖ, and its Cauchy stress
/// σ = s/J + the law's pressure term; with `density`, W = (G/2)(tr b̄ᵉ − 3) (+ the volumetric
/// energy (K/2)(½(J² − 1) − ln J) for hyperelastic). Other particles are left as they are.
/// Returns the plastic work Σ_p Ω_p ‖s‖ Δγ of the update, each particle's in `state.work`.
double update_plastic_stress(const std::vector<Material>& materials,
                             const Eigen::Ref<const Eigen::VectorXi>& material,
                             const ConstFieldRef& F,
                             const Eigen::Ref<const Eigen::VectorXd>& volume0,
                             const Eigen::VectorXd* pressure, PlasticState& state, FieldRef stress,
                             Eigen::VectorXd* density);

/// The pressure p + q of every plastic Mie–Grüneisen particle from its stress, F and b̄ᵉ,
/// −(1/d) Σ_a (σ_aa − s_aa/J) with s = G dev(b̄ᵉ) (shock_pressure for the elastic shear term);
/// other particles are left as they are.
void plastic_shock_pressure(const std::vector<Material>& materials,
                            const Eigen::Ref<const Eigen::VectorXi>& material,
                            const ConstFieldRef& F, const ConstFieldRef& stress,
                            const Field& elastic_cauchy_green,
                            Eigen::Ref<Eigen::VectorXd> pressure);

/// W of a plastic particle from its b̄ᵉ (row-major 3 × 3) and J: (G/2)(tr b̄ᵉ − 3), plus
/// (K/2)(½(J² − 1) − ln J) for hyperelastic (Mie–Grüneisen keeps its volumetric energy in U).
double plastic_strain_energy_density(const Material& mat, const double* be, double J);

/// b̄ᵉ = J^{−2/3} F Fᵀ of each row of F (N × d², embedded as embed_3d does), N × 9: the plastic
/// state of particles that have not yielded.
Field elastic_state_of(const ConstFieldRef& F, int dim);
/// When the particles have no plastic state (Particles::elastic_cauchy_green and
/// plastic_strain not of N rows), sets b̄ᵉ = J^{−2/3} F Fᵀ (all elastic) and ε̄ᵖ = 0 for every
/// particle: a model set up with F ≠ I starts elastic.
void initial_plastic_state(Particles& particles);

} // namespace smpm
