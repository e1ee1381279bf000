// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Multimaterial test problems shared by the contact tests (tests/lib/test_contact.cpp,
// test_contact_nodes.cpp, test_rigid.cpp) and the exact update's (tests/exact/test_exact.cpp).

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/step.hpp"

#include "support.hpp"

#include <cmath>
#include <random>
#include <string>

namespace smpm::test {

inline Material elastic(const std::string& name, double youngs, double density = 1.0) {
  return smpm::test::material(name, MaterialModel::NeoHookean, youngs, 0.3, density);
}

inline ContactPair pair_law(ContactLaw law, ContactDetection detection, double mu = 0,
                            ContactNormal normal = ContactNormal::AverageGradient) {
  ContactPair p;
  p.first = 0;
  p.second = 1;
  p.law = law;
  p.normal = normal;
  p.detection = detection;
  p.friction = mu;
  return p;
}

// A 2D block of 6 × 6 cells (2 × 2 jittered particles per cell) with a smooth velocity field,
// cut into materials 0 and 1 by a random line through it. Single material mode unless
// `contact` is given.
inline Model cut_block(unsigned seed, const ContactPair* contact) {
  Model m(Grid(2, {0, 0, 0}, {1, 1, 1}, {12, 12, 1}));
  m.materials = {elastic("a", 40), elastic("b", 40)};
  m.particles = smpm::test::jittered_lattice(m.grid, 3, 6, 2, 0.2, seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double angle = 2 * M_PI * u(rng), c = 6 + (u(rng) - 0.5);
  Particles& P = m.particles;
  for (Index q = 0; q < P.size(); ++q) {
    const double x = P.X(q, 0), y = P.X(q, 1);
    P.material[q] = (x - c) * std::cos(angle) + (y - c) * std::sin(angle) > 0 ? 1 : 0;
    P.V.row(q) << 0.3 * std::sin(0.9 * x + 0.4 * y), 0.2 * std::cos(0.6 * x - 0.8 * y);
  }
  if (contact) {
    m.contact.material_field = {0, 1};
    m.contact.pairs = {*contact};
  }
  return m;
}

/// `steps` steps of Δt = dt of two models side by side, each with its own stepper of `opt`
/// (a multimaterial run against its single-material twin).
inline void step_side_by_side(const StepOptions& opt, Model& a, Model& b, int steps,
                              double dt = 0.01) {
  Stepper sa(opt), sb(opt);
  for (int s = 0; s < steps; ++s) {
    sa.step(a, dt);
    sb.step(b, dt);
  }
}

inline double max_difference(const Field& a, const Field& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

// The operators of m (GIMP, one field per material of m.contact) and its contact nodes
// (find_contact_nodes, with the velocity conditions `bcs` if given).
inline void contact_nodes_of(const Model& m, Operators& ops, ContactNodes& cn,
                             const BoundaryConditions* bcs = nullptr) {
  Eigen::VectorXi field;
  m.contact.particle_fields(m.particles.material, field);
  assemble(m.grid, m.particles, Shape::GIMP, ops, 2, &field);
  const Eigen::VectorXd volume = m.particles.volume();
  const ContactParticles cp{m.particles.X, m.particles.F, m.particles.half_length, volume};
  find_contact_nodes(m.grid, ops, particle_operators(ops), m.contact, cp, cn, bcs);
}

// Two blocks of GIMP particles (2 × 2 per cell, half-length 0.25) on a 12 × 12 grid of unit
// cells, materials 0 below y = bottom and 1 above it, the upper lattice (of the same spacing
// and half-lengths) shifted up by `gap` (< 0: overlapping), with `law` between them: the
// contact nodes of the configuration (find_contact_nodes; their laws point into m.contact).
inline void stacked_blocks_contact(double bottom, double gap, const ContactPair& law, Model& m,
                                   ContactNodes& cn) {
  m = Model(Grid(2, {0, 0, 0}, {1, 1, 1}, {12, 12, 1}));
  m.materials = {elastic("a", 40), elastic("b", 40)};
  m.particles = make_block(m.grid, {2, 2, 0}, {10, bottom, 0}, {2, 2, 1}, 1.0, 0);
  Particles top = make_block(m.grid, {2, bottom, 0}, {10, bottom + 4, 0}, {2, 2, 1}, 1.0, 1);
  top.X.col(1).array() += gap;
  m.particles.append(top);
  m.contact.material_field = {0, 1};
  m.contact.pairs = {law};
  Operators ops;
  contact_nodes_of(m, ops, cn);
}

// A block (0.6 × 0.4, material 1) resting on a slab (2.4 × 0.4, material 0) inclined at `theta`
// to the x axis, under gravity g = 10 along −y: both on lattices of h/2 aligned with the slope (a
// flat interface, not aligned with the grid), the slab held by the nodes deeper than 0.2 in it.
// The contact is ContactPair's default but for its law (frictionless or Coulomb μ).
inline Model inclined_slab(double theta, double mu, double h = 0.05) {
  const Eigen::Vector2d t(std::cos(theta), std::sin(theta)), n(-std::sin(theta), std::cos(theta));
  const Eigen::Vector2d origin(0.4, 0.7);
  Model m(Grid(2, {0, 0, 0}, {h, h, 1}, {int(std::lround(3.2 / h)), int(std::lround(2.8 / h)), 1}));
  m.materials = {smpm::test::material("slab", MaterialModel::Linear, 1e6, 0.3, 1000),
                 smpm::test::material("block", MaterialModel::Linear, 1e6, 0.3, 1000)};
  const double dx = h / 2;
  std::vector<std::pair<Eigen::Vector2d, int>> points;
  for (double s = dx / 2; s < 2.4; s += dx)
    for (double q = -dx / 2; q > -0.4; q -= dx)
      points.push_back({origin + s * t + q * n, 0});
  for (double s = 0.6 + dx / 2; s < 1.2; s += dx)
    for (double q = dx / 2; q < 0.4; q += dx)
      points.push_back({origin + s * t + q * n, 1});
  Particles& P = m.particles;
  P.resize(2, Index(points.size()));
  for (size_t k = 0; k < points.size(); ++k) {
    const Index p = Index(k);
    P.X.row(p) = points[k].first.transpose();
    P.material[p] = points[k].second;
    P.volume0[p] = dx * dx;
    P.mass[p] = dx * dx * 1000;
    P.half_length.row(p).setConstant(dx / 2);
  }
  VelocityCondition fx, fy;
  for (Index i = 0; i < m.grid.num_nodes(); ++i) {
    const Eigen::Vector3d x = m.grid.node_position(i);
    const Eigen::Vector2d r = Eigen::Vector2d(x[0], x[1]) - origin;
    if (r.dot(t) > -0.2 && r.dot(t) < 2.6 && r.dot(n) < -0.2 && r.dot(n) > -0.6)
      fx.nodes.push_back(i);
  }
  fy.nodes = fx.nodes;
  fx.direction = Eigen::Vector3d::UnitX();
  fy.direction = Eigen::Vector3d::UnitY();
  fx.label = "slab x";
  fy.label = "slab y";
  m.bcs.conditions = {fx, fy};
  m.gravity = {0, -10, 0};
  ContactPair pair; // the defaults
  pair.law = mu > 0 ? ContactLaw::Coulomb : ContactLaw::Frictionless;
  pair.friction = mu;
  m.contact.material_field = {0, 1};
  m.contact.pairs = {pair};
  return m;
}

// The block of inclined_slab (material 1) stepped to t = 0.3 with C = 0.25: the least-squares
// slope of its mean velocity along the slope over 0.1 ≤ t ≤ 0.3 (its acceleration down the
// slope) and that mean velocity's average over the window.
struct Slide {
  double acceleration = 0, mean_velocity = 0;
};
inline Slide slide_down(Model& m, Stepper& stepper, double theta) {
  const Eigen::Vector2d t(std::cos(theta), std::sin(theta));
  double S = 0, St = 0, Stt = 0, Sv = 0, Stv = 0;
  while (m.time < 0.3) {
    stepper.step(m, stable_time_step(m, 0.25));
    double v = 0, M = 0;
    for (Index p = 0; p < m.particles.size(); ++p)
      if (m.particles.material[p] == 1) {
        v += m.particles.mass[p] * (m.particles.V(p, 0) * t[0] + m.particles.V(p, 1) * t[1]);
        M += m.particles.mass[p];
      }
    if (m.time >= 0.1) {
      S += 1, St += m.time, Stt += m.time * m.time, Sv += v / M, Stv += m.time * v / M;
    }
  }
  return {-(S * Stv - St * Sv) / (S * Stt - St * St), Sv / S};
}

} // namespace smpm::test
