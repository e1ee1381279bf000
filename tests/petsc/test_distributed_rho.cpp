// SPDX-License-Identifier: BSD-3-Clause
// ρ(T) of the linearised step and C* across ranks against the serial spectral_radius and
// critical_courant (FMPM 2026 §3.3), on 1 to 3 ranks ([rho]: ctest leaves them out on 4). The
// eigensolvers stop at 1e-10, so the radii are compared to 1e-8.
#include "mpi_support.hpp"
#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/petsc.hpp>

#include <cstdio>

using namespace smpm;
using smpm::test::all_sum;
using smpm::test::rank;
namespace sp = smpm::petsc;

namespace {

// The free-vibrating bar of FMPM 2026 §3.3 (80 particles), and a 2D plate: an 8 × 4-cell block
// of 2 × 2 particles per cell on a 12 × 8-cell grid, fixed on its left face, with a sinusoidal
// velocity (768 rows of T: the serial spectral_radius takes T's dense eigenvalues).
Model plate_model() {
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {12, 8, 1}));
  model.materials = {smpm::test::material("plate", MaterialModel::Linear, 100, 0.3)};
  model.particles = make_block(model.grid, {2, 2, 0}, {10, 6, 0}, {2, 2, 1}, 1.0, 0);
  model.bcs = BoundaryConditions::none(model.grid);
  fix_plane(model.grid, 0, 2.0, {true, true, false}, model.bcs);
  for (Index p = 0; p < model.particles.size(); ++p)
    model.particles.V(p, 1) = 0.01 * std::sin(0.2 * model.particles.X(p, 0));
  return model;
}

// The plate on a grid twice as long: the ranks whose boxes lie right of x = 12 own no particle.
Model left_plate_model() {
  Model model = plate_model();
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {24, 8, 1});
  model.grid = g;
  model.bcs = BoundaryConditions::none(g);
  fix_plane(g, 0, 2.0, {true, true, false}, model.bcs);
  return model;
}

} // namespace

TEST_CASE("rho(T) across ranks equals the serial spectral radius", "[petsc][rho]") {
  // FLIP, FMPM(4), FMPM(16), blended FMPM(8), periodic FMPM(4) (C_X = 2) and the exact update
  // (m̃⁻¹ by KSP across ranks) on the bar, the plate and the plate on a longer grid (ranks
  // without particles) at a stable and an unstable Courant number: SLEPc's |λ|max against the
  // serial dense eigenvalues (CHOLMOD for the exact update), 1e-8.
  const Model bar = vibrating_bar({});
  const Model plate = plate_model();
  const Model left_plate = left_plate_model();
  {
    const sp::DistributedGrid grid(left_plate.grid);
    const long without = all_sum(grid.owned_particles(left_plate.particles).empty() ? 1 : 0);
    CHECK((grid.size() == 1 || without >= 1)); // the case it is there for: ranks without particles
  }
  std::vector<std::pair<std::string, StepOptions>> schemes;
  StepOptions base;
  base.shape = Shape::GIMP;
  schemes.push_back({"FLIP", base});
  for (const FmpmOptions& f : {FmpmOptions{.order = 4}, FmpmOptions{.order = 16},
                               FmpmOptions{.order = 8, .blend_alpha = 0.8, .blend_every = 2}}) {
    StepOptions o = base;
    o.velocity = VelocityUpdate::FMPM;
    o.fmpm = f;
    schemes.push_back(
        {"FMPM(" + std::to_string(f.order) + ") alpha " + std::to_string(f.blend_alpha), o});
  }
  StepOptions periodic = base;
  periodic.velocity = VelocityUpdate::FMPM;
  periodic.fmpm.order = 4;
  periodic.periodic_cx = 2;
  schemes.push_back({"periodic FMPM(4)", periodic});
  StepOptions exact = base;
  exact.velocity = VelocityUpdate::Exact;
  exact.exact_solver = exact_solver_factory(); // the serial reference's; replaced across ranks
  schemes.push_back({"exact", exact});
  for (const Model* model : {&bar, &plate, &left_plate})
    for (double courant : {0.5, 1.3})
      for (const auto& [name, options] : schemes) {
        CAPTURE(model->grid.dim(), courant, name);
        const double dt = stable_time_step(*model, courant);
        // The serial reference on rank 0 (dense eigenvalues of T), sent to the others.
        double serial_rho = 0;
        if (rank() == 0)
          serial_rho = spectral_radius(LinearizedStep(*model, options, dt)).rho_T;
        MPI_Bcast(&serial_rho, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
        const sp::DistributedGrid grid(model->grid);
        const SpectralRadius dist = sp::spectral_radius(grid, *model, options, dt);
        CHECK(dist.status == SpectralStatus::Converged);
        CHECK(dist.rho_T == smpm::test::approx(serial_rho, 0, 1e-8));
      }
}

TEST_CASE("rho(T) above the dense limit follows the serial rule", "[petsc][rho]") {
  // A plate of 512 particles (3072 rows of T, above kDenseRadiusRows): the serial
  // spectral_radius measures the growth by power iteration (ρ = 1 within 10⁻³) and resolves an
  // eigenvalue that stands out by Arnoldi (Spectra), and so does the distributed one (SLEPc).
  // Stable (C = 0.5): ρ = 1 exactly on both; unstable (C = 1.3): the dominant |λ| to 1e-8.
  Model plate = plate_model();
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {20, 12, 1});
  plate.grid = g;
  plate.particles = make_block(g, {2, 2, 0}, {18, 10, 0}, {2, 2, 1}, 1.0, 0);
  for (Index p = 0; p < plate.particles.size(); ++p)
    plate.particles.V(p, 1) = 0.01 * std::sin(0.2 * plate.particles.X(p, 0));
  plate.bcs = BoundaryConditions::none(g);
  fix_plane(g, 0, 2.0, {true, true, false}, plate.bcs);
  StepOptions flip;
  flip.shape = Shape::GIMP;
  StepOptions fmpm4 = flip;
  fmpm4.velocity = VelocityUpdate::FMPM;
  fmpm4.fmpm.order = 4;
  for (const StepOptions& options : {flip, fmpm4})
    for (double courant : {0.5, 1.3}) {
      CAPTURE(to_string(options.velocity), courant);
      const double dt = stable_time_step(plate, courant);
      double serial[2] = {0, 0};
      if (rank() == 0) {
        const LinearizedStep T(plate, options, dt);
        REQUIRE(T.rows() > kDenseRadiusRows);
        const SpectralRadius r = spectral_radius(T);
        serial[0] = r.rho_T;
        serial[1] = double(r.status == SpectralStatus::Converged);
      }
      MPI_Bcast(serial, 2, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
      REQUIRE(serial[1] == 1.0);
      const sp::DistributedGrid grid(plate.grid);
      const SpectralRadius dist = sp::spectral_radius(grid, plate, options, dt);
      CHECK(dist.status == SpectralStatus::Converged);
      CHECK(dist.rho_T == smpm::test::approx(serial[0], 0, 1e-8));
      if (courant == 0.5)
        CHECK(dist.rho_T == 1.0);
      else
        CHECK(dist.rho_T > 1.01);
    }
}

TEST_CASE("the step across ranks refuses what it cannot sum", "[petsc][rho]") {
  // A one-process exact solver would invert each rank's partial sums: refused, as are XPIC and
  // the velocity-gradient transfer, before any product (every rank throws the same InputError).
  const Model bar = vibrating_bar({});
  const sp::DistributedGrid grid(bar.grid);
  sp::DistributedOperators ops;
  sp::assemble(grid, bar.particles, Shape::GIMP, ops);
  Model local = bar;
  local.particles = sp::select_particles(bar.particles, ops.particles);
  sp::WindowSums sums(grid, ops);
  StepOptions exact;
  exact.shape = Shape::GIMP;
  exact.velocity = VelocityUpdate::Exact;
  exact.exact_solver = exact_solver_factory();
  CHECK_THROWS_AS(LinearizedStep(local, exact, 0.1, sums), InputError);
  StepOptions xpic = exact;
  xpic.velocity = VelocityUpdate::XPIC;
  CHECK_THROWS_AS(LinearizedStep(local, xpic, 0.1, sums), InputError);
  StepOptions gradient = exact;
  gradient.velocity = VelocityUpdate::FLIP;
  gradient.transfer = Transfer::VelocityGradient;
  CHECK_THROWS_AS(LinearizedStep(local, gradient, 0.1, sums), InputError);
  exact.exact_solver =
      sp::distributed_mass_solver_factory(grid, ops, sums, sp::ExactMethod::CgBlockJacobiIcc);
  CHECK_NOTHROW(LinearizedStep(local, exact, 0.1, sums));
}

TEST_CASE("C* across ranks equals the serial critical Courant number", "[petsc][rho]") {
  // The serial search (critical_courant_search) on ρ(T) across ranks: the same grid point of
  // C (resolution 1e-3) as the serial critical_courant, FLIP and FMPM(4) on the bar with uGIMP
  // (0.7555 and 0.5547).
  const Model bar = vibrating_bar({});
  StepOptions flip;
  flip.shape = Shape::GIMP;
  StepOptions fmpm4 = flip;
  fmpm4.velocity = VelocityUpdate::FMPM;
  fmpm4.fmpm.order = 4;
  const std::vector<std::pair<const Model*, StepOptions>> cases{{&bar, flip}, {&bar, fmpm4}};
  for (const auto& [model, options] : cases) {
    CAPTURE(model->grid.dim(), to_string(options.velocity));
    double serial = 0;
    if (rank() == 0)
      serial = critical_courant(*model, options).critical_courant;
    MPI_Bcast(&serial, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    const sp::DistributedGrid grid(model->grid);
    const CriticalCourant dist = sp::critical_courant(grid, *model, options);
    CHECK(dist.critical_courant == serial);
    CHECK(dist.non_finite == 0);
    if (rank() == 0)
      std::printf("C* %s on the bar: %.4f (serial %.4f), %d evaluations\n",
                  std::string(to_string(options.velocity)).c_str(), dist.critical_courant, serial,
                  dist.evaluations);
  }
}
