// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file material.hpp
/// Elastic materials: Cauchy stress and strain energy as functions of F.
///
/// In 1D the linear model is a bar in uniaxial stress, σ = E (F − 1); the large-strain models
/// are in uniaxial strain (F = diag(F₁₁, 1, 1)). In 2D every model is plane strain (F₃₃ = 1).

#include "sparsempm/particles.hpp"

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

namespace smpm {

/// The constitutive laws of a Material.
enum class MaterialModel {
  /// σ = λ tr(ε) I + 2Gε, ε = sym(F) − I (1D: σ = E (F − 1)). Small rotations only: it is not
  /// objective (a rigid rotation by θ gives stress of order G θ²); see LinearCorotational.
  Linear,
  /// Objective small-strain elasticity, corotational: F = R U (polar decomposition), the Biot
  /// strain ε = U − I, T = λ tr(ε) I + 2Gε, τ = R (T U) Rᵀ = Jσ; hyperelastic with
  /// W = (λ/2)(tr ε)² + G ε : ε, so τ = (∂W/∂F) Fᵀ. Equals Linear to first order in the strain
  /// and the rotation; a rigid rotation gives σ = 0 (1D: σ = E (F − 1), as Linear).
  LinearCorotational,
  NeoHookean, ///< σ = (λ/2)(J − 1/J) I + (G/J)(F Fᵀ − I)   (FMPM 2026 Eq. 14)
  Hyperelastic, ///< W = (G/2)(I₁/J^{2/3} − 3) + (K/2)(½(J² − 1) − ln J)  (contact 2020 Eq. 18)
  /// Shock physics (contact 2020 Eqs. 51–52): σ = −(p + q) I + (G/J) dev(B̄), the shear term of
  /// Eq. (18) with the Mie–Grüneisen pressure p(J, U) (mie_gruneisen_pressure) and the
  /// artificial viscosity q (artificial_viscosity); U is the particle's internal energy per
  /// unit mass (Particles::energy), updated by the strain update.
  MieGruneisen,
  /// A rigid body's particles (rigid.hpp): no stress and no strain energy; they move with the
  /// velocity of their RigidMotion and set it on the nodes they reach.
  Rigid
};

/// Name used in input files: linear | neo-hookean | hyperelastic | mie-gruneisen.
std::string_view to_string(MaterialModel m);
/// Inverse of to_string; throws InputError naming the valid choices.
MaterialModel material_model_from_string(std::string_view name);

/// The most materials a model takes: the contact laws are a table over pairs of velocity
/// fields (10⁶ entries at this cap).
inline constexpr int kMaxMaterials = 1000;

/// An isotropic elastic material given by density, Young's modulus and Poisson's ratio (a
/// Mie–Grüneisen material by its bulk and shear moduli and its equation of state instead).
struct Material {
  std::string name;                            ///< [[material]] name: messages, bodies, contact
  MaterialModel model = MaterialModel::Linear; ///< the stress law
  double density = 1;                          ///< ρ₀, the density of the undeformed material
  double youngs = 1;                           ///< E, Young's modulus (not for Mie–Grüneisen)
  double poisson = 0;                          ///< ν, Poisson's ratio (not for Mie–Grüneisen)
  /// Mie–Grüneisen (contact 2020 Eqs. 51–52): K, the bulk modulus, given directly
  double bulk = 0, shear = 0; ///< Mie–Grüneisen: G, the shear modulus (0: a fluid)
  /// Mie–Grüneisen: γ₀, the Grüneisen parameter of Eq. (51)
  double gruneisen = 0, hugoniot_slope = 0; ///< Mie–Grüneisen: S₁ of U_s = c₀ + S₁ u_p
  /// Mie–Grüneisen: A₁, the linear coefficient of the artificial viscosity q (Eq. 52)
  double av_linear = 0, av_quadratic = 0; ///< Mie–Grüneisen: A₂, q's quadratic coefficient
  // Heat transport (transport.hpp; FMPM 2026 §3.5).
  double heat_capacity = 0; ///< C_V, heat capacity per unit mass (> 0 with transport)
  double conductivity = 0;  ///< κ, isotropic thermal conductivity (0: no conduction)
  /// T_ref, the stress-free absolute temperature: the particles' initial temperature and the
  /// origin of the thermal energy, entropy and free energy (> 0 with transport)
  double reference_temperature = 0;
  /// α, the linear coefficient of thermal expansion from T_ref (0: none; not for Mie–Grüneisen,
  /// whose thermal pressure is γ₀ρ₀U): thermoelastic_stress
  double thermal_expansion = 0;
  // J2 plasticity (plasticity.hpp; hyperelastic and mie-gruneisen only).
  double yield_stress = 0; ///< σ_y, the initial yield stress in uniaxial tension (0: elastic)
  double hardening = 0; ///< H, the linear isotropic hardening modulus, dσ_y/dε̄ᵖ (0: perfect)

  /// Whether the material is elastic–plastic (yield_stress > 0).
  bool plastic() const { return yield_stress > 0; }

  /// G: the shear modulus given (Mie–Grüneisen), else E / (2 (1 + ν)).
  double shear_modulus() const {
    return model == MaterialModel::MieGruneisen ? shear : youngs / (2 * (1 + poisson));
  }
  /// K: the bulk modulus given (Mie–Grüneisen), else E / (3 (1 − 2ν)).
  double bulk_modulus() const {
    return model == MaterialModel::MieGruneisen ? bulk : youngs / (3 * (1 - 2 * poisson));
  }
  /// Lamé's λ = K − 2G/3 (Mie–Grüneisen), else E ν / ((1 + ν)(1 − 2ν)).
  double lame_lambda() const {
    return model == MaterialModel::MieGruneisen
               ? bulk - 2 * shear / 3
               : youngs * poisson / ((1 + poisson) * (1 - 2 * poisson));
  }
  /// Dilatational wave speed in dimension d: √(E/ρ) for the 1D linear bar, otherwise
  /// √((λ + 2G)/ρ) (√((K + 4G/3)/ρ) for the hyperelastic model, the same number).
  double wave_speed(int dim) const;
};

/// Throws InputError (naming the material) unless density > 0, E > 0 and −1 < ν < ½ (for
/// Mie–Grüneisen: K > 0, G ≥ 0, γ₀ ≥ 0, S₁ ≥ 0, A₁, A₂ ≥ 0).
void validate(const Material& mat);

/// Mie–Grüneisen pressure (contact 2020 Eq. 51) at J = det F and internal energy U per unit
/// mass, with η = 1 − J the relative compression:
///     p = K η (1 − γ₀η/2) / (1 − S₁η)² + ρ₀ γ₀ U   (compression, η > 0),
///     p = K η                                        (tension, η ≤ 0).
/// The paper prints the two cases with the inequalities swapped; this is the form whose
/// Hugoniot is the linear U_s = c₀ + S₁u_p (c₀² = K/ρ₀), as NairnMPM's HEMGEOSMaterial has it.
/// Throws NumericalError when 1 − S₁η ≤ 0 (compression beyond the law's limit).
double mie_gruneisen_pressure(const Material& mat, double J, double U);
/// The bulk modulus along the current state, K_t = ρ dp/dρ = J (∂p/∂η + γ₀ p) (the energy
/// term on an isentrope, dU = p dη/ρ₀), so that the bulk wave speed is √(K_t/ρ).
double mie_gruneisen_tangent(const Material& mat, double J, double U);
/// The artificial viscosity of contact 2020 Eq. (52) in compression (D_kk < 0; 0 otherwise):
/// q = ρ Δx |D_kk| (A₁ C + A₂ Δx |D_kk|), ρ current density, C the current bulk wave speed.
double artificial_viscosity(const Material& mat, double rho, double C, double dx, double Dkk);

/// Cauchy stress for the deformation gradient F (3 × 3; in 1D/2D the unused rows and
/// columns hold the identity) of a material used in dimension `dim`.
Eigen::Matrix3d cauchy_stress(const Material& mat, int dim, const Eigen::Matrix3d& F);
/// Strain energy per unit reference volume W(F), with τ = J σ = (∂W/∂F) Fᵀ for the
/// large-strain models and W = ½ σ : ε for the linear one.
double strain_energy_density(const Material& mat, int dim, const Eigen::Matrix3d& F);

/// Thermoelasticity at the absolute temperature T (heat transport), for a material with thermal
/// expansion α from T_ref: returns σ(F, T) (3 × 3, as cauchy_stress) and sets W, the strain energy
/// per unit reference volume, and the coupling c = −∂Ψ_e/∂T of the elastic free energy Ψ_e (the
/// elastic part of the entropy per unit reference volume). The free energy is
///     Ψ = Ψ_e(F, T) + ρ₀ C_V ((T − T_ref) − T ln(T / T_ref)),
/// with, for the large-strain models, the multiplicative split F = F_e F_T, F_T = e^{αΔT} I (the
/// restrained directions of plane strain and of the 1D uniaxial strain included; Lu & Pister
/// 1975): Ψ_e = J_T W(F_e), σ = σ(F_e), c = α J_T (tr τ_e − 3 W(F_e)) with τ_e = det F_e σ(F_e);
/// and for the linear model ε_e = ε − αΔT I: Ψ_e = ½ σ : ε_e, c = α tr σ (the 1D bar in uniaxial
/// stress: σ = E (F − 1 − αΔT), c = α σ). With α = 0: cauchy_stress, W = strain_energy_density,
/// c = 0. The reversible (isentropic) temperature change of a step follows from the entropy
/// ρ₀ C_V ln(T/T_ref) + c: ΔT = −T Δc / (ρ₀ C_V) (the thermoelastic effect; small strain:
/// −(3αK T/(ρ₀ C_V)) Δε_v = −γ T ΔV/V, NairnMPM's dT_q0 with γ = 3αK/(ρ C_V)).
Eigen::Matrix3d thermoelastic_stress(const Material& mat, int dim, const Eigen::Matrix3d& F,
                                     double T, double& W, double& c);
/// The coupling c = −∂Ψ_e/∂T of thermoelastic_stress, and for a Mie–Grüneisen particle
/// c = ρ₀ C_V γ₀ (J − 1), the entropy of the Grüneisen solid s = C_V (ln(T/T_ref) + γ₀ (J − 1)),
/// whose isentropic heating is ΔT = −γ₀ T ΔJ (NairnMPM's HEMGEOSMaterial); 0 without expansion.
double thermal_coupling(const Material& mat, int dim, const Eigen::Matrix3d& F, double T);

/// A d × d tensor stored row-major (d² entries) as a 3 × 3 matrix with the identity in the unused
/// rows and columns: the form cauchy_stress takes.
Eigen::Matrix3d embed_3d(const double* F, int d);

/// 𝕂 = ∂σ/∂L of a stress law σ(f) of the relative deformation gradient f (3 × 3) at f = I, the
/// material tangent of a linearised step (σ̇ = 𝕂 : L): d⁴ values, row-major over (ab, cd), written
/// to K, by central differences (σ(I + εE_cd) − σ(I − εE_cd)) / 2ε with ε = 10⁻⁶.
template <class StressOfF>
void stress_tangent(int d, const StressOfF& stress, double* K) {
  const double eps = 1e-6;
  const int d2 = d * d;
  for (int c = 0; c < d; ++c)
    for (int e = 0; e < d; ++e) {
      Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
      E(c, e) = eps;
      const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
      const Eigen::Matrix3d dsig =
          (stress(Eigen::Matrix3d(I + E)) - stress(Eigen::Matrix3d(I - E))) / (2 * eps);
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b)
          K[(a * d + b) * d2 + c * d + e] = dsig(a, b);
    }
}

/// σ_p = σ(F_p) for every particle (rows of F and stress, N × d²), each with its own material
/// id (N). With `density`, also W(F_p) of each particle (resized to N; the same bits as
/// strain_energy_density), so that the energies of the step need no second pass over F. Throws
/// InputError for a material id without a material.
/// With `temperature` (N absolute temperatures, heat transport), the particles of materials with
/// thermal expansion take thermoelastic_stress (their W too).
void update_stress(const std::vector<Material>& materials,
                   const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                   FieldRef stress, Eigen::VectorXd* density = nullptr,
                   const Eigen::VectorXd* temperature = nullptr);
/// Total strain energy Σ_p V_p^(0) W(F_p) (with temperatures, the thermoelastic Ψ_e(F_p, T_p) of
/// materials with thermal expansion); for Mie–Grüneisen particles the internal energy
/// M_p U_p plus the elastic shear energy V_p^(0) (G/2)(I₁/J^{2/3} − 3). With `density` (W(F_p)
/// of each particle, as update_stress stores it) W is not evaluated again: the same bits.
double strain_energy(const std::vector<Material>& materials, const Particles& particles,
                     const Eigen::VectorXd* density = nullptr);
/// Largest dilatational wave speed: of the materials used by the particles at rest, and for
/// Mie–Grüneisen particles of their current state, √((K_t + 4G/3)/ρ) (the time step follows
/// the shock-compressed material).
double max_wave_speed(const std::vector<Material>& materials, const Particles& particles);

/// The Mie–Grüneisen part of the strain update (contact 2020 Eqs. 51–52, NairnMPM's order): for
/// each Mie–Grüneisen particle, from J_old, J_new (det F before and after the step) and its
/// pressure p_old (with q) before the step, writes σ = −(p + q) I + (G/J) dev(B̄) with
/// q from D_kk = (1 − J_old/J_new)/Δt (C at U_old), p = p(J_new, U_new) and
/// U_new = U_old − ½(p_old + p + q)(J_new − J_old)/ρ₀, the work of pressure and viscosity per
/// unit mass by the implicit trapezoidal rule (solved exactly: p is linear in U), so that a
/// closed cycle without viscosity returns U to 0 to second order. NairnMPM evaluates p with
/// U_old (first order). The shear term's energy is elastic and stays out of U. `pressure`
/// receives p + q. Returns the work of the viscosity, Σ_p −q_p ΔJ_p V_p^(0) (heat, ≥ 0); with
/// `work`, also each particle's (N; 0 for other materials).
double update_shock_stress(const std::vector<Material>& materials,
                           const Eigen::Ref<const Eigen::VectorXi>& material,
                           const ConstFieldRef& F, const Eigen::Ref<const Eigen::VectorXd>& volume0,
                           const Eigen::Ref<const Eigen::VectorXd>& J_old,
                           const Eigen::Ref<const Eigen::VectorXd>& p_old, double dt, double dx,
                           Eigen::Ref<Eigen::VectorXd> energy, Eigen::Ref<Eigen::VectorXd> pressure,
                           FieldRef stress, Eigen::VectorXd* work = nullptr);
/// The pressure p + q of every Mie–Grüneisen particle from its stress and F: −(1/d) Σ_a
/// (σ_aa − s_aa) with s the shear term at F (the in-plane components carry p in 2D plane
/// strain); 0 for other materials.
void shock_pressure(const std::vector<Material>& materials,
                    const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                    const ConstFieldRef& stress, Eigen::Ref<Eigen::VectorXd> pressure);
/// c_p = thermal_coupling of every particle (rows of F, N × d²) at its temperature T_p (N), into
/// c (resized to N; 0 without a coupling).
void thermal_couplings(const std::vector<Material>& materials,
                       const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                       const Eigen::VectorXd& T, Eigen::VectorXd& c);
/// The isentropic temperature of a step's deformation (FMPM 2026 §3.2.2's compressive heating;
/// NairnMPM's dT_q0) for every particle with thermal expansion or of a Mie–Grüneisen material:
/// its entropy ρ₀ C_V ln(T/T_ref) + c(F, T) kept across the step,
///     ρ₀ C_V ln(T₁/T₀) + c(F₁, T₁) − c(F₀, T₀) = 0,
/// with c₀ = c(F₀, T₀) (thermal_couplings before the step) and F₁ = F; T (N) is T₀ and becomes T₁.
/// Throws NumericalError naming the particle when Newton's method does not converge or T₁ is
/// not positive.
void isentropic_heating(const std::vector<Material>& materials,
                        const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                        const Eigen::VectorXd& c0, Eigen::VectorXd& T);
/// The heat of dissipated work w_p (N; the artificial viscosity's, the plastic work) in the
/// particles' temperatures T (N): ΔT = w / (M C_V) = w / (ρ₀ C_V Ω⁽⁰⁾).
void heat_of_work(const std::vector<Material>& materials,
                  const Eigen::Ref<const Eigen::VectorXi>& material,
                  const Eigen::Ref<const Eigen::VectorXd>& volume0, const Eigen::VectorXd& w,
                  Eigen::VectorXd& T);
/// True when a particle's material is Mie–Grüneisen.
bool uses_shock_physics(const std::vector<Material>& materials);

} // namespace smpm
