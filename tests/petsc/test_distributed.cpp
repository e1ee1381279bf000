// SPDX-License-Identifier: BSD-3-Clause
// The distributed operators and FMPM(k) against the serial library on the same particles, on
// every number of ranks ctest starts (1 to 4). The sums run in another order across ranks, so
// the comparisons are relative, with the tolerances of the component's specification: 1e-14 for
// the operators (a few roundings of sums of O(10) terms), 1e-12 for FMPM(k) up to k = 20.
#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/petsc.hpp>
#include <sparsempm/spectrum.hpp>

#include <Eigen/Dense>

#include <cstdio>

using namespace smpm;
namespace sp = smpm::petsc;

namespace {

double all_max(double x) {
  double y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return y;
}

long all_sum(long x) {
  long y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  return y;
}

int rank() {
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

// The largest difference of the rows of a local operator (window columns) from the serial
// operator's rows of the same particles (whole-grid columns), relative to the largest entry.
double row_error(const SparseRowMatrix& local, const sp::DistributedOperators& d,
                 const SparseRowMatrix& serial) {
  double err = 0;
  for (Index r = 0; r < local.rows(); ++r) {
    Eigen::VectorXd row = Eigen::VectorXd::Zero(serial.cols());
    for (SparseRowMatrix::InnerIterator it(local, r); it; ++it)
      row[d.local.whole_node(it.col())] += it.value();
    for (SparseRowMatrix::InnerIterator it(serial, d.particles[size_t(r)]); it; ++it)
      row[it.col()] -= it.value();
    err = std::max(err, row.cwiseAbs().maxCoeff());
  }
  double scale = 0;
  for (Index k = 0; k < serial.nonZeros(); ++k)
    scale = std::max(scale, std::abs(serial.valuePtr()[k]));
  return all_max(err) / scale;
}

struct OperatorErrors {
  double S = 0, G = 0, m = 0, mt = 0;
  long particles = 0; // particles owned over all ranks
};

OperatorErrors operator_errors(const Grid& g, const Particles& P, Shape shape, int fields,
                               const Eigen::VectorXi* field) {
  Operators s;
  assemble(g, P, shape, s, fields, field);
  const SparseMatrix mt = consistent_mass(s);
  const sp::DistributedGrid dg(g, fields);
  sp::DistributedOperators d;
  sp::assemble(dg, P, shape, d, field);
  OperatorErrors e;
  e.particles = all_sum(long(d.particles.size()));
  e.S = row_error(d.local.S, d, s.S);
  for (int a = 0; a < g.dim(); ++a)
    e.G = std::max(e.G, row_error(d.local.G[size_t(a)], d, s.G[size_t(a)]));
  const Field m = sp::gather(dg, d.m, 1);
  const SparseMatrix mt_d = sp::gather(dg, d.mt);
  if (rank() == 0) {
    e.m = (m.col(0) - s.m).cwiseAbs().maxCoeff() / s.m.maxCoeff();
    e.mt = (Eigen::MatrixXd(mt_d) - Eigen::MatrixXd(mt)).cwiseAbs().maxCoeff() /
           Eigen::MatrixXd(mt).cwiseAbs().maxCoeff();
  }
  return e;
}

// The fields of the two-field cases: alternate particles.
Eigen::VectorXi alternate(Index n) {
  Eigen::VectorXi f(n);
  for (Index p = 0; p < n; ++p)
    f[p] = int(p % 2);
  return f;
}

} // namespace

TEST_CASE("gathered S, G, m and m~ equal the serial operators", "[petsc][operators]") {
  // Random deformed clouds 3 cells inside a 10-cell grid: on 3 and 4 ranks the ranks at the ends
  // own no particle in 1D. Two fields: alternate particles.
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI})
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const Grid g = smpm::test::test_grid(dim, 10);
        const Particles P = smpm::test::random_cloud(g, 60, 31u * dim, 3.0, true);
        const Eigen::VectorXi f = alternate(P.size());
        const OperatorErrors e = operator_errors(g, P, shape, fields, &f);
        CHECK(e.particles == P.size()); // each particle owned by exactly one rank
        CHECK(e.S <= 1e-14);
        CHECK(e.G <= 1e-14);
        CHECK(e.m <= 1e-14);
        CHECK(e.mt <= 1e-14);
      }
}

TEST_CASE("particles on rank boundaries and ranks without particles", "[petsc][operators]") {
  // A particle on every node of the left half of the grid (so on every boundary between the
  // ranks' boxes there), none in the right half: the right-hand ranks own no particle.
  for (int dim = 1; dim <= 3; ++dim) {
    CAPTURE(dim);
    const int cells = dim == 3 ? 6 : 12;
    const Grid g(dim, {0, 0, 0}, {1, 1, 1}, {cells, cells, cells});
    Particles P = make_block(g, {0.5, 0.5, 0.5}, {cells / 2.0 + 0.5, cells - 1.5, cells - 1.5},
                             {1, 1, 1}, 1.0, 0);
    for (Index p = 0; p < P.size(); ++p)
      for (int a = 0; a < dim; ++a)
        P.X(p, a) = std::round(P.X(p, a) + 0.5); // onto the nodes 1 ... cells / 2 + 1
    const OperatorErrors e = operator_errors(g, P, Shape::GIMP, 1, nullptr);
    CHECK(e.particles == P.size());
    CHECK(e.S <= 1e-14);
    CHECK(e.m <= 1e-14);
    CHECK(e.mt <= 1e-14);
  }
}

namespace {

struct LoopCase {
  std::string name;
  FmpmOptions opt;
  bool bcs = false;
};

// A fixed plane through the body and a prescribed, varying velocity on another.
BoundaryConditions plane_conditions(const Grid& g) {
  BoundaryConditions bcs = BoundaryConditions::none(g);
  fix_plane(g, 0, g.origin(0) + 4 * g.cell_size(0), {true, g.dim() > 1, false}, bcs);
  VelocityCondition push;
  push.nodes = nodes_on_plane(g, 0, g.origin(0) + 6 * g.cell_size(0));
  push.direction = Eigen::Vector3d::UnitX();
  push.value = [](double t, const Eigen::Vector3d& x) { return 0.25 + t + 0.1 * x[0]; };
  push.label = "push";
  bcs.conditions.push_back(push);
  return bcs;
}

// max |v_distributed − v_serial| / max |v_serial| of the grid velocity from p⁺ = Sᵀ M V
// (updated_velocity with the lumped BCs), and whether the orders reached agree.
std::pair<double, bool> loop_error(const Grid& g, const Particles& P, Shape shape, int fields,
                                   const Eigen::VectorXi* field, const LoopCase& c) {
  const BoundaryConditions bcs = plane_conditions(g);
  // Without conditions the loop fuses Eqs. 6 and 5 (no hook between them).
  const LoopConstraints lc{&g, c.bcs ? &bcs : nullptr, 0.5};
  Operators s;
  assemble(g, P, shape, s, fields, field);
  ConsistentMass mt;
  assemble_consistent_mass(s, mt);
  Field p;
  map_momentum(particle_operators(s), P.V, p);
  Field v;
  FmpmWorkspace w;
  const FmpmReport rs = updated_velocity(s, &mt.matrix, c.opt, lc, true, 1e-3, p, nullptr, v, w);

  const sp::DistributedGrid dg(g, fields);
  sp::DistributedOperators d;
  sp::assemble(dg, P, shape, d, field);
  const Particles own = sp::select_particles(P, d.particles);
  sp::OwnedVec p_d = sp::momentum(dg, d, own.V);
  sp::OwnedVec v_d = sp::node_vector(dg, g.dim());
  sp::DistributedFmpmWorkspace wd;
  const FmpmReport rd = sp::updated_velocity(dg, d, c.opt, lc, p_d, v_d, wd);
  const Field vd = sp::gather(dg, v_d, g.dim());
  double err = 0;
  if (rank() == 0)
    err = (vd - v).cwiseAbs().maxCoeff() / v.cwiseAbs().maxCoeff();
  return {err, rd.order == rs.order};
}

} // namespace

TEST_CASE("FMPM(k) across ranks equals the serial loop", "[petsc][fmpm]") {
  std::vector<LoopCase> cases;
  for (int k : {1, 4, 20}) {
    cases.push_back({"plain", {.order = k}, false});
    cases.push_back({"blended", {.order = k, .blend_alpha = 0.9, .blend_every = 3}, false});
    for (BCMethod method :
         {BCMethod::Incremental, BCMethod::Lumped, BCMethod::Velocity, BCMethod::Combined})
      cases.push_back({std::string("bcs ") + std::string(to_string(method)),
                       {.order = k, .bc_method = method},
                       true});
  }
  cases.push_back({"dynamic means",
                   {.order = 20, .metric = ConvergenceMetric::Means, .dynamic_limit = 1e-3},
                   true});
  cases.push_back({"dynamic changes",
                   {.order = 20, .metric = ConvergenceMetric::Changes, .dynamic_limit = 1e-2},
                   false});
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI})
      for (int fields : {1, 2}) {
        const int cells = dim == 3 ? 9 : 12;
        const Grid g(dim, {0, 0, 0}, {1, 0.5, 2}, {cells, cells, cells});
        Particles P = smpm::test::jittered_lattice(g, 2, cells - 4, dim == 3 ? 2 : 3, 0.2, 7u);
        std::mt19937 rng(5u * dim);
        std::uniform_real_distribution<double> u(-1, 1);
        for (Index q = 0; q < P.V.size(); ++q)
          P.V.data()[q] = u(rng);
        const Eigen::VectorXi f = alternate(P.size());
        for (const LoopCase& c : cases) {
          CAPTURE(dim, to_string(shape), fields, c.name, c.opt.order);
          const auto [err, same_order] = loop_error(g, P, shape, fields, &f, c);
          CHECK(err <= 1e-12);
          CHECK(same_order);
        }
      }
}

namespace {

// A body over cells 2 to cells − 2 of a grid of `cells` cells per axis (`ppc` particles per
// cell per axis), jittered, with random velocities.
Particles jittered_body(const Grid& g, unsigned seed, int ppc) {
  const int cells = g.cells(0);
  Particles P = smpm::test::jittered_lattice(g, 2, cells - 4, ppc, 0.2, seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Index q = 0; q < P.V.size(); ++q)
    P.V.data()[q] = u(rng);
  return P;
}

} // namespace

TEST_CASE("the exact solve across ranks equals CHOLMOD", "[petsc][exact]") {
  // Every method, with and without velocity BCs, with the regularisation and the mass cutoff,
  // one and two fields: max |v − v_CHOLMOD| / max |v_CHOLMOD| ≤ 1e-10.
  for (int dim = 1; dim <= 3; ++dim)
    for (int fields : {1, 2}) {
      const int cells = dim == 3 ? 9 : 12;
      const Grid g(dim, {0, 0, 0}, {1, 0.5, 2}, {cells, cells, cells});
      const Particles P = jittered_body(g, 3u + unsigned(dim), dim == 3 ? 2 : 3);
      const Eigen::VectorXi f = alternate(P.size());
      const BoundaryConditions bcs = plane_conditions(g);
      Operators s;
      assemble(g, P, Shape::GIMP, s, fields, &f);
      ConsistentMass mt;
      assemble_consistent_mass(s, mt);
      Field p;
      map_momentum(particle_operators(s), P.V, p);
      const sp::DistributedGrid dg(g, fields);
      sp::DistributedOperators d;
      sp::assemble(dg, P, Shape::GIMP, d, &f);
      const Particles own = sp::select_particles(P, d.particles);
      for (bool with_bcs : {false, true})
        for (const ExactOptions& exact : {ExactOptions{}, ExactOptions{.regularization = 0.1},
                                          ExactOptions{.mass_cutoff = 0.05}})
          for (sp::ExactMethod method :
               {sp::ExactMethod::CgJacobi, sp::ExactMethod::CgBlockJacobiIcc,
                sp::ExactMethod::CgGamg, sp::ExactMethod::MumpsCholesky}) {
            CAPTURE(dim, fields, with_bcs, exact.regularization, exact.mass_cutoff,
                    to_string(method));
            const LoopConstraints lc{&g, with_bcs ? &bcs : nullptr, 0.5};
            Field v;
            CholmodSolver(exact).solve(s, mt.matrix, lc, p, v);
            sp::OwnedVec p_d = sp::momentum(dg, d, own.V);
            sp::OwnedVec v_d = sp::node_vector(dg, dim);
            const sp::ExactSolveReport r =
                sp::exact_solve(dg, d, {.exact = exact, .method = method}, lc, p_d, v_d);
            const Field vd = sp::gather(dg, v_d, dim);
            if (rank() == 0)
              CHECK((vd - v).cwiseAbs().maxCoeff() <= 1e-10 * v.cwiseAbs().maxCoeff());
            CHECK(r.residual <= 1e-11);
          }
    }
}

TEST_CASE("the mass spectrum across ranks equals the serial one", "[petsc][spectrum]") {
  // ρ(A), λ_min(m⁻¹m̃) and cond(m̃) by SLEPc against the serial mass_spectrum (dense Eigen on
  // these few hundred active nodes): relative 1e-8. Two fields: the left and right halves of
  // the body. Three particles per cell per axis, so that m̃ is far from singular (quadratic
  // B-splines with two per cell in 3D: cond(m̃) ≈ 2e15, which no eigensolver resolves).
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI})
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const int cells = dim == 3 ? 7 : 12;
        const Grid g(dim, {0, 0, 0}, {1, 0.5, 2}, {cells, cells, cells});
        const Particles P = jittered_body(g, 9u, 3);
        Eigen::VectorXi f(P.size());
        for (Index p = 0; p < P.size(); ++p)
          f[p] = P.X(p, 0) < cells / 2.0 ? 0 : 1;
        Operators s;
        assemble(g, P, shape, s, fields, &f);
        ConsistentMass mt;
        assemble_consistent_mass(s, mt);
        const MassSpectrum serial = mass_spectrum(s, mt.matrix);
        const sp::DistributedGrid dg(g, fields);
        sp::DistributedOperators d;
        sp::assemble(dg, P, shape, d, &f);
        const MassSpectrum dist = sp::mass_spectrum(dg, d);
        CHECK(dist.active == serial.active);
        CHECK(dist.rho_A == smpm::test::approx(serial.rho_A, 0, 1e-8));
        CHECK(dist.min_eig_minv_mt == smpm::test::approx(serial.min_eig_minv_mt, 0, 1e-8));
        // cond(m̃) is known to 1e-8, or to its own conditioning: the reference's λ_min =
        // λ_max − λ_max(λ_max I − m̃) carries an error of a few ε λ_max (B-splines: cond ≈ 2e7).
        CHECK(dist.cond_mt ==
              smpm::test::approx(serial.cond_mt, 0, std::max(1e-8, 1e-14 * serial.cond_mt)));
      }
}

TEST_CASE("a PETSc error is one NumericalError with PETSc's message", "[petsc][errors]") {
  // PETSc's own text (the routine and its reason) instead of a traceback on stderr; an unknown
  // type is checked by PETSc's optimised build too (Debian's has no debugging checks).
  sp::OwnedMat a;
  SMPM_PETSC_CALL(MatCreate(PETSC_COMM_SELF, a.out()));
  CHECK_THROWS_AS(SMPM_PETSC_CALL(MatSetType(a, "no-such-type")), NumericalError);
  CHECK_THROWS_WITH(SMPM_PETSC_CALL(MatSetType(a, "no-such-type")),
                    Catch::Contains("MatSetType(a, \"no-such-type\"): PETSc error") &&
                        Catch::Contains("MatSetType: Unknown") && Catch::Contains("no-such-type"));
  // A grid whose node fields would overflow PETSc's indices is refused before the DMDA exists.
  if (sizeof(PetscInt) == 4)
    CHECK_THROWS_WITH(sp::DistributedGrid(Grid(3, {0, 0, 0}, {1, 1, 1}, {1100, 1100, 1100})),
                      Catch::Contains("1334633301 nodes x 1 fields x 3 components") &&
                          Catch::Contains("petsc64-dev"));
  // An unknown solver name names the valid ones.
  CHECK_THROWS_WITH(sp::exact_method_from_string("cholesky"),
                    Catch::Contains("cg-bjacobi-icc") && Catch::Contains("mumps-cholesky"));
}

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
          serial_rho = spectral_radius(LinearizedStep(*model, options, dt)).rho;
        MPI_Bcast(&serial_rho, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
        const sp::DistributedGrid grid(model->grid);
        const SpectralRadius dist = sp::spectral_radius(grid, *model, options, dt);
        CHECK(dist.status == SpectralStatus::Converged);
        CHECK(dist.rho == smpm::test::approx(serial_rho, 0, 1e-8));
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
        serial[0] = r.rho;
        serial[1] = double(r.status == SpectralStatus::Converged);
      }
      MPI_Bcast(serial, 2, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
      REQUIRE(serial[1] == 1.0);
      const sp::DistributedGrid grid(plate.grid);
      const SpectralRadius dist = sp::spectral_radius(grid, plate, options, dt);
      CHECK(dist.status == SpectralStatus::Converged);
      CHECK(dist.rho == smpm::test::approx(serial[0], 0, 1e-8));
      if (courant == 0.5)
        CHECK(dist.rho == 1.0);
      else
        CHECK(dist.rho > 1.01);
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
  const sp::WindowSums sums(grid, ops);
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
      serial = critical_courant(*model, options).courant;
    MPI_Bcast(&serial, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    const sp::DistributedGrid grid(model->grid);
    const CriticalCourant dist = sp::critical_courant(grid, *model, options);
    CHECK(dist.courant == serial);
    CHECK(dist.non_finite == 0);
    if (rank() == 0)
      std::printf("C* %s on the bar: %.4f (serial %.4f), %d evaluations\n",
                  std::string(to_string(options.velocity)).c_str(), dist.courant, serial,
                  dist.evaluations);
  }
}
