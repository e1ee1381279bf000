// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/particles.hpp"

#include "sparsempm/plasticity.hpp"

#include "sparsempm/errors.hpp"

#include "kernels.hpp"
#include "parallel.hpp"

#include <cmath>
#include <string>

namespace smpm {

void Particles::resize(int d, Index N) {
  dim = d;
  X.setZero(N, d);
  V.setZero(N, d);
  F.setZero(N, d * d);
  for (Index p = 0; p < N; ++p)
    for (int a = 0; a < d; ++a)
      F(p, a * d + a) = 1;
  stress.setZero(N, d * d);
  mass.setZero(N);
  volume0.setZero(N);
  material.setZero(N);
  half_length.setZero(N, d);
  energy.setZero(N);
  temperature.resize(0);
  heat_source.resize(0);
  gradient.resize(0, 0);
  elastic_cauchy_green.resize(0, 0);
  plastic_strain.resize(0);
}

Eigen::VectorXd Particles::jacobian() const {
  Eigen::VectorXd J;
  jacobian(J);
  return J;
}

double Particles::det_F(Index p) const {
  const double* f = F.data() + p * dim * dim;
  return dim == 1 ? detail::det<1>(f) : dim == 2 ? detail::det<2>(f) : detail::det<3>(f);
}

void Particles::jacobian(Eigen::VectorXd& J) const {
  J.resize(size());
  detail::parallel_for(size(), [&](Index p) { J[p] = det_F(p); });
}

Eigen::VectorXd Particles::volume() const {
  return jacobian().cwiseProduct(volume0);
}

void Particles::append(const Particles& o) {
  if (size() == 0) {
    *this = o;
    return;
  }
  if (o.size() == 0)
    return;
  SMPM_VERIFY(o.dim == dim, "cannot append " + std::to_string(o.dim) + "D particles to " +
                                std::to_string(dim) + "D particles");
  auto stack = [](auto& a, const auto& b) {
    auto c = a;
    a.resize(c.rows() + b.rows(), c.cols());
    a << c, b;
  };
  stack(X, o.X);
  stack(V, o.V);
  stack(F, o.F);
  stack(stress, o.stress);
  stack(mass, o.mass);
  stack(volume0, o.volume0);
  stack(material, o.material);
  stack(half_length, o.half_length);
  const Index n0 = size() - o.size();
  // An optional column (empty: absent) of both sets, an absent one counting as zeros.
  auto stack_optional = [&](Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    if (a.size() != n0 && b.size() != o.size())
      return;
    const Eigen::VectorXd a0 = a.size() == n0 ? a : Eigen::VectorXd::Zero(n0);
    const Eigen::VectorXd b0 = b.size() == o.size() ? b : Eigen::VectorXd::Zero(o.size());
    a.resize(n0 + o.size());
    a << a0, b0;
  };
  if (energy.size() != n0 && o.energy.size() != o.size()) { // both absent: all 0
    energy.setZero(n0 + o.size());
  } else {
    stack_optional(energy, o.energy);
  }
  SMPM_VERIFY((temperature.size() == n0) == (o.temperature.size() == o.size()),
              "append: particles with temperatures and particles without");
  stack_optional(temperature, o.temperature);
  stack_optional(heat_source, o.heat_source);
  if (gradient.rows() == n0 || o.gradient.rows() == o.size()) { // absent: zero gradients
    const Field g0 = gradient.rows() == n0 ? gradient : Field::Zero(n0, dim * dim);
    const Field g1 = o.gradient.rows() == o.size() ? o.gradient : Field::Zero(o.size(), dim * dim);
    gradient.resize(n0 + o.size(), dim * dim);
    gradient << g0, g1;
  }
  // The plastic state: a set without one starts elastic (b̄ᵉ of its F, ε̄ᵖ = 0).
  if (elastic_cauchy_green.rows() == n0 || o.elastic_cauchy_green.rows() == o.size()) {
    const Field b0 = elastic_cauchy_green.rows() == n0 ? elastic_cauchy_green
                                                       : elastic_state_of(F.topRows(n0), dim);
    const Field b1 = o.elastic_cauchy_green.rows() == o.size() ? o.elastic_cauchy_green
                                                               : elastic_state_of(o.F, dim);
    const Eigen::VectorXd e0 =
        plastic_strain.size() == n0 ? plastic_strain : Eigen::VectorXd::Zero(n0);
    const Eigen::VectorXd e1 =
        o.plastic_strain.size() == o.size() ? o.plastic_strain : Eigen::VectorXd::Zero(o.size());
    elastic_cauchy_green.resize(n0 + o.size(), 9);
    elastic_cauchy_green << b0, b1;
    plastic_strain.resize(n0 + o.size());
    plastic_strain << e0, e1;
  }
}

Particles make_block(const Grid& grid, const std::array<double, 3>& lo,
                     const std::array<double, 3>& hi, const std::array<int, 3>& ppc, double density,
                     int material_id) {
  const int d = grid.dim();
  if (!(density > 0))
    throw InputError("density must be positive, got " + std::to_string(density));
  std::array<Index, 3> count{1, 1, 1};
  std::array<double, 3> spacing{1, 1, 1};
  for (int a = 0; a < d; ++a) {
    if (ppc[a] < 1)
      throw InputError("ppc[" + std::to_string(a) + "] must be at least 1");
    if (!(hi[a] > lo[a]))
      throw InputError("block max[" + std::to_string(a) + "] must exceed min[" + std::to_string(a) +
                       "]");
    spacing[a] = grid.cell_size(a) / ppc[a];
    count[a] = std::max<Index>(1, Index(std::llround((hi[a] - lo[a]) / spacing[a])));
    spacing[a] = (hi[a] - lo[a]) / double(count[a]);
  }
  if (!grid.contains(lo) || !grid.contains(hi))
    throw InputError("block [min, max] is not inside the grid");
  Particles P;
  P.resize(d, count[0] * count[1] * count[2]);
  double vol = 1;
  for (int a = 0; a < d; ++a)
    vol *= spacing[a];
  Index p = 0;
  for (Index k = 0; k < count[2]; ++k)
    for (Index j = 0; j < count[1]; ++j)
      for (Index i = 0; i < count[0]; ++i, ++p) {
        const Index ijk[3] = {i, j, k};
        for (int a = 0; a < d; ++a) {
          P.X(p, a) = lo[a] + (double(ijk[a]) + 0.5) * spacing[a];
          P.half_length(p, a) = 0.5 * spacing[a];
        }
        P.volume0[p] = vol;
        P.mass[p] = density * vol;
        P.material[p] = material_id;
      }
  return P;
}

} // namespace smpm
