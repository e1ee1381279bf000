// SPDX-License-Identifier: BSD-3-Clause
// The exact solve (exact.hpp) over its two back ends: CHOLMOD's Cholesky factor of a symmetric
// m̃_FF and UMFPACK's LU of a general one; the equations themselves are restricted_system.cpp's.
#include "sparsempm/exact.hpp"

#include "restricted_system.hpp"
#include "sparsempm/errors.hpp"

#include <cholmod.h>
#include <umfpack.h>

#include <Eigen/IterativeLinearSolvers>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace smpm {

using detail::Restricted;

// A back end holds the calls of FactoredMassSolver that depend on the factorisation: its Factor
// (the restricted matrix and its factors; analysed() once a symbolic analysis of its pattern
// exists, factored() once numeric factors do), accept (the options it can serve), analyse (the
// symbolic analysis of a new pattern), factorize (the numeric one; returns the reciprocal
// condition estimate, throws NumericalError naming the nodes), right_hand_sides (for its kind of
// matrix), solve (v(F, comps) = m̃_FF⁻¹ B) and release.

namespace {
cholmod_sparse as_cholmod(Restricted& f) {
  cholmod_sparse A{};
  A.nrow = A.ncol = f.free.size();
  A.nzmax = f.rowind.size();
  A.p = f.colptr.data();
  A.i = f.rowind.data();
  A.x = f.values.data();
  A.stype = -1; // symmetric, lower triangle used
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

[[noreturn]] void not_positive_definite(const Operators& ops, const Restricted& f, long minor,
                                        NodalSystem system) {
  std::ostringstream os;
  os << "the " << to_string(system)
     << " is not positive definite on the active nodes: CHOLMOD found a non-positive pivot at "
     << (minor >= 0 && minor < long(f.free.size()) ? ops.node_text(f.free[size_t(minor)])
                                                   : std::string("an unknown node"))
     << "; " << detail::lightest_nodes(ops, f.free, system) << detail::remedies(system);
  throw NumericalError(os.str());
}
} // namespace

struct CholmodBackend {
  // A Cholesky factor L Lᵀ of a symmetric restricted m̃.
  struct Factor : Restricted {
    cholmod_factor* L = nullptr;
    bool analysed() const { return L != nullptr; }
    bool factored() const { return L != nullptr; }
  };
  cholmod_common c;
  NodalSystem system = NodalSystem::ConsistentMass; // the matrix its messages name

  CholmodBackend() {
    cholmod_start(&c);
    c.print = 0; // failures are reported as NumericalError, not printed
    c.error_handler = nullptr;
  }
  ~CholmodBackend() { cholmod_finish(&c); }
  CholmodBackend(const CholmodBackend&) = delete;
  CholmodBackend& operator=(const CholmodBackend&) = delete;

  static void accept(const ExactOptions& options) {
    if (!is_symmetric(options.system))
      throw UsageError("CholmodSolver factors symmetric matrices, and the " +
                       std::string(to_string(options.system)) +
                       " is not: make the solver with exact_solver_factory() (UMFPACK for it)");
  }
  void analyse(Factor& f) {
    release(f);
    cholmod_sparse A = as_cholmod(f);
    f.L = cholmod_analyze(&A, &c);
    if (!f.L)
      throw NumericalError("CHOLMOD could not analyse the " + std::string(to_string(system)));
  }
  double factorize(const Operators& ops, Factor& f) {
    cholmod_sparse A = as_cholmod(f);
    cholmod_factorize(&A, f.L, &c);
    if (c.status == CHOLMOD_NOT_POSDEF || f.L->minor < f.L->n)
      not_positive_definite(ops, f, long(f.L->minor), system);
    return cholmod_rcond(f.L, &c);
  }
  static Eigen::MatrixXd right_hand_sides(const Operators& ops, const SparseRowMatrix& mt,
                                          double blend, const Field& p, const Field& prescribed,
                                          const std::vector<int>& F, const std::vector<int>& local,
                                          const std::vector<int>& comps, Field& v) {
    return detail::symmetric_right_hand_sides(ops, mt, blend, p, prescribed, F, local, comps, v);
  }
  // v(F, comps) = L⁻ᵀL⁻¹ B.
  void solve(Factor& f, Eigen::MatrixXd& B, Field& v) {
    cholmod_dense rhs{};
    rhs.nrow = f.free.size();
    rhs.ncol = f.comps.size();
    rhs.nzmax = rhs.nrow * rhs.ncol;
    rhs.d = rhs.nrow;
    rhs.x = B.data();
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* X = cholmod_solve(CHOLMOD_A, f.L, &rhs, &c);
    if (!X)
      throw NumericalError("CHOLMOD could not solve with the " + std::string(to_string(system)));
    const double* x = static_cast<const double*>(X->x);
    for (size_t k = 0; k < f.comps.size(); ++k)
      for (size_t q = 0; q < f.free.size(); ++q)
        v(f.free[q], f.comps[k]) = x[k * X->d + q];
    cholmod_free_dense(&X, &c);
  }
  void release(Factor& f) {
    if (f.L)
      cholmod_free_factor(&f.L, &c);
  }
};

struct UmfpackBackend {
  // An LU factorisation of a general restricted m̃ (m̃_L of the velocity-gradient transfer), of
  // its transpose's CSC arrays, solved with UMFPACK_At.
  struct Factor : Restricted {
    void* symbolic = nullptr;
    void* numeric = nullptr;
    bool analysed() const { return symbolic != nullptr; }
    bool factored() const { return numeric != nullptr; }
  };
  NodalSystem system = NodalSystem::ConsistentMass; // the matrix its messages name

  static void accept(const ExactOptions&) {}
  void analyse(Factor& f) {
    release(f);
    const int m = int(f.free.size());
    double info[UMFPACK_INFO];
    if (umfpack_di_symbolic(m, m, f.colptr.data(), f.rowind.data(), f.values.data(), &f.symbolic,
                            nullptr, info) != UMFPACK_OK)
      throw NumericalError("UMFPACK could not analyse the " + std::string(to_string(system)));
  }
  double factorize(const Operators& ops, Factor& f) {
    release_numeric(f);
    double info[UMFPACK_INFO];
    const int status = umfpack_di_numeric(f.colptr.data(), f.rowind.data(), f.values.data(),
                                          f.symbolic, &f.numeric, nullptr, info);
    if (status == UMFPACK_WARNING_singular_matrix || status < 0)
      throw NumericalError("the " + std::string(to_string(system)) +
                           " is singular on the active nodes (UMFPACK status " +
                           std::to_string(status) + "); " +
                           detail::lightest_nodes(ops, f.free, system) + detail::remedies(system));
    return info[UMFPACK_RCOND];
  }
  static Eigen::MatrixXd right_hand_sides(const Operators&, const SparseRowMatrix& mt, double blend,
                                          const Field& p, const Field& prescribed,
                                          const std::vector<int>& F, const std::vector<int>&,
                                          const std::vector<int>& comps, Field& v) {
    return detail::general_right_hand_sides(mt, blend, p, prescribed, F, comps, v);
  }
  // v(F, comps) = m̃_FF⁻¹ B (UMFPACK_At: f holds m̃_FFᵀ in CSC).
  void solve(Factor& f, const Eigen::MatrixXd& B, Field& v) {
    Eigen::VectorXd x(B.rows());
    double info[UMFPACK_INFO];
    for (size_t k = 0; k < f.comps.size(); ++k) {
      const int status =
          umfpack_di_solve(UMFPACK_At, f.colptr.data(), f.rowind.data(), f.values.data(), x.data(),
                           B.col(Index(k)).data(), f.numeric, nullptr, info);
      if (status < 0)
        throw NumericalError("UMFPACK could not solve with the " + std::string(to_string(system)) +
                             " (status " + std::to_string(status) + ")");
      for (size_t q = 0; q < f.free.size(); ++q)
        v(f.free[q], f.comps[k]) = x[Index(q)];
    }
  }
  static void release_numeric(Factor& f) {
    if (f.numeric)
      umfpack_di_free_numeric(&f.numeric);
  }
  void release(Factor& f) {
    release_numeric(f);
    if (f.symbolic)
      umfpack_di_free_symbolic(&f.symbolic);
  }
};

struct PcgBackend {
  // The conjugate gradient on a symmetric restricted m̃ (stored whole: its rows are its
  // columns), preconditioned by its diagonal or Eigen's IncompleteCholesky, to a relative
  // residual. It factors nothing: "factorize" checks the diagonal, solve builds the
  // preconditioner and iterates from v_F = 0.
  struct Factor : Restricted {
    bool ready = false;
    bool analysed() const { return ready; }
    bool factored() const { return ready; }
  };
  NodalSystem system = NodalSystem::ConsistentMass; // the matrix its messages name
  ExactOptions options;

  static void accept(const ExactOptions& options) {
    if (!is_symmetric(options.system))
      throw UsageError("the conjugate gradient needs a symmetric matrix, and the " +
                       std::string(to_string(options.system)) + " is not");
  }
  void analyse(Factor& f) { f.ready = true; }
  double factorize(const Operators& ops, Factor& f) {
    for (size_t j = 0; j < f.free.size(); ++j) // a non-positive diagonal: not SPD
      for (int q = f.colptr[j]; q < f.colptr[j + 1]; ++q)
        if (f.rowind[size_t(q)] == int(j) && !(f.values[size_t(q)] > 0))
          not_positive_definite(ops, f, long(j), system);
    return std::numeric_limits<double>::quiet_NaN(); // no condition estimate
  }
  static Eigen::MatrixXd right_hand_sides(const Operators& ops, const SparseRowMatrix& mt,
                                          double blend, const Field& p, const Field& prescribed,
                                          const std::vector<int>& F, const std::vector<int>& local,
                                          const std::vector<int>& comps, Field& v) {
    return detail::symmetric_right_hand_sides(ops, mt, blend, p, prescribed, F, local, comps, v);
  }
  template <class Preconditioner>
  void iterate(Factor& f, const Eigen::MatrixXd& B, Field& v) {
    const Index m = Index(f.free.size());
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>> A(
        m, m, Index(f.values.size()), f.colptr.data(), f.rowind.data(), f.values.data());
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::ColMajor, int>,
                             Eigen::Lower | Eigen::Upper, Preconditioner>
        cg;
    cg.setTolerance(options.tolerance);
    cg.setMaxIterations(std::max<Index>(100, 10 * m));
    cg.compute(A);
    if (cg.info() != Eigen::Success)
      throw NumericalError("the preconditioner of the conjugate gradient failed on the " +
                           std::string(to_string(system)));
    for (size_t k = 0; k < f.comps.size(); ++k) {
      const Eigen::VectorXd x = cg.solve(B.col(Index(k)));
      if (cg.info() != Eigen::Success) {
        std::ostringstream os;
        os << "the conjugate gradient on the " << to_string(system) << " reached a relative "
           << "residual of " << cg.error() << " after " << cg.iterations()
           << " iterations, not the tolerance " << options.tolerance << " (a larger tolerance, "
           << "or exact_method = \"factor\")" << detail::remedies(system);
        throw NumericalError(os.str());
      }
      for (size_t q = 0; q < f.free.size(); ++q)
        v(f.free[q], f.comps[k]) = x[Index(q)];
    }
  }
  void solve(Factor& f, const Eigen::MatrixXd& B, Field& v) {
    if (options.preconditioner == ExactPreconditioner::IncompleteCholesky)
      iterate<Eigen::IncompleteCholesky<double, Eigen::Lower>>(f, B, v);
    else
      iterate<Eigen::DiagonalPreconditioner<double>>(f, B, v);
  }
  void release(Factor& f) { f.ready = false; }
};

template <class Backend>
struct FactoredMassSolver<Backend>::Impl {
  Backend backend;
  std::vector<typename Backend::Factor> factors;
  size_t used = 0; // factors of the last solve
  Index rows = 0;  // nodes of the last solve
  long analyses = 0, factorizations = 0;
  double rcond = std::numeric_limits<double>::quiet_NaN();
  ~Impl() {
    for (typename Backend::Factor& f : factors)
      backend.release(f);
  }
};

template <class Backend>
FactoredMassSolver<Backend>::FactoredMassSolver(const ExactOptions& options)
    : impl_(std::make_unique<Impl>()), options_(options) {
  validate(options_);
  Backend::accept(options_);
  impl_->backend.system = options_.system;
  if constexpr (requires { impl_->backend.options; }) // PCG's tolerance and preconditioner
    impl_->backend.options = options_;
}
template <class Backend>
FactoredMassSolver<Backend>::~FactoredMassSolver() = default;
template <class Backend>
long FactoredMassSolver<Backend>::analyses() const {
  return impl_->analyses;
}
template <class Backend>
long FactoredMassSolver<Backend>::factorizations() const {
  return impl_->factorizations;
}
template <class Backend>
double FactoredMassSolver<Backend>::last_rcond() const {
  return impl_->rcond;
}

template <class Backend>
void FactoredMassSolver<Backend>::solve(const Operators& ops, const SparseRowMatrix& mt,
                                        const LoopConstraints& bc, const Field& p, Field& v) {
  Impl& I = *impl_;
  const Index n = ops.num_nodes();
  const int d = int(p.cols());
  const Field prescribed =
      prescribed_components(bc, ops.active, ops.m, p,
                            options_.mass_cutoff > 0 ? options_.mass_cutoff * ops.m.maxCoeff() : 0);
  v.setZero(n, d);
  size_t slot = 0;
  for (const auto& [F, comps] : detail::free_groups(ops, prescribed)) {
    if (slot >= I.factors.size())
      I.factors.emplace_back();
    typename Backend::Factor& f = I.factors[slot++];
    std::vector<int> local(static_cast<size_t>(n), -1);
    for (size_t k = 0; k < F.size(); ++k)
      local[size_t(F[k])] = int(k);
    const bool same_pattern =
        detail::restrict_matrix(ops, mt, options_.regularization, local, f, F, f.analysed());
    f.comps = comps;
    if (F.empty())
      continue;
    if (!same_pattern) {
      I.backend.analyse(f);
      ++I.analyses;
    }
    ++I.factorizations; // a failed factorisation counts too
    I.rcond = I.backend.factorize(ops, f);
    Eigen::MatrixXd B = Backend::right_hand_sides(ops, mt, 1 - options_.regularization, p,
                                                  prescribed, F, local, comps, v);
    I.backend.solve(f, B, v);
  }
  I.used = slot;
  I.rows = n;
  // Components whose free set is empty keep only their prescribed values.
  for (int a = 0; a < d; ++a)
    for (Index i = 0; i < n; ++i)
      if (ops.active[i] && !std::isnan(prescribed(i, a)))
        v(i, a) = prescribed(i, a);
}

template <class Backend>
void FactoredMassSolver<Backend>::solve_again(const Field& r, Field& v) {
  Impl& I = *impl_;
  SMPM_VERIFY(r.rows() == I.rows, "solve_again: " + std::to_string(r.rows()) +
                                      " rows after a solve of " + std::to_string(I.rows));
  v.setZero(r.rows(), r.cols());
  for (size_t s = 0; s < I.used; ++s) {
    typename Backend::Factor& f = I.factors[s];
    if (f.free.empty() || !f.factored())
      continue;
    Eigen::MatrixXd B(f.free.size(), f.comps.size());
    for (size_t k = 0; k < f.comps.size(); ++k)
      for (size_t q = 0; q < f.free.size(); ++q)
        B(Index(q), Index(k)) = r(f.free[q], f.comps[k]);
    I.backend.solve(f, B, v);
  }
}

template class FactoredMassSolver<CholmodBackend>;
template class FactoredMassSolver<UmfpackBackend>;
template class FactoredMassSolver<PcgBackend>;

MassSolverFactory cholmod_solver_factory() {
  return [](const ExactOptions& options) { return std::make_unique<CholmodSolver>(options); };
}

MassSolverFactory exact_solver_factory() {
  return [](const ExactOptions& options) -> std::unique_ptr<MassSolver> {
    if (options.method == ExactMethod::PCG)
      return std::make_unique<PcgSolver>(options);
    if (is_symmetric(options.system))
      return std::make_unique<CholmodSolver>(options);
    return std::make_unique<UmfpackSolver>(options);
  };
}

} // namespace smpm
