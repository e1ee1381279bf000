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

enum class MaterialModel {
  Linear,     ///< σ = λ tr(ε) I + 2Gε, ε = sym(F) − I (1D: σ = E (F − 1))
  NeoHookean, ///< σ = (λ/2)(J − 1/J) I + (G/J)(F Fᵀ − I)   (FMPM 2026 Eq. 14)
  Hyperelastic ///< W = (G/2)(I₁/J^{2/3} − 3) + (K/2)(½(J² − 1) − ln J)  (contact 2020 Eq. 18)
};

/// Name used in input files: linear | neo-hookean | hyperelastic.
std::string_view to_string(MaterialModel m);
/// Inverse of to_string; throws InputError naming the valid choices.
MaterialModel material_model_from_string(std::string_view name);

/// An isotropic elastic material given by density, Young's modulus and Poisson's ratio.
struct Material {
  std::string name;
  MaterialModel model = MaterialModel::Linear;
  double density = 1;
  double youngs = 1;
  double poisson = 0;

  double shear_modulus() const { return youngs / (2 * (1 + poisson)); }
  double lame_lambda() const { return youngs * poisson / ((1 + poisson) * (1 - 2 * poisson)); }
  double bulk_modulus() const { return youngs / (3 * (1 - 2 * poisson)); }
  /// Dilatational wave speed in dimension d: √(E/ρ) for the 1D linear bar, otherwise
  /// √((λ + 2G)/ρ) (√((K + 4G/3)/ρ) for the hyperelastic model, the same number).
  double wave_speed(int dim) const;
};

/// Throws InputError (naming the material) unless density > 0, E > 0 and −1 < ν < ½.
void validate(const Material& mat);

/// Cauchy stress for the deformation gradient F (3 × 3; in 1D/2D the unused rows and
/// columns hold the identity) of a material used in dimension `dim`.
Eigen::Matrix3d cauchy_stress(const Material& mat, int dim, const Eigen::Matrix3d& F);
/// Strain energy per unit reference volume W(F), with τ = J σ = (∂W/∂F) Fᵀ for the
/// large-strain models and W = ½ σ : ε for the linear one.
double strain_energy_density(const Material& mat, int dim, const Eigen::Matrix3d& F);

/// A d × d tensor stored row-major (d² entries) as a 3 × 3 matrix with the identity in the unused
/// rows and columns: the form cauchy_stress takes.
Eigen::Matrix3d embed_3d(const double* F, int d);

/// σ_p = σ(F_p) for every particle (rows of F and stress, N × d²), each with its own material
/// id (N). Throws InputError for a material id without a material.
void update_stress(const std::vector<Material>& materials,
                   const Eigen::Ref<const Eigen::VectorXi>& material, const ConstFieldRef& F,
                   FieldRef stress);
/// Total strain energy Σ_p V_p^(0) W(F_p).
double strain_energy(const std::vector<Material>& materials, const Particles& particles);
/// Largest wave speed over the materials used by the particles.
double max_wave_speed(const std::vector<Material>& materials, const Particles& particles);

} // namespace smpm
