#pragma once
/// \file diagnostics.hpp
/// Energies and momentum of the particle state.

#include "sparsempm/model.hpp"

#include <Eigen/Core>
#include <vector>

namespace smpm {

struct Energies {
  double kinetic = 0;                                 ///< ½ Σ_p M_p |V_p|²
  double strain = 0;                                  ///< Σ_p V_p^(0) W(F_p)
  double total = 0;                                   ///< kinetic + strain
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(); ///< Σ_p M_p V_p (d entries used)
  double max_speed = 0; ///< max_p |V_p|, the particle speed of the Courant relation
};

/// The energies, momentum and largest speed of the particles, in one pass over V and one over
/// the strain energy (strain_energy, with the densities W(F_p) of `density` when given).
Energies energies(const Model& model, const Eigen::VectorXd* density = nullptr);
/// |V_p|² summed over the axes in order (energies and signal_speed).
inline double speed_squared(const Particles& P, Index p) {
  double v2 = 0;
  for (int a = 0; a < P.dim; ++a)
    v2 += P.V(p, a) * P.V(p, a);
  return v2;
}

/// Mass, momentum and centre of mass of each material's particles (one body per material in
/// multimaterial runs), one pass: for material k, out[k(1 + 2d) + 0] = Σ M_p,
/// out[… + 1 + a] = Σ M_p V_pa, out[… + 1 + d + a] = Σ M_p X_pa / Σ M_p (NaN without
/// particles). `out` is resized to n_materials (1 + 2d).
void material_sums(const Model& model, std::vector<double>& out);

} // namespace smpm
