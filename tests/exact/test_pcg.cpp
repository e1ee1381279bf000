// SPDX-License-Identifier: BSD-3-Clause
// The exact update by the preconditioned conjugate gradient (PcgSolver, exact.hpp) against
// CHOLMOD's factorisation: the same equations (velocity BCs, regularisation, mass cutoff), m̃⁻¹
// to the tolerance asked, and a refusal for the non-symmetric m̃_L.

#include "exact_setup.hpp"

#include <sparsempm/exact.hpp>

#include <Eigen/Dense>

using namespace smpm;

namespace {
using Setup = smpm::test::ExactSetup;
Setup setup() {
  return smpm::test::exact_setup();
}
// The relative distance of a PCG solve from CHOLMOD's, with the same options but the method.
double distance(const Setup& s, ExactOptions o, const LoopConstraints& bc) {
  Field exact, iterated;
  CholmodSolver(o).solve(s.ops, s.mt.matrix, bc, s.p, exact);
  o.method = ExactMethod::PCG;
  PcgSolver(o).solve(s.ops, s.mt.matrix, bc, s.p, iterated);
  return (iterated - exact).norm() / exact.norm();
}
} // namespace

TEST_CASE("PCG solves m~ v = p as CHOLMOD does, to its tolerance", "[exact][pcg]") {
  // ‖v − v*‖/‖v*‖ ≤ cond(m̃_FF) ‖r‖/‖b‖: with cond(m̃) of this CPDI lattice below 10³ and the
  // tolerance 1e-12, below 1e-9 (measured 1e-13 to 1e-11).
  const Setup s = setup();
  BoundaryConditions bcs;
  fix_plane(s.grid, 1, 3.0, {true, true, false}, bcs); // a fixed row of nodes
  const LoopConstraints fixed{&s.grid, &bcs, 0.0};
  for (const ExactPreconditioner pre :
       {ExactPreconditioner::Diagonal, ExactPreconditioner::IncompleteCholesky}) {
    ExactOptions o;
    o.preconditioner = pre;
    INFO("preconditioner " << to_string(pre));
    CHECK(distance(s, o, {}) < 1e-9);
    CHECK(distance(s, o, fixed) < 1e-9);
    o.regularization = 1e-3; // the blended (1 − ε) m̃ + ε m
    CHECK(distance(s, o, fixed) < 1e-9);
    o.regularization = 0;
    o.mass_cutoff = 0.2; // light nodes take p_i / m_i
    CHECK(distance(s, o, fixed) < 1e-9);
  }
}

TEST_CASE("PCG's residual follows its tolerance", "[exact][pcg]") {
  // The relative residual ‖p − m̃ v‖/‖p‖ on the active nodes is at most the tolerance (CG's
  // own stopping test, on the preconditioned system's residual, is ‖r‖ ≤ tol ‖b‖).
  const Setup s = setup();
  for (const double tol : {1e-4, 1e-8, 1e-12}) {
    ExactOptions o;
    o.method = ExactMethod::PCG;
    o.tolerance = tol;
    Field v;
    PcgSolver(o).solve(s.ops, s.mt.matrix, {}, s.p, v);
    Field r = Field(s.mt.matrix * Eigen::MatrixXd(v)) - s.p;
    for (Index i = 0; i < r.rows(); ++i)
      if (!s.ops.active[i])
        r.row(i).setZero();
    INFO("tolerance " << tol);
    CHECK(r.norm() <= tol * s.p.norm());
  }
}

TEST_CASE("PCG's solve_again iterates with the matrix of the last solve", "[exact][pcg]") {
  const Setup s = setup();
  ExactOptions o;
  o.method = ExactMethod::PCG;
  PcgSolver pcg(o);
  CholmodSolver cholmod;
  Field v, w;
  pcg.solve(s.ops, s.mt.matrix, {}, s.p, v);
  cholmod.solve(s.ops, s.mt.matrix, {}, s.p, w);
  const Field r = 0.5 * s.p;
  pcg.solve_again(r, v);
  cholmod.solve_again(r, w);
  CHECK((v - w).norm() < 1e-9 * w.norm());
}

TEST_CASE("PCG is refused for the non-symmetric m~_L, and by the factory", "[exact][pcg]") {
  ExactOptions o;
  o.method = ExactMethod::PCG;
  o.system = NodalSystem::GradientMass;
  CHECK_THROWS_AS(exact_solver_factory()(o), InputError);
  StepOptions step;
  step.velocity = VelocityUpdate::Exact;
  step.exact_solver = exact_solver_factory();
  step.exact.method = ExactMethod::PCG;
  step.transfer = Transfer::VelocityGradient;
  CHECK_THROWS_WITH(validate(step), Catch::Contains("exact_method"));
  step.transfer = Transfer::Standard;
  CHECK_NOTHROW(validate(step));
  step.exact.tolerance = 0;
  CHECK_THROWS_WITH(validate(step), Catch::Contains("exact_tolerance"));
}
