// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/loads.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace smpm {

double face_area(const Particles& P, Index p, int axis) {
  SMPM_VERIFY(axis >= 0 && axis < P.dim, "face_area: axis out of range");
  double area = 1;
  for (int b = 0; b < P.dim; ++b)
    if (b != axis)
      area *= 2 * P.half_length(p, b);
  return area;
}

std::vector<Index> exposed_face(const Particles& P, const std::vector<Index>& candidates, int axis,
                                int side) {
  SMPM_VERIFY(axis >= 0 && axis < P.dim && (side == 1 || side == -1),
              "exposed_face: axis out of range or side not +1/-1");
  // Cells of a quarter of the smallest particle size hash the centres; a neighbour is looked for
  // in the cells around its expected centre.
  double h = std::numeric_limits<double>::infinity();
  for (const Index p : candidates)
    for (int b = 0; b < P.dim; ++b)
      h = std::min(h, 0.5 * P.half_length(p, b));
  if (candidates.empty())
    return {};
  SMPM_VERIFY(h > 0 && std::isfinite(h), "exposed_face: particles need positive half-lengths");
  using Key = std::array<long long, 3>;
  auto key_of = [&](const double* x) {
    Key k{0, 0, 0};
    for (int b = 0; b < P.dim; ++b)
      k[size_t(b)] = (long long)std::floor(x[b] / h);
    return k;
  };
  std::multimap<Key, Index> cells;
  for (const Index p : candidates) {
    double x[3] = {0, 0, 0};
    for (int b = 0; b < P.dim; ++b)
      x[b] = P.X(p, b);
    cells.emplace(key_of(x), p);
  }
  std::vector<Index> face;
  for (const Index p : candidates) {
    double x[3] = {0, 0, 0};
    for (int b = 0; b < P.dim; ++b)
      x[b] = P.X(p, b);
    x[axis] += side * 2 * P.half_length(p, axis);
    const Key k = key_of(x);
    bool covered = false;
    // The cells within one of k in every direction hold every centre within h of x.
    for (int i = -1; i <= 1 && !covered; ++i)
      for (int j = (P.dim > 1 ? -1 : 0); j <= (P.dim > 1 ? 1 : 0) && !covered; ++j)
        for (int l = (P.dim > 2 ? -1 : 0); l <= (P.dim > 2 ? 1 : 0) && !covered; ++l) {
          const Key c{k[0] + i, k[1] + j, k[2] + l};
          const auto [lo, hi] = cells.equal_range(c);
          for (auto it = lo; it != hi && !covered; ++it) {
            double dist = 0;
            for (int b = 0; b < P.dim; ++b)
              dist = std::max(dist, std::abs(P.X(it->second, b) - x[b]));
            covered = dist < 0.5 * P.half_length(p, axis);
          }
        }
    if (!covered)
      face.push_back(p);
  }
  return face;
}

namespace {
// b(t, x) of one load, checked finite; x and b are scratch.
void load_values(const ParticleLoad& load, const Particles& P, double t, Field& x, Field& b) {
  const Index n = Index(load.particles.size());
  x.resize(n, P.dim);
  for (Index k = 0; k < n; ++k)
    x.row(k) = P.X.row(load.particles[size_t(k)]);
  b.resize(n, P.dim);
  load.value(t, x, b);
  SMPM_VERIFY(b.rows() == n && b.cols() == P.dim, "ParticleLoad::value: b must be n x d");
  for (Index k = 0; k < n; ++k)
    for (int a = 0; a < P.dim; ++a)
      if (!std::isfinite(b(k, a)))
        throw NumericalError(load.label + ": the value is " + number_text(b(k, a)) +
                             " at t = " + number_text(t) + " for particle " +
                             std::to_string(load.particles[size_t(k)]));
}

// The weight of a load's k-th particle: M_p (body force) or A_p (traction).
double weight(const ParticleLoad& load, const Particles& P, size_t k) {
  return load.kind == LoadKind::Traction ? load.area[Index(k)] : P.mass[load.particles[k]];
}
} // namespace

void external_forces(const std::vector<ParticleLoad>& loads, const Particles& P, double t,
                     bool deformed, ExternalForces& out) {
  const int d = P.dim;
  out.points.clear();
  out.any_body_force = false;
  for (const ParticleLoad& load : loads)
    if (load.kind == LoadKind::BodyForce && !out.any_body_force) {
      out.particle.setZero(P.size(), d);
      out.any_body_force = true;
    }
  for (const ParticleLoad& load : loads) {
    const bool traction = load.kind == LoadKind::Traction;
    SMPM_VERIFY(!traction || (load.area.size() == Index(load.particles.size()) && load.axis >= 0 &&
                              load.axis < d && (load.side == 1 || load.side == -1)),
                "ParticleLoad: a traction needs one area per particle, an axis and a side");
    load_values(load, P, t, out.x, out.b);
    for (size_t k = 0; k < load.particles.size(); ++k) {
      const Index p = load.particles[k];
      SMPM_VERIFY(p >= 0 && p < P.size(), "ParticleLoad: particle id out of range");
      if (!traction) {
        out.particle.row(p) += P.mass[p] * out.b.row(Index(k));
        continue;
      }
      // The face's half-edge vectors R ê_b, R = F diag(r⁰) (CPDI) or diag(r⁰).
      Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
      for (int b = 0; b < d; ++b)
        for (int a = 0; a < d; ++a)
          R(a, b) = (deformed ? P.F(p, a * d + b) : double(a == b)) * P.half_length(p, b);
      Eigen::Vector3d centre = Eigen::Vector3d::Zero(), force = Eigen::Vector3d::Zero();
      for (int a = 0; a < d; ++a) {
        centre[a] = P.X(p, a) + load.side * R(a, load.axis);
        force[a] = load.area[Index(k)] * out.b(Index(k), a);
      }
      const int corners = 1 << (d - 1);
      for (int c = 0; c < corners; ++c) { // ± each tangent half-edge
        PointForce pf{p, centre, force / corners};
        for (int b = 0, bit = 0; b < d; ++b) {
          if (b == load.axis)
            continue;
          pf.x += ((c >> bit++) & 1 ? 1.0 : -1.0) * R.col(b);
        }
        out.points.push_back(pf);
      }
    }
  }
}

Eigen::Vector3d total_load(const ParticleLoad& load, const Particles& P, double t) {
  Field x, b;
  load_values(load, P, t, x, b);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < load.particles.size(); ++k)
    for (int a = 0; a < P.dim; ++a)
      sum[a] += weight(load, P, k) * b(Index(k), a);
  return sum;
}

} // namespace smpm
