// SPDX-License-Identifier: BSD-3-Clause
// Simulations across ranks (DistributedStepper: the serial Stepper with the node sums over the
// ranks, and the particles' migration by DMSwarm) against the serial Stepper on the whole model,
// on 1 to 4 ranks.
#include "mpi_support.hpp"
#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/loads.hpp>
#include <sparsempm/petsc.hpp>
#include <sparsempm/problems.hpp>
#include <sparsempm/rigid.hpp>

#include <cmath>

using namespace smpm;
using smpm::test::all_sum;
using smpm::test::rank;
namespace sp = smpm::petsc;

namespace {

// The free-vibrating bar of FMPM 2026 §3.3 at v₀ = 0.4 (displacements of several cells, so that
// particles cross the boxes' boundaries), fixed at x = 0.
Model bar_model() {
  BarSetup setup;
  setup.v0 = 0.4;
  return vibrating_bar(setup);
}

// A free 2D plate (8 × 6 cells of 2 × 2 particles) on a 24 × 16-cell grid, drifting at
// (1, 0.6) (3 and 1.8 cells in 200 steps at C = 0.2: across x = 8 and 12 and y = 8, the boxes'
// boundaries on 2 to 4 ranks) with a shear wave v_y = 0.05 sin(0.4 x) on it. It starts in the
// box of rank 0 alone on 2 and 4 ranks (the others step without particles until some arrive).
// Masses and volumes vary by ±30% from particle to particle, so that a sum taken over the wrong
// particles does not cancel out.
Model plate_model() {
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {24, 16, 1}));
  model.materials = {smpm::test::material("plate", MaterialModel::Linear, 100, 0.3)};
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

// max |a − b| / max |b| (0 for two empty or zero fields).
double relative(const Field& a, const Field& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

} // namespace

TEST_CASE("a simulation across ranks equals the serial one", "[petsc][run]") {
  // 200 steps of the bar (uGIMP) and of the drifting plate (uGIMP; CPDI for FMPM(4)) at C = 0.2
  // (below C* of every member here), FLIP, PIC, FMPM(8), blended FMPM(8) with USF, periodic
  // FMPM(4) with USL+, dynamic FMPM(16) (Changes metric, limit 1e-3) with USAVG, and 400 steps
  // at C = 0.1 of the exact update: X, V, F and σ gathered in global id order equal the serial
  // run's to 1e-10 of each field's largest entry, the kinetic and strain energies to 1e-12, the
  // momentum to 1e-12 of its scale, the bar's reaction at x = 0 to 1e-10 of the largest. The
  // node sums add the ranks' partial sums in another order than the serial scatter, so the runs
  // agree to round-off only. The exact update solves by CG to a relative residual of 1e-13
  // across ranks where the serial one factorises (CHOLMOD): 1e-9 and 1e-10 there (measured up to
  // 2.5e-10 and 1.9e-11 on 2 to 4 ranks).
  std::vector<std::pair<std::string, StepOptions>> schemes;
  StepOptions flip;
  flip.shape = Shape::GIMP;
  schemes.push_back({"FLIP", flip});
  StepOptions pic = flip;
  pic.velocity = VelocityUpdate::PIC;
  schemes.push_back({"PIC", pic});
  StepOptions fmpm8 = flip;
  fmpm8.velocity = VelocityUpdate::FMPM;
  fmpm8.fmpm.order = 8;
  schemes.push_back({"FMPM(8)", fmpm8});
  StepOptions blended = fmpm8;
  blended.fmpm.blend_alpha = 0.8;
  blended.scheme = UpdateScheme::USF;
  schemes.push_back({"blended FMPM(8) USF", blended});
  StepOptions periodic = fmpm8;
  periodic.fmpm.order = 4;
  periodic.periodic_cx = 2;
  periodic.scheme = UpdateScheme::USLPlus;
  schemes.push_back({"periodic FMPM(4) USL+", periodic});
  StepOptions dynamic = fmpm8;
  dynamic.fmpm.order = 16;
  dynamic.fmpm.metric = ConvergenceMetric::Changes;
  dynamic.fmpm.dynamic_limit = 1e-3;
  dynamic.scheme = UpdateScheme::USAVG;
  schemes.push_back({"dynamic FMPM(16) USAVG", dynamic});
  // m̃⁻¹ by CHOLMOD serially, by CG across ranks; CPDI, and nodes below 1% of the largest mass
  // lumped (τ = 0.01): nearly massless nodes at the bodies' edges (the bar's end with uGIMP, the
  // plate's corners) make the unregularised m̃ singular enough to fail serially too.
  StepOptions exact = flip;
  exact.shape = Shape::CPDI;
  exact.velocity = VelocityUpdate::Exact;
  exact.exact.mass_cutoff = 0.01;
  exact.exact_solver = exact_solver_factory();
  schemes.push_back({"exact", exact});
  StepOptions cpdi = fmpm8;
  cpdi.fmpm.order = 4;
  cpdi.shape = Shape::CPDI;
  schemes.push_back({"CPDI FMPM(4)", cpdi});

  const Model bar = bar_model(), plate = plate_model();
  for (const Model* whole : {&bar, &plate})
    for (const auto& [name, options] : schemes) {
      CAPTURE(whole->grid.dim(), name);
      const sp::DistributedGrid grid(whole->grid);
      // The exact inverse's C* on the bar is below 0.2 (0.1616 by simulation): it runs at 0.1.
      const bool exact_update = options.velocity == VelocityUpdate::Exact;
      const double courant = exact_update ? 0.1 : 0.2;
      const int steps = exact_update ? 400 : 200;
      const double fields = exact_update ? 1e-9 : 1e-10, sums = exact_update ? 1e-10 : 1e-12;
      const double dt = stable_time_step(*whole, courant);
      sp::RankModel local = sp::distribute(grid, *whole);
      sp::DistributedStepper dist(grid, options);
      CHECK(dist.stable_time_step(local, courant) == dt); // the same largest speed
      long moved = 0;
      double max_reaction = 0; // the largest |reaction| over the run
      for (int s = 0; s < steps; ++s) {
        const Index now = dist.step(local, dt);
        moved += long(now);
        for (const double r : dist.reactions())
          max_reaction = std::max(max_reaction, std::abs(r));
        if (now > 0) { // after a migration: the energies of the particles each rank now holds
          const double strain = dist.energies(local).strain;
          const double here = energies(local.model).strain;
          double total = 0;
          MPI_Allreduce(&here, &total, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
          CHECK(strain == smpm::test::approx(total, 0, 1e-14));
        }
      }
      const Energies e = dist.energies(local);
      const Particles gathered = sp::gather_particles(grid, local);
      if (grid.size() > 1)
        CHECK(moved > 0); // particles crossed the boxes' boundaries
      if (rank() != 0)
        continue;
      Model serial = *whole;
      Stepper stepper(options);
      for (int s = 0; s < steps; ++s)
        stepper.step(serial, dt);
      const Energies es = stepper.energies(serial);
      const Particles& P = serial.particles;
      if (grid.size() == 1 && !exact_update) { // one rank: the serial step, bit for bit
        CHECK(gathered.X == P.X);
        CHECK(gathered.V == P.V);
        CHECK(gathered.F == P.F);
        CHECK(gathered.stress == P.stress);
        CHECK(e.kinetic == es.kinetic);
        CHECK(e.strain == es.strain);
      }
      CHECK(relative(gathered.X, P.X) < fields);
      CHECK(relative(gathered.V, P.V) < fields);
      CHECK(relative(gathered.F, P.F) < fields);
      CHECK(relative(gathered.stress, P.stress) < fields);
      CHECK(e.kinetic == smpm::test::approx(es.kinetic, 0, sums));
      CHECK(e.strain == smpm::test::approx(es.strain, 0, sums));
      const double p_scale = std::sqrt(2 * es.kinetic * P.mass.sum());
      CHECK((e.momentum - es.momentum).norm() < sums * p_scale);
      if (whole->grid.dim() == 1)
        CHECK(max_reaction > 0); // the fixed end's
      const std::vector<double>& r = dist.reactions();
      REQUIRE(r.size() == stepper.reactions().size());
      for (size_t c = 0; c < r.size(); ++c)
        CHECK(std::abs(r[c] - stepper.reactions()[c]) <= fields * max_reaction);
    }
}

TEST_CASE("a moving wall across ranks selects the serial nodes", "[petsc][run]") {
  // The stretching strip of FMPM 2026 §3.1 (V = ε̇X, ε̇ = 0.025; 960 particles, neo-Hookean),
  // its right end driven by a wall of depth one cell (s_w = 10(1 + ε̇t), v = 10ε̇,
  // ∇v = ε̇/(1 + ε̇t)): the wall selects its nodes among the active ones, which across ranks are
  // those of the total masses, so every rank constrains the serial nodes of its window. 200
  // steps at C = 0.2 (the right end moves 12 cells, across the boxes' boundaries), FLIP and
  // FMPM(4): the fields to 1e-10 of their largest entries, the wall's reaction to 1e-10 of its
  // largest over the run.
  constexpr double rate = 0.025;
  Model whole(Grid(2, {-1, -1, 0}, {0.25, 0.25, 1}, {60, 12, 1}));
  whole.materials = {smpm::test::material("bar", MaterialModel::NeoHookean, 0.75, 0)};
  whole.particles = make_block(whole.grid, {0, 0, 0}, {10, 1, 0}, {2, 2, 1}, 1.0, 0);
  whole.particles.V.col(0) = rate * whole.particles.X.col(0);
  MovingWall wall;
  wall.position = [](double t) { return 10 * (1 + rate * t); };
  wall.velocity = [](double) { return 10 * rate; };
  wall.gradient = [](double t) { return rate / (1 + rate * t); };
  wall.depth = 0.25;
  wall.label = "right wall";
  whole.bcs.add_wall(wall);
  StepOptions flip;
  flip.shape = Shape::GIMP;
  StepOptions fmpm4 = flip;
  fmpm4.velocity = VelocityUpdate::FMPM;
  fmpm4.fmpm.order = 4;
  for (const StepOptions& options : {flip, fmpm4}) {
    CAPTURE(to_string(options.velocity));
    const sp::DistributedGrid grid(whole.grid);
    const double dt = stable_time_step(whole, 0.2);
    sp::RankModel local = sp::distribute(grid, whole);
    sp::DistributedStepper dist(grid, options);
    long moved = 0;
    double max_reaction = 0;
    std::vector<double> reactions;
    for (int s = 0; s < 200; ++s) {
      moved += long(dist.step(local, dt));
      reactions.push_back(dist.reactions().at(0));
      max_reaction = std::max(max_reaction, std::abs(reactions.back()));
    }
    const Particles gathered = sp::gather_particles(grid, local);
    if (grid.size() > 1)
      CHECK(moved > 0);
    if (rank() != 0)
      continue;
    Model serial = whole;
    Stepper stepper(options);
    double worst = 0;
    for (int s = 0; s < 200; ++s) {
      stepper.step(serial, dt);
      worst = std::max(worst, std::abs(stepper.reactions().at(0) - reactions[size_t(s)]));
    }
    CHECK(max_reaction > 0);
    CHECK(worst <= 1e-10 * max_reaction);
    const Particles& P = serial.particles;
    CHECK(relative(gathered.X, P.X) < 1e-10);
    CHECK(relative(gathered.V, P.V) < 1e-10);
    CHECK(relative(gathered.F, P.F) < 1e-10);
    CHECK(relative(gathered.stress, P.stress) < 1e-10);
  }
}

TEST_CASE("a rigid piston across ranks drives the serial nodes", "[petsc][run]") {
  // The bar of FMPM 2026 §3.3 at rest, fixed at x = 0, compressed by a rigid piston of particles
  // on [40, 44] moving in at 0.2 (10% of the bar's wave speed; tests/lib/test_rigid.cpp's
  // piston, faster, so that it crosses the boxes' boundaries): the piston's nodes are those its
  // particles reach on any rank (summed over the ranks), so every rank whose window holds one
  // sets the piston's velocity there. 300 steps at C = 0.2, FLIP and FMPM(4), CPDI: the fields
  // to 1e-10 of their largest entries, the piston's reaction (the force it applies) at every
  // step to 1e-10 of its largest.
  BarSetup setup;
  setup.v0 = 0;
  setup.cells_right = 8;
  Model whole = vibrating_bar(setup);
  Material piston;
  piston.name = "piston";
  piston.model = MaterialModel::Rigid;
  piston.density = 0.5;
  whole.materials.push_back(piston);
  whole.particles.append(make_block(whole.grid, {40, 0, 0}, {44, 0, 0}, {2, 1, 1}, 0.5, 1));
  RigidMotion motion;
  motion.material = 1;
  motion.velocity[0] = [](double) { return -0.2; };
  motion.label = "material.piston";
  whole.rigid.push_back(motion);
  StepOptions flip;
  flip.shape = Shape::CPDI;
  StepOptions fmpm4 = flip;
  fmpm4.velocity = VelocityUpdate::FMPM;
  fmpm4.fmpm.order = 4;
  for (const StepOptions& options : {flip, fmpm4}) {
    CAPTURE(to_string(options.velocity));
    const sp::DistributedGrid grid(whole.grid);
    const double dt = stable_time_step(whole, 0.2);
    sp::RankModel local = sp::distribute(grid, whole);
    sp::DistributedStepper dist(grid, options);
    long moved = 0;
    std::vector<double> reactions;
    for (int s = 0; s < 300; ++s) {
      moved += long(dist.step(local, dt));
      reactions.push_back(dist.reactions().back()); // the piston's, along x
    }
    const Particles gathered = sp::gather_particles(grid, local);
    if (grid.size() > 1)
      CHECK(moved > 0);
    if (rank() != 0)
      continue;
    Model serial = whole;
    Stepper stepper(options);
    double worst = 0, largest = 0;
    for (int s = 0; s < 300; ++s) {
      stepper.step(serial, dt);
      worst = std::max(worst, std::abs(stepper.reactions().back() - reactions[size_t(s)]));
      largest = std::max(largest, std::abs(stepper.reactions().back()));
    }
    CHECK(largest > 0);
    CHECK(worst <= 1e-10 * largest);
    const Particles& P = serial.particles;
    CHECK(relative(gathered.X, P.X) < 1e-10);
    CHECK(relative(gathered.V, P.V) < 1e-10);
    CHECK(relative(gathered.F, P.F) < 1e-10);
    CHECK(relative(gathered.stress, P.stress) < 1e-10);
  }
}

TEST_CASE("loads across ranks follow their particles", "[petsc][run]") {
  // The drifting plate with a body force b = (0, −0.1 − 0.02 x) on the particles of its left
  // half and a traction (0.3 cos t, 0.1) on its +x face (the exposed faces of its last column,
  // their initial areas): each rank loads the particles it holds, named by their index there and
  // named again after every migration (RankModel::loads). 200 steps at C = 0.2, FLIP and FMPM(4):
  // the fields to 1e-10 of their largest entries, the energies and momentum to 1e-12.
  Model whole = plate_model();
  const Particles& P0 = whole.particles;
  std::vector<Index> left, all(size_t(P0.size()));
  for (Index p = 0; p < P0.size(); ++p) {
    all[size_t(p)] = p;
    if (P0.X(p, 0) < 6)
      left.push_back(p);
  }
  ParticleLoad body;
  body.kind = LoadKind::BodyForce;
  body.particles = left;
  body.label = "body";
  body.value = [](double, const Field& x, Field& b) {
    for (Index k = 0; k < x.rows(); ++k) {
      b(k, 0) = 0;
      b(k, 1) = -0.1 - 0.02 * x(k, 0);
    }
  };
  ParticleLoad traction;
  traction.kind = LoadKind::Traction;
  traction.particles = exposed_face(P0, all, 0, 1);
  traction.axis = 0;
  traction.side = 1;
  traction.label = "traction";
  traction.area.resize(Index(traction.particles.size()));
  for (size_t k = 0; k < traction.particles.size(); ++k)
    traction.area[Index(k)] = face_area(P0, traction.particles[k], 0);
  traction.value = [](double t, const Field& x, Field& b) {
    for (Index k = 0; k < x.rows(); ++k) {
      b(k, 0) = 0.3 * std::cos(t);
      b(k, 1) = 0.1;
    }
  };
  REQUIRE(traction.particles.size() == 12);
  whole.loads = {body, traction};
  StepOptions flip;
  flip.shape = Shape::GIMP;
  StepOptions fmpm4 = flip;
  fmpm4.velocity = VelocityUpdate::FMPM;
  fmpm4.fmpm.order = 4;
  for (const StepOptions& options : {flip, fmpm4}) {
    CAPTURE(to_string(options.velocity));
    const sp::DistributedGrid grid(whole.grid);
    const double dt = stable_time_step(whole, 0.2);
    sp::RankModel local = sp::distribute(grid, whole);
    sp::DistributedStepper dist(grid, options);
    long moved = 0;
    for (int s = 0; s < 200; ++s)
      moved += long(dist.step(local, dt));
    const Energies e = dist.energies(local);
    const Particles gathered = sp::gather_particles(grid, local);
    if (grid.size() > 1)
      CHECK(moved > 0);
    if (rank() != 0)
      continue;
    Model serial = whole;
    Stepper stepper(options);
    for (int s = 0; s < 200; ++s)
      stepper.step(serial, dt);
    const Energies es = stepper.energies(serial);
    const Particles& P = serial.particles;
    CHECK(relative(gathered.X, P.X) < 1e-10);
    CHECK(relative(gathered.V, P.V) < 1e-10);
    CHECK(relative(gathered.F, P.F) < 1e-10);
    CHECK(relative(gathered.stress, P.stress) < 1e-10);
    CHECK(e.kinetic == smpm::test::approx(es.kinetic, 0, 1e-12));
    CHECK(e.strain == smpm::test::approx(es.strain, 0, 1e-12));
    CHECK((e.momentum - es.momentum).norm() < 1e-12 * es.momentum.norm());
    // the loads' impulse: the body force's alone is about −0.2 × 12 × 3.4 along y
    CHECK(std::abs(es.momentum[1] - whole.particles.mass.dot(whole.particles.V.col(1))) > 1);
  }
}

TEST_CASE("migration moves every column to the owner of the particle's cell", "[petsc][run]") {
  // Every particle to the last rank's box (the others left without particles), then each jumped
  // by (7.3, 5.1) cells (across one or more boxes in one migration), then back: each rank ends
  // with exactly the particles whose cell it owns, in ascending global id, and the gathered set
  // equals the original in every column (the positions as set).
  Model whole = plate_model();
  whole.particles.temperature = Eigen::VectorXd::LinSpaced(whole.particles.size(), 300, 400);
  whole.particles.plastic_strain = Eigen::VectorXd::LinSpaced(whole.particles.size(), 0, 0.1);
  for (Index p = 0; p < whole.particles.size(); ++p) {
    whole.particles.F(p, 1) = 0.001 * double(p); // a distinct F and σ per particle
    whole.particles.stress(p, 3) = -0.5 * double(p);
  }
  const sp::DistributedGrid grid(whole.grid);
  sp::RankModel local = sp::distribute(grid, whole);
  const sp::WindowSums sums(grid);
  auto check_owned = [&](const Field& X_expected) {
    const Particles& P = local.model.particles;
    long owned = 0;
    for (Index p = 0; p < P.size(); ++p)
      owned += grid.owns_cell(grid.cell_of(P.X.row(p).data())) ? 1 : 0;
    CHECK(owned == long(P.size()));
    CHECK(std::is_sorted(local.ids.begin(), local.ids.end()));
    CHECK(all_sum(long(P.size())) == long(whole.particles.size()));
    const Particles g = sp::gather_particles(grid, local);
    if (rank() == 0) {
      CHECK(relative(g.X, X_expected) == 0);
      CHECK(relative(g.V, whole.particles.V) == 0);
      CHECK(relative(g.F, whole.particles.F) == 0);
      CHECK(relative(g.stress, whole.particles.stress) == 0);
      CHECK(g.mass == whole.particles.mass);
      CHECK(g.volume0 == whole.particles.volume0);
      CHECK(g.material == whole.particles.material);
      CHECK(relative(g.half_length, whole.particles.half_length) == 0);
      REQUIRE(g.temperature.size() == whole.particles.size());
      CHECK(g.temperature == whole.particles.temperature);
      CHECK(g.plastic_strain == whole.particles.plastic_strain);
    }
  };
  // All to the cell at the grid's far corner: the last rank's box.
  Field far = whole.particles.X;
  far.col(0).setConstant(22.5);
  far.col(1).setConstant(14.5);
  for (Index p = 0; p < local.model.particles.size(); ++p)
    local.model.particles.X.row(p) = far.row(local.ids[size_t(p)]);
  const long on_last = all_sum(grid.rank() == grid.size() - 1 ? long(local.ids.size()) : 0);
  const Index moved = sp::migrate(grid, sums, local);
  CHECK(long(moved) == long(whole.particles.size()) - on_last);
  if (grid.size() > 1)
    CHECK((grid.rank() == grid.size() - 1) == (local.model.particles.size() > 0));
  check_owned(far);
  // Jumps of several boxes at once.
  Field jumped = whole.particles.X;
  jumped.col(0).array() += 7.3;
  jumped.col(1).array() += 5.1;
  for (Index p = 0; p < local.model.particles.size(); ++p)
    local.model.particles.X.row(p) = jumped.row(local.ids[size_t(p)]);
  sp::migrate(grid, sums, local);
  check_owned(jumped);
  for (Index p = 0; p < local.model.particles.size(); ++p)
    local.model.particles.X.row(p) = whole.particles.X.row(local.ids[size_t(p)]);
  sp::migrate(grid, sums, local);
  check_owned(whole.particles.X);
}

TEST_CASE("energies after particles swap ranks in equal numbers", "[petsc][run]") {
  // Two 2 × 2-particle blocks in the lowest row of boxes, one crossing the first boundary
  // between boxes to the right and one to the left in the same step (uniform velocities, so the
  // grid moves each exactly one cell): the two ranks there swap four particles and keep their
  // counts. Each particle has its own F (so its own W(F)) and volume: the energies after the
  // step are those of the particles each rank now holds (1e-14), not of the densities the
  // stress update stored for the particles it held before.
  Model whole(Grid(2, {0, 0, 0}, {1, 1, 1}, {24, 16, 1}));
  whole.materials = {smpm::test::material("soft", MaterialModel::Linear, 1e-4, 0.3)};
  whole.bcs = BoundaryConditions::none(whole.grid);
  const sp::DistributedGrid grid(whole.grid);
  int boundary = 1; // the first cell of the next box along x in the lowest row
  while (boundary < 23 && grid.owner_of_cell({boundary, 0, 0}) == grid.owner_of_cell({0, 0, 0}))
    ++boundary;
  const double xb = boundary;
  Particles right = make_block(whole.grid, {xb - 1, 1, 0}, {xb, 2, 0}, {2, 2, 1}, 1.0, 0);
  Particles left = make_block(whole.grid, {xb, 4, 0}, {xb + 1, 5, 0}, {2, 2, 1}, 1.0, 0);
  right.V.col(0).setConstant(1.0);
  left.V.col(0).setConstant(-1.0);
  whole.particles = right;
  whole.particles.append(left);
  for (Index p = 0; p < whole.particles.size(); ++p) {
    whole.particles.F(p, 0) = 1 + 0.01 * double(p % 5);
    whole.particles.volume0[p] *= 1 + 0.2 * double(p % 3);
  }
  StepOptions flip;
  flip.shape = Shape::Linear;
  sp::RankModel local = sp::distribute(grid, whole);
  sp::DistributedStepper dist(grid, flip);
  const Index moved = dist.step(local, 1.0);
  if (grid.size() > 1)
    CHECK(moved == 8);
  CHECK(all_sum(long(local.model.particles.size())) == 8);
  const double strain = dist.energies(local).strain;
  const double here = energies(local.model).strain;
  double total = 0;
  MPI_Allreduce(&here, &total, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  CHECK(total > 0);
  CHECK(strain == smpm::test::approx(total, 0, 1e-14));
}

TEST_CASE("a failure on one rank stops every rank at the same step", "[petsc][run]") {
  // The bar's last particle (global id 79, on the last rank, where its index is smaller on 2 or
  // more ranks) sent off the grid: that rank's step throws the serial NumericalError (step 1,
  // its support off the grid, naming particle 79 as the serial run does), every other rank
  // FailedElsewhere, and no rank waits.
  const Model whole = bar_model();
  const sp::DistributedGrid grid(whole.grid);
  sp::RankModel local = sp::distribute(grid, whole);
  StepOptions flip;
  flip.shape = Shape::GIMP;
  sp::DistributedStepper dist(grid, flip);
  const Index last = whole.particles.size() - 1;
  const bool holder = !local.ids.empty() && local.ids.back() == last;
  if (holder)
    local.model.particles.X(Index(local.ids.size()) - 1, 0) = 1e6;
  long here = 0, elsewhere = 0;
  try {
    dist.step(local, 0.01);
  } catch (const FailedElsewhere&) {
    ++elsewhere;
  } catch (const NumericalError& e) {
    ++here;
    CHECK(e.step() == 1);
    CHECK_THAT(std::string(e.what()), Catch::Contains("particle " + std::to_string(last) + " "));
  }
  CHECK(here == (holder ? 1 : 0));
  CHECK(all_sum(here) == 1);
  CHECK(all_sum(elsewhere) == grid.size() - 1);
}
