#pragma once
/// \file diagnostics.hpp
/// Energies and momentum of the particle state.

#include "sparsempm/model.hpp"

#include <Eigen/Core>

namespace smpm {

struct Energies {
  double kinetic = 0;                                 ///< ½ Σ_p M_p |V_p|²
  double strain = 0;                                  ///< Σ_p V_p^(0) W(F_p)
  double total = 0;                                   ///< kinetic + strain
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(); ///< Σ_p M_p V_p (d entries used)
};

Energies energies(const Model& model);

} // namespace smpm
