// SPDX-License-Identifier: BSD-3-Clause
// The step's node sums across ranks (WindowSums) and ρ(T) of the linearised step by SLEPc.
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

struct WindowSums::Impl {
  Impl(const DistributedGrid& g, std::vector<PetscInt> r, const Grid& w)
      : grid(g), rows(std::move(r)), window(w) {}
  const DistributedGrid& grid;
  std::vector<PetscInt> rows; // the PETSc row of each window column
  Grid window;                // the window bound (bind), and its fields
  int fields = 0;
  bool bound = false;
  struct Buffers { // per number of components
    OwnedVec global, local;
    OwnedScatter scatter;
    std::vector<PetscInt> index;
  };
  std::map<Index, Buffers> buffers;
  Index remote_rows = 0;           // window rows another rank owns
  mutable double communicated = 0; // bytes this rank sent and received through the scatters

  // One scatter of a field of c components: its remote entries, 8 bytes each.
  void count(Index c) const { communicated += 8.0 * double(remote_rows * c); }

  Buffers& for_components(Index c) {
    Buffers& b = buffers[c];
    if (b.global.get())
      return b;
    b.index.resize(rows.size() * size_t(c));
    for (size_t r = 0; r < rows.size(); ++r)
      for (Index a = 0; a < c; ++a)
        b.index[r * size_t(c) + size_t(a)] = rows[r] * PetscInt(c) + PetscInt(a);
    b.global = node_vector(grid, int(c));
    SMPM_PETSC_CALL(VecCreateSeq(PETSC_COMM_SELF, PetscInt(b.index.size()), b.local.out()));
    OwnedIS is;
    SMPM_PETSC_CALL(ISCreateGeneral(PETSC_COMM_SELF, PetscInt(b.index.size()), b.index.data(),
                                    PETSC_COPY_VALUES, is.out()));
    SMPM_PETSC_CALL(VecScatterCreate(b.global, is, b.local, nullptr, b.scatter.out()));
    return b;
  }

  // The buffers of `window`'s components with the window in the local Vec (row-major: its rows
  // in order, their components together).
  Buffers& load(const Field& window) {
    if (size_t(window.rows()) != rows.size())
      throw UsageError("WindowSums: a field of " + std::to_string(window.rows()) +
                       " rows on a window of " + std::to_string(rows.size()) + " columns");
    Buffers& b = for_components(window.cols());
    PetscScalar* a = nullptr;
    SMPM_PETSC_CALL(VecGetArray(b.local, &a));
    std::copy(window.data(), window.data() + window.size(), a);
    SMPM_PETSC_CALL(VecRestoreArray(b.local, &a));
    return b;
  }

  // The largest of `flags` over the ranks, the first being whether a rank failed: every
  // collective call of the sums starts here, so that a rank's fail() meets the others' next
  // call whichever it is (NodeSums), and they throw.
  std::array<int, 2> agree(std::array<int, 2> flags) const {
    std::array<int, 2> any{0, 0};
    MPI_Allreduce(flags.data(), any.data(), 2, MPI_INT, MPI_MAX, grid.comm());
    if (any[0] && !flags[0])
      throw FailedElsewhere("the step failed on another rank");
    return any;
  }
};

WindowSums::WindowSums(const DistributedGrid& grid)
    : impl_(std::make_unique<Impl>(grid, std::vector<PetscInt>{}, grid.grid())) {}

WindowSums::WindowSums(const DistributedGrid& grid, const DistributedOperators& ops)
    : impl_(std::make_unique<Impl>(grid, ops.rows, ops.local.grid)) {
  impl_->fields = ops.local.fields;
  impl_->bound = true;
}

WindowSums::~WindowSums() = default;

void WindowSums::bind(const Grid& window, int fields) {
  Impl& I = *impl_;
  if (fields != I.grid.fields())
    throw UsageError("WindowSums: operators of " + std::to_string(fields) +
                     " velocity fields on a distributed grid of " +
                     std::to_string(I.grid.fields()));
  const bool same = I.bound && window == I.window && fields == I.fields;
  // Every rank takes its new window's rows (the application ordering) and remakes its scatters
  // (collective) when any rank's window changed.
  if (!I.agree({0, same ? 0 : 1})[1])
    return;
  I.window = window;
  I.fields = fields;
  I.bound = true;
  I.buffers.clear();
  const Index ng = window.num_nodes();
  std::vector<PetscInt> nodes(static_cast<size_t>(ng)), rows;
  for (Index i = 0; i < ng; ++i)
    nodes[size_t(i)] = PetscInt(window.whole_node(i));
  I.rows.resize(size_t(ng * fields));
  for (int a = 0; a < fields; ++a) {
    I.grid.petsc_rows(nodes, a, rows);
    std::copy(rows.begin(), rows.end(), I.rows.begin() + a * ng);
  }
  const PetscInt first = I.grid.first_row(), end = first + I.grid.owned_rows();
  I.remote_rows = Index(std::count_if(I.rows.begin(), I.rows.end(),
                                      [&](PetscInt r) { return r < first || r >= end; }));
}

void WindowSums::add(Field& window) const {
  // The window's partial sums added into the owners' rows by the scatter's reverse (ADD_VALUES),
  // the totals sent back forward: two neighbour exchanges on the scatter's fixed pattern.
  impl_->agree({0, 0});
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecSet(b.global, 0.0));
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, b.global, ADD_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, b.global, ADD_VALUES, SCATTER_REVERSE));
  impl_->count(window.cols());
  to_window(b.global, window);
}

void WindowSums::to_global(const Field& window, Vec global) const {
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, global, INSERT_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, global, INSERT_VALUES, SCATTER_REVERSE));
  impl_->count(window.cols());
}

void WindowSums::to_window(Vec global, Field& window) const {
  window.resize(Index(impl_->rows.size()), window.cols());
  Impl::Buffers& b = impl_->for_components(window.cols());
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, global, b.local, INSERT_VALUES, SCATTER_FORWARD));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, global, b.local, INSERT_VALUES, SCATTER_FORWARD));
  impl_->count(window.cols());
  const PetscScalar* t = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(b.local, &t));
  std::copy(t, t + window.size(), window.data());
  SMPM_PETSC_CALL(VecRestoreArrayRead(b.local, &t));
}

const std::vector<PetscInt>& WindowSums::rows() const {
  return impl_->rows;
}

double WindowSums::communicated_bytes() const {
  return impl_->communicated;
}

double WindowSums::maximum(double value) const {
  impl_->agree({0, 0});
  double out = value;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, impl_->grid.comm());
  return out;
}

void WindowSums::sum(double* values, int count) const {
  impl_->agree({0, 0});
  if (count > 0)
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, impl_->grid.comm());
}

void WindowSums::sum_rows(const Field& window, double* totals) const {
  impl_->agree({0, 0});
  const Index c = window.cols();
  if (c == 0)
    return;
  Impl::Buffers& b = impl_->load(window);
  SMPM_PETSC_CALL(VecSet(b.global, 0.0));
  SMPM_PETSC_CALL(VecScatterBegin(b.scatter, b.local, b.global, INSERT_VALUES, SCATTER_REVERSE));
  SMPM_PETSC_CALL(VecScatterEnd(b.scatter, b.local, b.global, INSERT_VALUES, SCATTER_REVERSE));
  impl_->count(c);
  std::vector<double> owned(size_t(c), 0.0); // this rank's owned rows, column by column
  PetscInt n = 0;
  SMPM_PETSC_CALL(VecGetLocalSize(b.global, &n));
  const PetscScalar* g = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(b.global, &g));
  for (PetscInt k = 0; k < n; ++k)
    owned[size_t(k % c)] += g[k];
  SMPM_PETSC_CALL(VecRestoreArrayRead(b.global, &g));
  MPI_Allreduce(owned.data(), totals, int(c), MPI_DOUBLE, MPI_SUM, impl_->grid.comm());
}

void WindowSums::fail() const {
  impl_->agree({1, 0});
}

namespace {

using OwnedEPS = Owned<EPS, EPSDestroy>;

// m̃⁻¹ of the exact update across ranks: the window's totals → a distributed Vec → exact_solve
// → the window (distributed_mass_solver_factory).
class DistributedMassSolver final : public MassSolver {
public:
  DistributedMassSolver(const DistributedGrid& grid, const DistributedOperators& ops,
                        const WindowSums& sums, DistributedExactOptions options)
      : grid_(grid), ops_(ops), sums_(sums), options_(options) {}

  void solve(const Operators&, const SparseRowMatrix&, const LoopConstraints& bc, const Field& p,
             Field& v) override {
    if (!p_.get() || dim_ != p.cols()) {
      dim_ = p.cols();
      p_ = node_vector(grid_, int(dim_));
      v_ = node_vector(grid_, int(dim_));
    }
    sums_.to_global(p, p_);
    exact_solve(grid_, ops_, options_, bc, p_, v_);
    v.resize(p.rows(), p.cols());
    sums_.to_window(v_, v);
  }
  bool across_processes() const override { return true; }

private:
  const DistributedGrid& grid_;
  const DistributedOperators& ops_;
  const WindowSums& sums_;
  DistributedExactOptions options_;
  Index dim_ = 0;
  OwnedVec p_, v_;
};

// m̃⁻¹ of the exact update in a simulation across ranks: each solve assembles the step's
// distributed m̃ from the m̃ the step hands it (the window changes from step to step), then
// solves as DistributedMassSolver.
class StepMassSolver final : public MassSolver {
public:
  StepMassSolver(const DistributedGrid& grid, const WindowSums& sums,
                 DistributedExactOptions options)
      : grid_(grid), sums_(sums), options_(options) {}

  void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
             const Field& p, Field& v) override {
    assemble_step(grid_, sums_, ops, mt, int(p.cols()), dops_);
    if (!p_.get() || dim_ != p.cols()) {
      dim_ = p.cols();
      p_ = node_vector(grid_, int(dim_));
      v_ = node_vector(grid_, int(dim_));
    }
    sums_.to_global(p, p_);
    exact_solve(grid_, dops_, options_, bc, p_, v_);
    v.resize(p.rows(), p.cols());
    sums_.to_window(v_, v);
  }
  bool across_processes() const override { return true; }

private:
  const DistributedGrid& grid_;
  const WindowSums& sums_;
  DistributedExactOptions options_;
  DistributedOperators dops_;
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
        grid, ops, sums, DistributedExactOptions{.exact = exact, .method = method});
  };
}

MassSolverFactory step_mass_solver_factory(const DistributedGrid& grid, const WindowSums& sums,
                                           ExactMethod method) {
  return [&grid, &sums, method](const ExactOptions& exact) -> std::unique_ptr<MassSolver> {
    return std::make_unique<StepMassSolver>(
        grid, sums, DistributedExactOptions{.exact = exact, .method = method});
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
