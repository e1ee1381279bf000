#include "sparsempm/diagnostics.hpp"

#include "parallel.hpp"

#include <cmath>

namespace smpm {

Energies energies(const Model& model) {
  const Particles& P = model.particles;
  const int d = P.dim;
  Energies e;
  // Σ_p M_p |V_p|² and Σ_p M_p V_p in one pass, summed in the fixed order of ordered_reduce.
  double sums[4];
  detail::ordered_reduce(
      P.size(), 1 + d, 0.0, sums,
      [&](Index p, double* acc) {
        const double M = P.mass[p];
        double v2 = 0;
        for (int a = 0; a < d; ++a) {
          v2 += P.V(p, a) * P.V(p, a);
          acc[1 + a] += M * P.V(p, a);
        }
        acc[0] += M * v2;
      },
      [](double a, double b) { return a + b; });
  e.kinetic = 0.5 * sums[0];
  e.strain = strain_energy(model.materials, P);
  e.total = e.kinetic + e.strain;
  for (int a = 0; a < d; ++a)
    e.momentum[a] = sums[1 + a];
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
