// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/exact.hpp"

#include "sparsempm/errors.hpp"

#include <cholmod.h>
#include <umfpack.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

namespace smpm {

namespace {
// m̃ restricted to one set F of free active nodes: the rows of F in CSR, which is the CSC of
// the restricted matrix's transpose (and of the matrix itself when m̃ is symmetric).
struct Restricted {
  std::vector<int> free;           // local → node
  std::vector<int> colptr, rowind; // pattern of the restricted matrix
  std::vector<double> values;
  std::vector<int> comps; // the velocity components solved with this factor
};
// A Cholesky factor of a symmetric restricted m̃ (CHOLMOD).
struct Factor : Restricted {
  cholmod_factor* L = nullptr;
};
// An LU factorisation of a general restricted m̃ (UMFPACK; m̃_L of the velocity-gradient
// transfer), of its transpose's CSC arrays, solved with UMFPACK_At.
struct LuFactor : Restricted {
  void* symbolic = nullptr;
  void* numeric = nullptr;
  void release_numeric() {
    if (numeric)
      umfpack_di_free_numeric(&numeric);
  }
  void release() {
    release_numeric();
    if (symbolic)
      umfpack_di_free_symbolic(&symbolic);
  }
};
} // namespace

struct CholmodSolver::Impl {
  cholmod_common c;
  std::vector<Factor> factors;
  size_t used = 0; // factors of the last solve
  Index rows = 0;  // nodes of the last solve
  long analyses = 0, factorizations = 0;
  double rcond = std::numeric_limits<double>::quiet_NaN();
  Impl() {
    cholmod_start(&c);
    c.print = 0; // failures are reported as NumericalError, not printed
    c.error_handler = nullptr;
  }
  ~Impl() {
    for (Factor& f : factors)
      if (f.L)
        cholmod_free_factor(&f.L, &c);
    cholmod_finish(&c);
  }
};

CholmodSolver::CholmodSolver(const ExactOptions& options)
    : impl_(std::make_unique<Impl>()), options_(options) {
  validate(options_);
  if (!options_.symmetric)
    throw UsageError("CholmodSolver factors symmetric matrices, and m~_L of the "
                     "velocity-gradient transfer is not: make the solver with "
                     "exact_solver_factory() (UMFPACK for it)");
}
CholmodSolver::~CholmodSolver() = default;
long CholmodSolver::analyses() const {
  return impl_->analyses;
}
long CholmodSolver::factorizations() const {
  return impl_->factorizations;
}
double CholmodSolver::last_rcond() const {
  return impl_->rcond;
}

MassSolverFactory cholmod_solver_factory() {
  return [](const ExactOptions& options) { return std::make_unique<CholmodSolver>(options); };
}

MassSolverFactory exact_solver_factory() {
  return [](const ExactOptions& options) -> std::unique_ptr<MassSolver> {
    if (options.symmetric)
      return std::make_unique<CholmodSolver>(options);
    return std::make_unique<UmfpackSolver>(options);
  };
}

namespace {
int axis_of(const VelocityCondition& c, int d) {
  for (int a = 0; a < d; ++a)
    if (std::abs(std::abs(c.direction[a]) - 1) < 1e-12)
      return a;
  throw InputError("the exact velocity update supports velocity conditions along axes only ('" +
                   c.label + "' is not)");
}

// The nodes of smallest lumped mass among `free`, for the messages below.
std::string lightest_nodes(const Operators& ops, const std::vector<int>& free) {
  std::vector<int> order(free);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return ops.m[a] < ops.m[b]; });
  std::ostringstream os;
  for (size_t k = 0; k < std::min<size_t>(3, order.size()); ++k)
    os << (k ? ", " : "") << ops.node_text(order[k]) << " (m = " << ops.m[order[k]] << ")";
  return os.str();
}

constexpr const char* kRemedies =
    " (set step.exact_mass_cutoff > 0 to give light nodes their lumped velocity, or "
    "step.exact_regularization > 0 to factor (1 - eps) m~ + eps m)";

[[noreturn]] void not_positive_definite(const Operators& ops, const Restricted& f, long minor) {
  std::ostringstream os;
  os << "the consistent mass matrix is not positive definite on the active nodes: CHOLMOD found "
        "a non-positive pivot at "
     << (minor >= 0 && minor < long(f.free.size()) ? ops.node_text(f.free[size_t(minor)])
                                                   : std::string("an unknown node"))
     << "; smallest lumped masses: " << lightest_nodes(ops, f.free) << kRemedies;
  throw NumericalError(os.str());
}
} // namespace

Field prescribed_components(const LoopConstraints& bc,
                            const Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                            const Eigen::VectorXd& m, const Field& p, double light) {
  const Index n = active.size();
  const int d = int(p.cols());
  Field prescribed = Field::Constant(n, d, std::numeric_limits<double>::quiet_NaN());
  if (bc.bcs && !bc.bcs->conditions.empty()) {
    // Conditions along axes only; a direction within round-off of an axis is taken as the axis.
    const BoundaryConditions* bcs = bc.bcs;
    BoundaryConditions snapped;
    for (const VelocityCondition& cond : bc.bcs->conditions) {
      const int a = axis_of(cond, d);
      const Eigen::Vector3d axis = (cond.direction[a] > 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a);
      if (cond.direction.head(d) != axis.head(d) && bcs == bc.bcs) {
        snapped = *bc.bcs;
        bcs = &snapped;
      }
    }
    if (bcs == &snapped)
      for (VelocityCondition& cond : snapped.conditions) {
        const int a = axis_of(cond, d);
        cond.direction = (cond.direction[a] > 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a);
      }
    Field values = Field::Zero(n, d), fixed = Field::Ones(n, d);
    bcs->constrain_velocity(*bc.grid, bc.time, values, &active);
    bcs->zero_directions(*bc.grid, fixed);
    for (Index i = 0; i < n; ++i)
      for (int a = 0; a < d; ++a)
        if (active[i] && fixed(i, a) == 0)
          prescribed(i, a) = values(i, a);
  }
  if (light > 0)
    for (Index i = 0; i < n; ++i)
      if (active[i] && m[i] < light)
        for (int a = 0; a < d; ++a)
          if (std::isnan(prescribed(i, a)))
            prescribed(i, a) = p(i, a) * (1.0 / m[i]);
  return prescribed;
}

namespace {
// Components grouped by their free set F (active nodes whose component is not prescribed):
// components with the same F share one factorisation.
std::vector<std::pair<std::vector<int>, std::vector<int>>> free_groups(const Operators& ops,
                                                                       const Field& prescribed) {
  std::vector<std::pair<std::vector<int>, std::vector<int>>> groups; // (F, components)
  for (int a = 0; a < int(prescribed.cols()); ++a) {
    std::vector<int> F;
    for (Index i = 0; i < ops.num_nodes(); ++i)
      if (ops.active[i] && std::isnan(prescribed(i, a)))
        F.push_back(int(i));
    auto same =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == F; });
    if (same != groups.end())
      same->second.push_back(a);
    else
      groups.push_back({std::move(F), {a}});
  }
  return groups;
}

// The blended matrix (1 − ε) m̃_FF + ε m_F of `f.free`: its rows in CSR, stored as the CSC of
// the transpose (for a symmetric m̃ the CSC of the matrix: row j is column j); `local` maps node
// → position in F (−1 outside). Returns whether the pattern equals the one already factorised
// (`factored`: a factor of the old pattern exists).
bool restrict_matrix(const Operators& ops, const SparseRowMatrix& mt, double regularization,
                     const std::vector<int>& local, Restricted& f, const std::vector<int>& F,
                     bool factored) {
  std::vector<int> colptr(F.size() + 1, 0), rowind;
  std::vector<double> values;
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  for (size_t k = 0; k < F.size(); ++k) {
    const int j = F[k];
    for (int q = ro[j]; q < ro[j + 1]; ++q)
      if (local[size_t(ri[q])] >= 0) {
        rowind.push_back(local[size_t(ri[q])]);
        values.push_back((1 - regularization) * rv[q] +
                         (ri[q] == j ? regularization * ops.m[j] : 0.0));
      }
    colptr[k + 1] = int(rowind.size());
  }
  const bool same_pattern = factored && f.free == F && f.colptr == colptr && f.rowind == rowind;
  f.free = F;
  f.colptr.swap(colptr);
  f.rowind.swap(rowind);
  f.values.swap(values);
  return same_pattern;
}

cholmod_sparse as_cholmod(Factor& f) {
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

// Right-hand sides b = p_F − (1 − ε) m̃_FC v_C, one column per component; sets v_C in v.
Eigen::MatrixXd right_hand_sides(const Operators& ops, const SparseRowMatrix& mt, double blend,
                                 const Field& p, const Field& prescribed, const std::vector<int>& F,
                                 const std::vector<int>& local, const std::vector<int>& comps,
                                 Field& v) {
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  Eigen::MatrixXd B(F.size(), comps.size());
  for (size_t k = 0; k < comps.size(); ++k) {
    const int comp = comps[k];
    for (size_t q = 0; q < F.size(); ++q)
      B(Index(q), Index(k)) = p(F[q], comp);
    for (Index i = 0; i < ops.num_nodes(); ++i) {
      const double vc = prescribed(i, comp);
      if (!ops.active[i] || std::isnan(vc))
        continue;
      v(i, comp) = vc;
      for (int q = ro[i]; q < ro[i + 1]; ++q)
        if (const int l = local[size_t(ri[q])]; l >= 0)
          B(l, Index(k)) -= blend * rv[q] * vc;
    }
  }
  return B;
}
} // namespace

namespace {
// v(F, comps) = L⁻ᵀL⁻¹ B with the factor of f.
void solve_factor(cholmod_common& c, Factor& f, Eigen::MatrixXd& B, Field& v) {
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
    throw NumericalError("CHOLMOD could not solve with the consistent mass matrix");
  const double* x = static_cast<const double*>(X->x);
  for (size_t k = 0; k < f.comps.size(); ++k)
    for (size_t q = 0; q < f.free.size(); ++q)
      v(f.free[q], f.comps[k]) = x[k * X->d + q];
  cholmod_free_dense(&X, &c);
}
} // namespace

void CholmodSolver::solve_again(const Field& r, Field& v) {
  SMPM_VERIFY(r.rows() == impl_->rows, "solve_again: " + std::to_string(r.rows()) +
                                           " rows after a solve of " + std::to_string(impl_->rows));
  v.setZero(r.rows(), r.cols());
  for (size_t s = 0; s < impl_->used; ++s) {
    Factor& f = impl_->factors[s];
    if (f.free.empty() || !f.L)
      continue;
    Eigen::MatrixXd B(f.free.size(), f.comps.size());
    for (size_t k = 0; k < f.comps.size(); ++k)
      for (size_t q = 0; q < f.free.size(); ++q)
        B(Index(q), Index(k)) = r(f.free[q], f.comps[k]);
    solve_factor(impl_->c, f, B, v);
  }
}

void CholmodSolver::solve(const Operators& ops, const SparseRowMatrix& mt,
                          const LoopConstraints& bc, const Field& p, Field& v) {
  const Index n = ops.num_nodes();
  const int d = int(p.cols());
  cholmod_common& c = impl_->c;
  const Field prescribed =
      prescribed_components(bc, ops.active, ops.m, p,
                            options_.mass_cutoff > 0 ? options_.mass_cutoff * ops.m.maxCoeff() : 0);
  v.setZero(n, d);
  size_t slot = 0;
  for (const auto& [F, comps] : free_groups(ops, prescribed)) {
    if (slot >= impl_->factors.size())
      impl_->factors.emplace_back();
    Factor& f = impl_->factors[slot++];
    std::vector<int> local(static_cast<size_t>(n), -1);
    for (size_t k = 0; k < F.size(); ++k)
      local[size_t(F[k])] = int(k);
    const bool same_pattern =
        restrict_matrix(ops, mt, options_.regularization, local, f, F, f.L != nullptr);
    f.comps = comps;
    if (F.empty())
      continue;
    cholmod_sparse A = as_cholmod(f);
    if (!same_pattern) {
      if (f.L)
        cholmod_free_factor(&f.L, &c);
      f.L = cholmod_analyze(&A, &c);
      if (!f.L)
        throw NumericalError("CHOLMOD could not analyse the consistent mass matrix");
      ++impl_->analyses;
    }
    cholmod_factorize(&A, f.L, &c);
    ++impl_->factorizations;
    if (c.status == CHOLMOD_NOT_POSDEF || f.L->minor < f.L->n)
      not_positive_definite(ops, f, long(f.L->minor));
    impl_->rcond = cholmod_rcond(f.L, &c);
    Eigen::MatrixXd B =
        right_hand_sides(ops, mt, 1 - options_.regularization, p, prescribed, F, local, comps, v);
    solve_factor(c, f, B, v);
  }
  impl_->used = slot;
  impl_->rows = n;
  // Components whose free set is empty keep only their prescribed values.
  for (int a = 0; a < d; ++a)
    for (Index i = 0; i < n; ++i)
      if (ops.active[i] && !std::isnan(prescribed(i, a)))
        v(i, a) = prescribed(i, a);
}

// ---- UmfpackSolver: the same equations with a general (non-symmetric) m̃ ----

namespace {
// Right-hand sides b = p_F − (1 − ε) m̃_FC v_C of a general m̃ (row by row: m̃_lc ≠ m̃_cl), one
// column per component; sets v_C in v.
Eigen::MatrixXd general_right_hand_sides(const SparseRowMatrix& mt, double blend, const Field& p,
                                         const Field& prescribed, const std::vector<int>& F,
                                         const std::vector<int>& comps, Field& v) {
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  for (const int comp : comps)
    for (Index i = 0; i < prescribed.rows(); ++i)
      if (!std::isnan(prescribed(i, comp)))
        v(i, comp) = prescribed(i, comp);
  Eigen::MatrixXd B(F.size(), comps.size());
  for (size_t k = 0; k < comps.size(); ++k) {
    const int comp = comps[k];
    for (size_t l = 0; l < F.size(); ++l) {
      double b = p(F[l], comp);
      for (int q = ro[F[l]]; q < ro[F[l] + 1]; ++q)
        if (const double vc = prescribed(ri[q], comp); !std::isnan(vc))
          b -= blend * rv[q] * vc;
      B(Index(l), Index(k)) = b;
    }
  }
  return B;
}

// v(F, comps) = m̃_FF⁻¹ B with the LU factors of f (UMFPACK_At: f holds m̃_FFᵀ in CSC).
void solve_lu(LuFactor& f, const Eigen::MatrixXd& B, Field& v) {
  Eigen::VectorXd x(B.rows());
  double info[UMFPACK_INFO];
  for (size_t k = 0; k < f.comps.size(); ++k) {
    const int status =
        umfpack_di_solve(UMFPACK_At, f.colptr.data(), f.rowind.data(), f.values.data(), x.data(),
                         B.col(Index(k)).data(), f.numeric, nullptr, info);
    if (status < 0)
      throw NumericalError("UMFPACK could not solve with the mass matrix m~_L (status " +
                           std::to_string(status) + ")");
    for (size_t q = 0; q < f.free.size(); ++q)
      v(f.free[q], f.comps[k]) = x[Index(q)];
  }
}
} // namespace

struct UmfpackSolver::Impl {
  std::vector<LuFactor> factors;
  size_t used = 0; // factors of the last solve
  Index rows = 0;  // nodes of the last solve
  long analyses = 0, factorizations = 0;
  double rcond = std::numeric_limits<double>::quiet_NaN();
  ~Impl() {
    for (LuFactor& f : factors)
      f.release();
  }
};

UmfpackSolver::UmfpackSolver(const ExactOptions& options)
    : impl_(std::make_unique<Impl>()), options_(options) {
  validate(options_);
}
UmfpackSolver::~UmfpackSolver() = default;
long UmfpackSolver::analyses() const {
  return impl_->analyses;
}
long UmfpackSolver::factorizations() const {
  return impl_->factorizations;
}
double UmfpackSolver::last_rcond() const {
  return impl_->rcond;
}

void UmfpackSolver::solve(const Operators& ops, const SparseRowMatrix& mt,
                          const LoopConstraints& bc, const Field& p, Field& v) {
  const Index n = ops.num_nodes();
  const int d = int(p.cols());
  const Field prescribed =
      prescribed_components(bc, ops.active, ops.m, p,
                            options_.mass_cutoff > 0 ? options_.mass_cutoff * ops.m.maxCoeff() : 0);
  v.setZero(n, d);
  size_t slot = 0;
  double info[UMFPACK_INFO];
  for (const auto& [F, comps] : free_groups(ops, prescribed)) {
    if (slot >= impl_->factors.size())
      impl_->factors.emplace_back();
    LuFactor& f = impl_->factors[slot++];
    std::vector<int> local(static_cast<size_t>(n), -1);
    for (size_t k = 0; k < F.size(); ++k)
      local[size_t(F[k])] = int(k);
    const bool same_pattern =
        restrict_matrix(ops, mt, options_.regularization, local, f, F, f.symbolic != nullptr);
    f.comps = comps;
    f.release_numeric();
    if (F.empty())
      continue;
    const int m = int(F.size());
    if (!same_pattern) {
      f.release();
      if (umfpack_di_symbolic(m, m, f.colptr.data(), f.rowind.data(), f.values.data(), &f.symbolic,
                              nullptr, info) != UMFPACK_OK)
        throw NumericalError("UMFPACK could not analyse the mass matrix m~_L");
      ++impl_->analyses;
    }
    const int status = umfpack_di_numeric(f.colptr.data(), f.rowind.data(), f.values.data(),
                                          f.symbolic, &f.numeric, nullptr, info);
    ++impl_->factorizations;
    if (status == UMFPACK_WARNING_singular_matrix || status < 0)
      throw NumericalError("the mass matrix m~_L of the velocity-gradient transfer is singular on "
                           "the active nodes (UMFPACK status " +
                           std::to_string(status) +
                           "); smallest lumped masses: " + lightest_nodes(ops, F) + kRemedies);
    impl_->rcond = info[UMFPACK_RCOND];
    const Eigen::MatrixXd B =
        general_right_hand_sides(mt, 1 - options_.regularization, p, prescribed, F, comps, v);
    solve_lu(f, B, v);
  }
  impl_->used = slot;
  impl_->rows = n;
  for (int a = 0; a < d; ++a)
    for (Index i = 0; i < n; ++i)
      if (ops.active[i] && !std::isnan(prescribed(i, a)))
        v(i, a) = prescribed(i, a);
}

void UmfpackSolver::solve_again(const Field& r, Field& v) {
  SMPM_VERIFY(r.rows() == impl_->rows, "solve_again: " + std::to_string(r.rows()) +
                                           " rows after a solve of " + std::to_string(impl_->rows));
  v.setZero(r.rows(), r.cols());
  for (size_t s = 0; s < impl_->used; ++s) {
    LuFactor& f = impl_->factors[s];
    if (f.free.empty() || !f.numeric)
      continue;
    Eigen::MatrixXd B(f.free.size(), f.comps.size());
    for (size_t k = 0; k < f.comps.size(); ++k)
      for (size_t q = 0; q < f.free.size(); ++q)
        B(Index(q), Index(k)) = r(f.free[q], f.comps[k]);
    solve_lu(f, B, v);
  }
}

} // namespace smpm
