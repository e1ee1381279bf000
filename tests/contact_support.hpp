#pragma once
// Multimaterial test problems shared by the contact tests (tests/lib/test_contact.cpp,
// test_contact_nodes.cpp) and the exact update's (tests/exact/test_exact.cpp).

#include "support.hpp"

#include <cmath>
#include <random>
#include <string>

namespace smpm::test {

inline Material elastic(const std::string& name, double youngs, double density = 1.0) {
  return smpm::test::material(name, MaterialModel::NeoHookean, youngs, 0.3, density);
}

inline ContactPair pair_law(ContactLaw law, ContactDetection detection, double mu = 0) {
  ContactPair p;
  p.first = 0;
  p.second = 1;
  p.law = law;
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

} // namespace smpm::test
