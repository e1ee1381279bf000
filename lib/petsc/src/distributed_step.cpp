// SPDX-License-Identifier: BSD-3-Clause
// The exact update's m̃⁻¹ inside a step across ranks and ρ(T) of the linearised step by SLEPc.
#include "sparsempm/petsc.hpp"

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/errors.hpp"

#include <slepceps.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <utility>

namespace smpm::petsc {

namespace {

using OwnedEPS = Owned<EPS, EPSDestroy>;

// m̃⁻¹ of the exact update in a step across ranks: the window's momentum totals → a distributed
// Vec → exact_solve → the window. With `fixed` operators (distributed_mass_solver_factory: the
// linearised step's frozen configuration) every solve uses their m̃; without
// (step_mass_solver_factory: a simulation, whose window changes from step to step) each solve
// assembles the step's distributed m̃ from the m̃ the step hands it (assemble_step).
class DistributedMassSolver final : public MassSolver {
public:
  DistributedMassSolver(const DistributedGrid& grid, const DistributedOperators* fixed,
                        const WindowSums& sums, DistributedExactOptions options)
      : grid_(grid), fixed_(fixed), sums_(sums), options_(options) {}

  void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
             const Field& p, Field& v) override {
    if (!fixed_)
      assemble_step(grid_, sums_, ops, mt, int(p.cols()), step_);
    if (!p_.get() || dim_ != p.cols()) {
      dim_ = p.cols();
      p_ = node_vector(grid_, int(dim_));
      v_ = node_vector(grid_, int(dim_));
    }
    sums_.to_global(p, p_);
    exact_solve(grid_, fixed_ ? *fixed_ : step_, options_, bc, p_, v_);
    v.resize(p.rows(), p.cols());
    sums_.to_window(v_, v);
  }
  bool across_processes() const override { return true; }

private:
  const DistributedGrid& grid_;
  const DistributedOperators* fixed_; // null: each step's own (step_)
  const WindowSums& sums_;
  DistributedExactOptions options_;
  DistributedOperators step_;
  Index dim_ = 0;
  OwnedVec p_, v_;
};

// The MATSHELL's context: the linearised step, and the exception a product threw (PETSc's C
// callbacks must not throw: the product returns an error code and the caller rethrows this).
struct ShellContext {
  const LinearizedStep* T = nullptr;
  const NodeSums* sums = nullptr; // told when this rank's product fails (NodeSums::fail)
  std::exception_ptr failure;
  bool non_finite = false;
};

PetscErrorCode shell_mult(Mat a, Vec x, Vec y) {
  void* raw = nullptr;
  MatShellGetContext(a, &raw);
  auto* ctx = static_cast<ShellContext*>(raw);
  const PetscScalar* xa = nullptr;
  PetscScalar* ya = nullptr;
  VecGetArrayRead(x, &xa);
  VecGetArray(y, &ya);
  PetscErrorCode code = 0;
  try {
    ctx->T->perform_op(xa, ya);
  } catch (const FailedElsewhere&) { // another rank's product failed, and said so
    ctx->failure = std::current_exception();
    code = PETSC_ERR_LIB;
  } catch (const NumericalError&) {
    ctx->sums->fail(); // the others' pending sum throws FailedElsewhere
    ctx->non_finite = true;
    ctx->failure = std::current_exception();
    code = PETSC_ERR_FP;
  } catch (...) {
    ctx->sums->fail();
    ctx->failure = std::current_exception();
    code = PETSC_ERR_LIB;
  }
  VecRestoreArray(y, &ya);
  VecRestoreArrayRead(x, &xa);
  return code;
}

// The linearised step of this rank's particles with the step's sums over the ranks, as a
// MATSHELL, and SLEPc's eigensolver on it: built once, evaluated at any Δt.
class DistributedRadius {
public:
  DistributedRadius(const DistributedGrid& grid, const Model& model, StepOptions options, double dt,
                    ExactMethod exact)
      : grid_(grid), local_(local_model(grid, model, ids_)), total_(model.particles.size()) {
    assemble(grid, local_.particles, ids_, options.shape, ops_);
    sums_ = std::make_unique<WindowSums>(grid, ops_);
    if (options.velocity == VelocityUpdate::Exact)
      options.exact_solver = distributed_mass_solver_factory(grid, ops_, *sums_, exact);
    T_ = std::make_unique<LinearizedStep>(local_, options, dt, *sums_);
    ctx_.T = T_.get();
    ctx_.sums = sums_.get();
    const PetscInt n = PetscInt(T_->rows());
    SMPM_PETSC_CALL(
        MatCreateShell(grid.comm(), n, n, PETSC_DETERMINE, PETSC_DETERMINE, &ctx_, shell_.out()));
    SMPM_PETSC_CALL(MatShellSetOperation(shell_, MATOP_MULT, (void (*)(void))shell_mult));
  }

  LinearizedStep& step() { return *T_; }

  // ρ(T) by the serial spectral_radius's rule (spectral_radius_rule) on PETSc Vecs: up to
  // kDenseRadiusRows rows (where the serial code takes T's eigenvalues directly) Krylov–Schur
  // resolves |λ|max; above, power iterations measure the growth first, and Krylov–Schur starts
  // from the power iterate only when an eigenvalue stands out.
  SpectralRadius radius(double tol) {
    ctx_.failure = nullptr;
    ctx_.non_finite = false;
    PetscInt N = 0;
    SMPM_PETSC_CALL(MatGetSize(shell_, &N, nullptr));
    struct PetscAlgebra {
      DistributedRadius& r;
      double tol;
      PetscInt N;
      OwnedVec x, y;
      Index rows() const { return Index(N); }
      SpectralRadius small() { return r.krylov_schur(nullptr, tol, std::nan("")); }
      void start() { r.start_vector(x); } // unit length, as the whole vector it is taken from
      bool apply() { return !r.failure(MatMult(r.shell_, x, y), "MatMult (rho(T))"); }
      double norm() const {
        PetscReal g = 0;
        SMPM_PETSC_CALL(VecNorm(y, NORM_2, &g));
        return double(g);
      }
      void next(double g) { SMPM_PETSC_CALL(VecAXPBY(x, 1.0 / g, 0.0, y)); }
      SpectralRadius resolve(double rate) { return r.krylov_schur(x, tol, rate); }
    };
    PetscAlgebra alg{*this, tol, N, {}, {}};
    SMPM_PETSC_CALL(MatCreateVecs(shell_, alg.x.out(), alg.y.out()));
    return spectral_radius_rule(alg, kDenseRadiusRows);
  }

private:
  // |λ|max of T by SLEPc's Krylov–Schur, from `start` when given (the power iterate of a large
  // T: NotConverged with the measured growth `rate` when it does not converge).
  SpectralRadius krylov_schur(Vec start, double tol, double rate) {
    PetscInt N = 0;
    SMPM_PETSC_CALL(MatGetSize(shell_, &N, nullptr));
    OwnedEPS eps;
    SMPM_PETSC_CALL(EPSCreate(grid_.comm(), eps.out()));
    SMPM_PETSC_CALL(EPSSetOperators(eps, shell_, nullptr));
    SMPM_PETSC_CALL(EPSSetProblemType(eps, EPS_NHEP));
    SMPM_PETSC_CALL(EPSSetType(eps, EPSKRYLOVSCHUR));
    SMPM_PETSC_CALL(EPSSetWhichEigenpairs(eps, EPS_LARGEST_MAGNITUDE));
    const bool large = start != nullptr;
    SMPM_PETSC_CALL(
        EPSSetDimensions(eps, 1, std::min<PetscInt>(N, large ? 30 : 60), PETSC_DEFAULT));
    SMPM_PETSC_CALL(EPSSetTolerances(eps, tol, large ? 300 : 20000));
    if (large)
      SMPM_PETSC_CALL(EPSSetInitialSpace(eps, 1, &start));
    SMPM_PETSC_CALL(EPSSetOptionsPrefix(eps, "rho_"));
    SMPM_PETSC_CALL(EPSSetFromOptions(eps));
    if (std::optional<SpectralRadius> r = failure(EPSSolve(eps), "EPSSolve (rho(T))"))
      return *r;
    PetscInt converged = 0;
    SMPM_PETSC_CALL(EPSGetConverged(eps, &converged));
    if (converged < 1) // the measured growth above the dense limit, as the serial code
      return {rate, SpectralStatus::NotConverged};
    PetscScalar re = 0, im = 0;
    SMPM_PETSC_CALL(EPSGetEigenvalue(eps, 0, &re, &im));
    const double rho = std::hypot(double(re), double(im));
    if (!std::isfinite(rho))
      return {std::numeric_limits<double>::infinity(), SpectralStatus::NonFinite};
    return {rho, SpectralStatus::Converged};
  }

  static Model local_model(const DistributedGrid& grid, const Model& model,
                           std::vector<Index>& ids) {
    ids = grid.owned_particles(model.particles);
    Model local = model;
    local.particles = select_particles(model.particles, ids);
    return local;
  }

  // The power iteration's start: the serial spectral_radius's (power_start over the whole
  // set's (V, σ), N d velocities then N d² stresses), each rank taking its particles' entries;
  // the same vector for any number of ranks.
  void start_vector(Vec x) const {
    const Index d = local_.grid.dim(), n = Index(ids_.size());
    const Eigen::VectorXd all = power_start(total_ * (d + d * d));
    PetscScalar* a = nullptr;
    SMPM_PETSC_CALL(VecGetArray(x, &a));
    for (Index p = 0; p < n; ++p) {
      const Index id = ids_[size_t(p)];
      for (Index c = 0; c < d; ++c)
        a[p * d + c] = all[id * d + c];
      for (Index c = 0; c < d * d; ++c)
        a[n * d + p * d * d + c] = all[total_ * d + id * d * d + c];
    }
    SMPM_PETSC_CALL(VecRestoreArray(x, &a));
  }

  // After a collective call that applied T (returning `code` on this rank): NonFinite when the
  // step met a non-finite value on any rank, the product's own exception rethrown, a PETSc
  // error thrown; nothing when every rank succeeded.
  std::optional<SpectralRadius> failure(PetscErrorCode code, const char* what) {
    int failed = code != 0, non_finite = ctx_.non_finite, any_failed = 0, any_non_finite = 0;
    MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, grid_.comm());
    MPI_Allreduce(&non_finite, &any_non_finite, 1, MPI_INT, MPI_MAX, grid_.comm());
    if (any_non_finite)
      return SpectralRadius{std::numeric_limits<double>::infinity(), SpectralStatus::NonFinite};
    if (ctx_.failure)
      std::rethrow_exception(ctx_.failure);
    check(code, what);
    if (any_failed) // every rank stops, not only the one that failed
      throw NumericalError(std::string(what) + " failed on another rank");
    return std::nullopt;
  }

  const DistributedGrid& grid_;
  std::vector<Index> ids_;
  Model local_;
  Index total_ = 0;          // particles in the whole set
  DistributedOperators ops_; // this rank's window: the sums' rows
  std::unique_ptr<WindowSums> sums_;
  std::unique_ptr<LinearizedStep> T_;
  ShellContext ctx_;
  OwnedMat shell_;
};

} // namespace

MassSolverFactory distributed_mass_solver_factory(const DistributedGrid& grid,
                                                  const DistributedOperators& ops,
                                                  const WindowSums& sums, ExactMethod method) {
  return [&grid, &ops, &sums, method](const ExactOptions& exact) -> std::unique_ptr<MassSolver> {
    return std::make_unique<DistributedMassSolver>(
        grid, &ops, sums, DistributedExactOptions{.exact = exact, .method = method});
  };
}

MassSolverFactory step_mass_solver_factory(const DistributedGrid& grid, const WindowSums& sums,
                                           ExactMethod method) {
  return [&grid, &sums, method](const ExactOptions& exact) -> std::unique_ptr<MassSolver> {
    return std::make_unique<DistributedMassSolver>(
        grid, nullptr, sums, DistributedExactOptions{.exact = exact, .method = method});
  };
}

SpectralRadius spectral_radius(const DistributedGrid& grid, const Model& model,
                               const StepOptions& options, double dt, double tol,
                               ExactMethod exact) {
  DistributedRadius r(grid, model, options, dt, exact);
  return r.radius(tol);
}

CriticalCourant critical_courant(const DistributedGrid& grid, const Model& model,
                                 const StepOptions& options, double tol, double c_max,
                                 double resolution, double hint, ExactMethod exact) {
  DistributedRadius r(grid, model, options, stable_time_step(model, 0.05), exact);
  return critical_courant_search(
      [&](double C, int& steps) {
        r.step().set_dt(stable_time_step(model, C));
        steps = r.step().steps_per_application();
        return r.radius(1e-10);
      },
      tol, c_max, resolution, hint, nullptr, small_courant_scan(options));
}

} // namespace smpm::petsc
