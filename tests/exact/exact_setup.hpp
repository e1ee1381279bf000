// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The configuration the exact-solve tests share: a jittered CPDI lattice on an 8 × 8 grid with a
// smooth velocity field, its operators, m̃ and the momentum p = Sᵀ M V.

#include "support.hpp"

#include <cmath>

namespace smpm::test {

struct ExactSetup {
  Grid grid = Grid(2, {0, 0, 0}, {1, 1, 1}, {8, 8, 1});
  Particles P;
  Operators ops;
  ConsistentMass mt;
  Field p;
};

inline ExactSetup exact_setup() {
  ExactSetup s;
  s.P = jittered_lattice(s.grid, 2, 4, 2, 0.3, 5u);
  for (Index q = 0; q < s.P.size(); ++q)
    s.P.V.row(q) << std::sin(1.1 * s.P.X(q, 1)), 0.3 * std::cos(0.9 * s.P.X(q, 0) + q);
  assemble(s.grid, s.P, Shape::CPDI, s.ops);
  assemble_consistent_mass(s.ops, s.mt);
  map_momentum(particle_operators(s.ops), s.P.V, s.p);
  return s;
}

} // namespace smpm::test
