// SPDX-License-Identifier: BSD-3-Clause
// The particles' migration across ranks (migrate, DMSwarm): every column to the owner of the
// particle's cell, the energies of the particles a rank holds after it, and a failure on one
// rank stopping every rank, on 1 to 4 ranks.
#include "run_support.hpp"

#include <sparsempm/petsc_run.hpp>

#include <algorithm>
#include <string>

using namespace smpm;
using smpm::test::all_sum;
using smpm::test::bar_model;
using smpm::test::plate_model;
using smpm::test::rank;
using smpm::test::relative;
namespace sp = smpm::petsc;

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
