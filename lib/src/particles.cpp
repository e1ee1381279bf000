// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/particles.hpp"

#include "sparsempm/particle_columns.hpp"

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
  for (const ParticleColumn& c : particle_columns()) { // the parts' columns: none yet
    clear_column(*this, c);
    if (c.always)
      set_column(*this, c, Field::Zero(N, column_width(c, d)));
  }
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
  const Particles first = *this; // the first set, for its columns' absent values
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
  // The parts' columns: where one set has a column the other lacks, the other's particles take
  // the column's start values (ParticleColumn::absent).
  for (const ParticleColumn& c : particle_columns()) {
    const bool a = has_column(first, c), b = has_column(o, c);
    if (!a && !b) {
      clear_column(*this, c);
      if (c.always)
        set_column(*this, c, Field::Zero(size(), column_width(c, dim)));
      continue;
    }
    SMPM_VERIFY(c.absent || (a && b),
                "append: particles with " + std::string(c.name) + " and particles without");
    Field values(size(), column_width(c, dim));
    values.topRows(n0) = a ? Field(column_values(first, c)) : c.absent(first);
    values.bottomRows(o.size()) = b ? Field(column_values(o, c)) : c.absent(o);
    set_column(*this, c, values);
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
