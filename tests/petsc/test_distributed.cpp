// SPDX-License-Identifier: BSD-3-Clause
// The distributed operators and FMPM(k) against the serial library on the same particles, on
// every number of ranks ctest starts (1 to 4). The sums run in another order across ranks, so
// the comparisons are relative, with the tolerances of the component's specification: 1e-14 for
// the operators (a few roundings of sums of O(10) terms), 1e-12 for FMPM(k) up to k = 20.
#include "mpi_support.hpp"
#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/petsc.hpp>
#include <sparsempm/spectrum.hpp>

#include <Eigen/Dense>

using namespace smpm;
using smpm::test::all_max;
using smpm::test::all_sum;
using smpm::test::rank;
namespace sp = smpm::petsc;

namespace {

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
    // The family's other members (fmpm.hpp, Polynomial): the same passes with a residual.
    for (Polynomial p :
         {Polynomial::Chebyshev, Polynomial::LeastSquares, Polynomial::ChebyshevSquared}) {
      FmpmOptions o{.order = k};
      o.polynomial = p;
      o.interval_low = 0.05;
      cases.push_back({std::string(to_string(p)), o, false});
      o.bc_method = BCMethod::Incremental;
      cases.push_back({std::string(to_string(p)) + " bcs", o, true});
    }
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
