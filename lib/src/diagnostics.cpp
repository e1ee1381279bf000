#include "sparsempm/diagnostics.hpp"

namespace smpm {

Energies energies(const Model& model) {
  const Particles& P = model.particles;
  Energies e;
  e.kinetic = 0.5 * (P.mass.asDiagonal() * P.V.rowwise().squaredNorm()).sum();
  e.strain = strain_energy(model.materials, P);
  e.total = e.kinetic + e.strain;
  const Eigen::RowVectorXd mom = P.mass.transpose() * P.V;
  for (int a = 0; a < P.dim; ++a)
    e.momentum[a] = mom[a];
  return e;
}

} // namespace smpm
