// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The models and the comparison of the simulations across ranks (test_distributed_run.cpp,
// test_distributed_migration.cpp): a run across ranks and, on rank 0, the serial run of the
// whole model.

#include "mpi_support.hpp"
#include "support.hpp"

#include <sparsempm/petsc_run.hpp>
#include <sparsempm/problems.hpp>

#include <cmath>
#include <functional>
#include <vector>

namespace smpm::test {

/// The free-vibrating bar of FMPM 2026 §3.3 at v₀ = 0.4 (displacements of several cells, so that
/// particles cross the boxes' boundaries), fixed at x = 0.
inline Model bar_model() {
  BarSetup setup;
  setup.v0 = 0.4;
  return vibrating_bar(setup);
}

/// A free 2D plate (8 × 6 cells of 2 × 2 particles) on a 24 × 16-cell grid, drifting at
/// (1, 0.6) (3 and 1.8 cells in 200 steps at C = 0.2: across x = 8 and 12 and y = 8, the boxes'
/// boundaries on 2 to 4 ranks) with a shear wave v_y = 0.05 sin(0.4 x) on it. It starts in the
/// box of rank 0 alone on 2 and 4 ranks (the others step without particles until some arrive).
/// Masses and volumes vary by ±30% from particle to particle, so that a sum taken over the wrong
/// particles does not cancel out.
inline Model plate_model() {
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {24, 16, 1}));
  model.materials = {material("plate", MaterialModel::Linear, 100, 0.3)};
  model.particles = make_block(model.grid, {2, 2, 0}, {10, 8, 0}, {2, 2, 1}, 1.0, 0);
  model.bcs = BoundaryConditions::none(model.grid);
  for (Index p = 0; p < model.particles.size(); ++p) {
    model.particles.V(p, 0) = 1.0;
    model.particles.V(p, 1) = 0.6 + 0.05 * std::sin(0.4 * model.particles.X(p, 0));
    const double f = 1 + 0.3 * std::sin(1.7 * double(p));
    model.particles.mass[p] *= f;
    model.particles.volume0[p] *= f;
  }
  return model;
}

/// max |a − b| / max |b| (the difference itself for a zero b).
inline double relative(const Field& a, const Field& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

/// A run across ranks and the serial one (on rank 0), of the same steps.
struct Compared {
  long moved = 0;                     ///< particles migrated over the run (every rank)
  Particles gathered;                 ///< rank 0: the particles across ranks at the end
  Model serial;                       ///< rank 0: the serial model at the end
  Energies energies, serial_energies; ///< at the end (serial_energies: rank 0)
  std::vector<std::vector<double>> reactions, serial_reactions; ///< every step's (rank 0)
};

/// `steps` steps of `dt` of `whole` across the ranks (DistributedStepper; `each_step` after each
/// with the particles the step migrated) and, on rank 0, of the serial Stepper. Collective.
inline Compared run_both(const Model& whole, const StepOptions& options, int steps, double dt,
                         const std::function<void(petsc::DistributedStepper&, petsc::RankModel&,
                                                  Index)>& each_step = {}) {
  Compared c;
  const petsc::DistributedGrid grid(whole.grid);
  petsc::RankModel local = petsc::distribute(grid, whole);
  petsc::DistributedStepper dist(grid, options);
  for (int s = 0; s < steps; ++s) {
    const Index moved = dist.step(local, dt);
    c.moved += long(moved);
    c.reactions.push_back(dist.reactions());
    if (each_step)
      each_step(dist, local, moved);
  }
  c.energies = dist.energies(local);
  c.gathered = petsc::gather_particles(grid, local);
  if (rank() != 0)
    return c;
  c.serial = whole;
  Stepper stepper(options);
  for (int s = 0; s < steps; ++s) {
    stepper.step(c.serial, dt);
    c.serial_reactions.push_back(stepper.reactions());
  }
  c.serial_energies = stepper.energies(c.serial);
  return c;
}

/// On rank 0: X, V, F and σ within `tol` of each field's largest entry.
inline void check_fields(const Compared& c, double tol) {
  if (rank() != 0)
    return;
  const Particles& P = c.serial.particles;
  CHECK(relative(c.gathered.X, P.X) < tol);
  CHECK(relative(c.gathered.V, P.V) < tol);
  CHECK(relative(c.gathered.F, P.F) < tol);
  CHECK(relative(c.gathered.stress, P.stress) < tol);
}

/// On rank 0: the kinetic and strain energies within `tol` relative, the momentum within `tol`
/// of its scale √(2 K M).
inline void check_energies(const Compared& c, double tol) {
  if (rank() != 0)
    return;
  const Energies &e = c.energies, &es = c.serial_energies;
  CHECK(e.kinetic == approx(es.kinetic, 0, tol));
  CHECK(e.strain == approx(es.strain, 0, tol));
  const double scale = std::sqrt(2 * es.kinetic * c.serial.particles.mass.sum());
  CHECK((e.momentum - es.momentum).norm() < tol * scale);
}

/// On rank 0: every condition's reaction at every step within `tol` of the largest over the run,
/// which is not zero. Returns that largest.
inline double check_reactions(const Compared& c, double tol) {
  if (rank() != 0)
    return 0;
  double largest = 0, worst = 0;
  REQUIRE(c.reactions.size() == c.serial_reactions.size());
  for (size_t s = 0; s < c.reactions.size(); ++s) {
    REQUIRE(c.reactions[s].size() == c.serial_reactions[s].size());
    for (size_t k = 0; k < c.reactions[s].size(); ++k) {
      largest = std::max(largest, std::abs(c.serial_reactions[s][k]));
      worst = std::max(worst, std::abs(c.reactions[s][k] - c.serial_reactions[s][k]));
    }
  }
  CHECK(largest > 0);
  CHECK(worst <= tol * largest);
  return largest;
}

} // namespace smpm::test
