#include "sparsempm/diagnostics.hpp"

#include <cmath>

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

void material_sums(const Model& model, std::vector<double>& out) {
  const Particles& P = model.particles;
  const int d = P.dim, w = 1 + 2 * d;
  out.assign(model.materials.size() * size_t(w), 0.0);
  for (Index p = 0; p < P.size(); ++p) {
    double* o = out.data() + size_t(P.material[p]) * size_t(w);
    const double M = P.mass[p];
    o[0] += M;
    for (int a = 0; a < d; ++a) {
      o[1 + a] += M * P.V(p, a);
      o[1 + d + a] += M * P.X(p, a);
    }
  }
  for (size_t k = 0; k < model.materials.size(); ++k)
    for (int a = 0; a < d; ++a) {
      double& c = out[k * size_t(w) + size_t(1 + d + a)];
      c = out[k * size_t(w)] > 0 ? c / out[k * size_t(w)] : std::nan("");
    }
}

} // namespace smpm
