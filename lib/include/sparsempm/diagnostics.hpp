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
};

Energies energies(const Model& model);

/// Mass, momentum and centre of mass of each material's particles (one body per material in
/// multimaterial runs), one pass: for material k, out[k(1 + 2d) + 0] = Σ M_p,
/// out[… + 1 + a] = Σ M_p V_pa, out[… + 1 + d + a] = Σ M_p X_pa / Σ M_p (NaN without
/// particles). `out` is resized to n_materials (1 + 2d).
void material_sums(const Model& model, std::vector<double>& out);

} // namespace smpm
