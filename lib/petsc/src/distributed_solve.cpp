// SPDX-License-Identifier: BSD-3-Clause
// The exact consistent-mass solve (KSP, MUMPS) and the mass spectrum (SLEPc) across ranks.
#include "sparsempm/petsc.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/exact.hpp"

#include <petscksp.h>
#include <slepceps.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace smpm::petsc {

namespace {
constexpr std::array<std::pair<ExactMethod, std::string_view>, 4> kMethods{{
    {ExactMethod::CgJacobi, "cg-jacobi"},
    {ExactMethod::CgBlockJacobiIcc, "cg-bjacobi-icc"},
    {ExactMethod::CgGamg, "cg-gamg"},
    {ExactMethod::MumpsCholesky, "mumps-cholesky"},
}};

using OwnedKSP = Owned<KSP, KSPDestroy>;
using OwnedEPS = Owned<EPS, EPSDestroy>;

// The PETSc row of row r of the owned layout (α n_o + i, get_owned).
PetscInt petsc_row(const DistributedGrid& grid, Index r) {
  const Index no = grid.owned().num_nodes();
  return grid.first_row() + PetscInt((r % no) * grid.fields() + r / no);
}

void configure(KSP ksp, const DistributedExactOptions& o) {
  PC pc = nullptr;
  SMPM_PETSC_CALL(KSPGetPC(ksp, &pc));
  if (o.method == ExactMethod::MumpsCholesky) {
    SMPM_PETSC_CALL(KSPSetType(ksp, KSPPREONLY));
    SMPM_PETSC_CALL(PCSetType(pc, PCCHOLESKY));
    SMPM_PETSC_CALL(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  } else {
    SMPM_PETSC_CALL(KSPSetType(ksp, KSPCG));
    SMPM_PETSC_CALL(KSPSetTolerances(ksp, o.rtol, 0.0, PETSC_DEFAULT, o.max_iterations));
    SMPM_PETSC_CALL(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
    switch (o.method) {
    case ExactMethod::CgJacobi:
      SMPM_PETSC_CALL(PCSetType(pc, PCJACOBI));
      break;
    case ExactMethod::CgBlockJacobiIcc:
      SMPM_PETSC_CALL(PCSetType(pc, PCBJACOBI));
      break;
    default:
      SMPM_PETSC_CALL(PCSetType(pc, PCGAMG));
    }
  }
  SMPM_PETSC_CALL(KSPSetOptionsPrefix(ksp, "exact_"));
  SMPM_PETSC_CALL(KSPSetFromOptions(ksp));
  SMPM_PETSC_CALL(KSPSetUp(ksp));
  PCType type = nullptr;
  SMPM_PETSC_CALL(PCGetType(pc, &type));
  if (o.method == ExactMethod::CgBlockJacobiIcc && std::string_view(type) == PCBJACOBI) {
    // ICC(0) in each rank's block (PETSc's default sub-preconditioner is ILU(0)).
    PetscInt blocks = 0, first = 0;
    KSP* sub = nullptr;
    SMPM_PETSC_CALL(PCBJacobiGetSubKSP(pc, &blocks, &first, &sub));
    for (PetscInt b = 0; b < blocks; ++b) {
      PC subpc = nullptr;
      SMPM_PETSC_CALL(KSPGetPC(sub[b], &subpc));
      SMPM_PETSC_CALL(PCSetType(subpc, PCICC));
      SMPM_PETSC_CALL(KSPSetFromOptions(sub[b]));
    }
  }
}

// The extreme eigenvalue of the symmetric `a` by SLEPc's Krylov–Schur: the largest, or with
// `smallest` the one nearest 0 by shift-and-invert (a MUMPS Cholesky factor of a): accurate to
// `tol` relative to itself, where the largest of λ_max I − a would lose λ_max/λ_min digits.
double extreme_eigenvalue(Mat a, double tol, bool smallest, const char* what) {
  OwnedEPS eps;
  MPI_Comm comm = MPI_COMM_NULL;
  SMPM_PETSC_CALL(PetscObjectGetComm(PetscObject(a), &comm));
  SMPM_PETSC_CALL(EPSCreate(comm, eps.out()));
  SMPM_PETSC_CALL(EPSSetOperators(eps, a, nullptr));
  SMPM_PETSC_CALL(EPSSetProblemType(eps, EPS_HEP));
  SMPM_PETSC_CALL(EPSSetType(eps, EPSKRYLOVSCHUR));
  PetscInt n = 0;
  SMPM_PETSC_CALL(MatGetSize(a, &n, nullptr));
  SMPM_PETSC_CALL(EPSSetDimensions(eps, 1, std::min<PetscInt>(n, 40), PETSC_DEFAULT));
  SMPM_PETSC_CALL(EPSSetTolerances(eps, tol, 10000));
  if (smallest) {
    SMPM_PETSC_CALL(EPSSetWhichEigenpairs(eps, EPS_TARGET_MAGNITUDE));
    SMPM_PETSC_CALL(EPSSetTarget(eps, 0.0));
    ST st = nullptr;
    KSP ksp = nullptr;
    PC pc = nullptr;
    SMPM_PETSC_CALL(EPSGetST(eps, &st));
    SMPM_PETSC_CALL(STSetType(st, STSINVERT));
    SMPM_PETSC_CALL(STGetKSP(st, &ksp));
    SMPM_PETSC_CALL(KSPSetType(ksp, KSPPREONLY));
    SMPM_PETSC_CALL(KSPGetPC(ksp, &pc));
    SMPM_PETSC_CALL(PCSetType(pc, PCCHOLESKY));
    SMPM_PETSC_CALL(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  } else {
    SMPM_PETSC_CALL(EPSSetWhichEigenpairs(eps, EPS_LARGEST_REAL));
  }
  SMPM_PETSC_CALL(EPSSetOptionsPrefix(eps, "mass_"));
  SMPM_PETSC_CALL(EPSSetFromOptions(eps));
  SMPM_PETSC_CALL(EPSSolve(eps));
  PetscInt converged = 0;
  SMPM_PETSC_CALL(EPSGetConverged(eps, &converged));
  if (converged < 1) {
    EPSConvergedReason reason;
    SMPM_PETSC_CALL(EPSGetConvergedReason(eps, &reason));
    throw NumericalError(std::string("SLEPc's Krylov-Schur did not converge to the ") +
                         (smallest ? "smallest" : "largest") + " eigenvalue of " + what + " (" +
                         EPSConvergedReasons[reason] + ")");
  }
  PetscScalar re = 0, im = 0;
  SMPM_PETSC_CALL(EPSGetEigenvalue(eps, 0, &re, &im));
  return re;
}
} // namespace

std::string_view to_string(ExactMethod m) {
  for (const auto& [method, name] : kMethods)
    if (method == m)
      return name;
  return "?";
}

ExactMethod exact_method_from_string(std::string_view name) {
  std::string valid;
  for (const auto& [method, text] : kMethods) {
    if (text == name)
      return method;
    valid += (valid.empty() ? "" : " | ") + std::string(text);
  }
  throw InputError("unknown exact solver '" + std::string(name) + "' (valid: " + valid + ")");
}

namespace {
// The known components on the owned nodes (the serial solver's rule; τ of the largest m): the
// prescribed values, NaN where a component is free.
Field known_components(const DistributedGrid& grid, const DistributedOperators& ops,
                       const ExactOptions& exact, const LoopConstraints& bc, const Field& p_owned,
                       const Eigen::VectorXd& m) {
  double local_max = m.size() ? m.maxCoeff() : 0.0, max_m = 0;
  MPI_Allreduce(&local_max, &max_m, 1, MPI_DOUBLE, MPI_MAX, grid.comm());
  LoopConstraints owned_bc = bc;
  owned_bc.grid = &grid.owned();
  return prescribed_components(owned_bc, ops.active, m, p_owned,
                               exact.mass_cutoff > 0 ? exact.mass_cutoff * max_m : 0.0);
}

// K = (1 − ε) m̃ + ε m                                              (FMPM 2026 §3.3)
OwnedMat regularized_mass(const DistributedOperators& ops, double eps) {
  OwnedMat K;
  SMPM_PETSC_CALL(MatDuplicate(ops.mt, MAT_COPY_VALUES, K.out()));
  if (eps > 0) {
    OwnedVec em;
    SMPM_PETSC_CALL(VecDuplicate(ops.m, em.out()));
    SMPM_PETSC_CALL(VecCopy(ops.m, em));
    SMPM_PETSC_CALL(VecScale(em, eps));
    SMPM_PETSC_CALL(MatScale(K, 1 - eps));
    SMPM_PETSC_CALL(MatDiagonalSet(K, em, ADD_VALUES));
  }
  return K;
}

// F of component a: the active rows whose component is free, in PETSc order, with the lumped
// velocity p/m that starts CG in `guess`; the known values of the other active rows in `kx`.
void free_rows_of(const DistributedGrid& grid, const DistributedOperators& ops, const Field& known,
                  const Field& p_owned, const Eigen::VectorXd& m, int a,
                  std::vector<PetscInt>& free_rows, Field& kx, Field& guess) {
  const Index n = p_owned.rows();
  free_rows.clear();
  kx = Field::Zero(n, 1);
  guess = Field::Zero(n, 1);
  for (Index r = 0; r < n; ++r) {
    if (ops.active[r] && std::isnan(known(r, a))) {
      free_rows.push_back(petsc_row(grid, r));
      guess(r, 0) = p_owned(r, a) / m[r]; // the lumped velocity starts CG
    } else if (ops.active[r]) {
      kx(r, 0) = known(r, a);
    }
  }
  std::sort(free_rows.begin(), free_rows.end());
}

// The true residual ‖b_F − K_FF x_F‖ / ‖b_F‖ (‖b_F − K_FF x_F‖ when b_F = 0).
double true_residual(Mat KFF, Vec bF, Vec xF) {
  OwnedVec r;
  SMPM_PETSC_CALL(VecDuplicate(bF, r.out()));
  SMPM_PETSC_CALL(MatMult(KFF, xF, r));
  SMPM_PETSC_CALL(VecAYPX(r, -1.0, bF));
  PetscReal rn = 0, bn = 0;
  SMPM_PETSC_CALL(VecNorm(r, NORM_2, &rn));
  SMPM_PETSC_CALL(VecNorm(bF, NORM_2, &bn));
  return bn > 0 ? double(rn / bn) : double(rn);
}

// The system K_FF x_F = b_F of the free rows F of a component, and its solver.
struct FreeSystem {
  OwnedIS free_is;
  OwnedMat KFF;
  OwnedKSP ksp;
  std::vector<PetscInt> last_rows; // the F of the last system made
  bool have_last = false;

  // K_FF and its solver, unless every rank has the free rows of the last component.
  void update(const DistributedGrid& grid, Mat K, const std::vector<PetscInt>& free_rows,
              const DistributedExactOptions& o, ExactSolveReport& report) {
    int same = have_last && free_rows == last_rows, all_same = 0;
    MPI_Allreduce(&same, &all_same, 1, MPI_INT, MPI_LAND, grid.comm());
    if (all_same)
      return;
    SMPM_PETSC_CALL(ISCreateGeneral(grid.comm(), PetscInt(free_rows.size()), free_rows.data(),
                                    PETSC_COPY_VALUES, free_is.out()));
    SMPM_PETSC_CALL(MatCreateSubMatrix(K, free_is, free_is, MAT_INITIAL_MATRIX, KFF.out()));
    SMPM_PETSC_CALL(MatSetOption(KFF, MAT_SPD, PETSC_TRUE));
    SMPM_PETSC_CALL(KSPCreate(grid.comm(), ksp.out()));
    SMPM_PETSC_CALL(KSPSetOperators(ksp, KFF, KFF));
    configure(ksp, o);
    ++report.systems;
    last_rows = free_rows;
    have_last = true;
  }

  // x_F from b_F (the free rows of b and x, x_F starting from x's), refused when the solver does
  // not converge; its iterations and true residual go into `report`.
  void solve(Vec b, Vec x, int a, const DistributedExactOptions& o, ExactSolveReport& report) {
    PetscInt nf = 0;
    SMPM_PETSC_CALL(MatGetSize(KFF, &nf, nullptr));
    if (nf == 0)
      return;
    Vec bF = nullptr, xF = nullptr;
    SMPM_PETSC_CALL(VecGetSubVector(b, free_is, &bF));
    SMPM_PETSC_CALL(VecGetSubVector(x, free_is, &xF));
    SMPM_PETSC_CALL(KSPSolve(ksp, bF, xF));
    KSPConvergedReason reason;
    SMPM_PETSC_CALL(KSPGetConvergedReason(ksp, &reason));
    PetscInt its = 0;
    SMPM_PETSC_CALL(KSPGetIterationNumber(ksp, &its));
    if (reason < 0)
      throw NumericalError("the exact solve (" + std::string(to_string(o.method)) +
                           ") of velocity component " + std::to_string(a) +
                           " did not converge: " + KSPConvergedReasons[reason] + " after " +
                           std::to_string(int(its)) + " iterations");
    report.iterations += int(std::max<PetscInt>(its, 1));
    report.residual = std::max(report.residual, true_residual(KFF, bF, xF));
    SMPM_PETSC_CALL(VecRestoreSubVector(b, free_is, &bF));
    SMPM_PETSC_CALL(VecRestoreSubVector(x, free_is, &xF));
  }
};
} // namespace

ExactSolveReport exact_solve(const DistributedGrid& grid, const DistributedOperators& ops,
                             const DistributedExactOptions& o, const LoopConstraints& bc, Vec p,
                             Vec v) {
  validate(o.exact);
  const int d = ops.dim;
  const double eps = o.exact.regularization;
  Field p_owned, m_owned;
  get_owned(grid, p, d, p_owned);
  get_owned(grid, ops.m, 1, m_owned);
  const Eigen::VectorXd m = m_owned.col(0);
  const Field known = known_components(grid, ops, o.exact, bc, p_owned, m);
  const OwnedMat K = regularized_mass(ops, eps);
  ExactSolveReport report;
  OwnedVec b, known_x, Kx, x;
  SMPM_PETSC_CALL(VecDuplicate(ops.m, b.out()));
  SMPM_PETSC_CALL(VecDuplicate(ops.m, known_x.out()));
  SMPM_PETSC_CALL(VecDuplicate(ops.m, Kx.out()));
  SMPM_PETSC_CALL(VecDuplicate(ops.m, x.out()));
  FreeSystem system;
  std::vector<PetscInt> free_rows;
  Field v_owned = Field::Zero(p_owned.rows(), d);
  const Index n = p_owned.rows();
  for (int a = 0; a < d; ++a) {
    // F: the active rows whose component is free, in PETSc order; the known values in known_x.
    Field kx, guess;
    free_rows_of(grid, ops, known, p_owned, m, a, free_rows, kx, guess);
    set_owned(grid, kx, known_x);
    set_owned(grid, guess, x);
    // b = p − K v_C over every row; b_F the right-hand side p_F − K_FC v_C.
    SMPM_PETSC_CALL(VecStrideGather(p, a, b, INSERT_VALUES));
    SMPM_PETSC_CALL(MatMult(K, known_x, Kx));
    SMPM_PETSC_CALL(VecAXPY(b, -1.0, Kx));
    system.update(grid, K, free_rows, o, report);
    system.solve(b, x, a, o, report);
    Field xo;
    get_owned(grid, x, 1, xo);
    for (Index r = 0; r < n; ++r) // the known values exactly, 0 on inactive nodes
      v_owned(r, a) = !ops.active[r] ? 0.0 : std::isnan(known(r, a)) ? xo(r, 0) : known(r, a);
  }
  set_owned(grid, v_owned, v);
  return report;
}

MassSpectrum mass_spectrum(const DistributedGrid& grid, const DistributedOperators& ops,
                           double tol) {
  // The active rows, in PETSc order (the owned layout's rows sorted by their PETSc row).
  std::vector<PetscInt> act;
  std::vector<double> scale;
  Field m_owned;
  get_owned(grid, ops.m, 1, m_owned);
  std::vector<std::pair<PetscInt, double>> rows;
  for (Index r = 0; r < ops.active.size(); ++r)
    if (ops.active[r])
      rows.emplace_back(petsc_row(grid, r), m_owned(r, 0));
  std::sort(rows.begin(), rows.end());
  for (const auto& [row, mass] : rows) {
    act.push_back(row);
    scale.push_back(1 / std::sqrt(mass));
  }
  OwnedIS is;
  SMPM_PETSC_CALL(
      ISCreateGeneral(grid.comm(), PetscInt(act.size()), act.data(), PETSC_COPY_VALUES, is.out()));
  OwnedMat K, B;
  SMPM_PETSC_CALL(MatCreateSubMatrix(ops.mt, is, is, MAT_INITIAL_MATRIX, K.out()));
  PetscInt na = 0;
  SMPM_PETSC_CALL(MatGetSize(K, &na, nullptr));
  MassSpectrum out;
  out.active = Index(na);
  // ρ(A) = λ_max(I − B), B = m^{-1/2} m̃ m^{-1/2}.
  OwnedVec s;
  SMPM_PETSC_CALL(MatCreateVecs(K, s.out(), nullptr));
  PetscScalar* sa = nullptr;
  SMPM_PETSC_CALL(VecGetArray(s, &sa));
  std::copy(scale.begin(), scale.end(), sa);
  SMPM_PETSC_CALL(VecRestoreArray(s, &sa));
  SMPM_PETSC_CALL(MatDuplicate(K, MAT_COPY_VALUES, B.out()));
  SMPM_PETSC_CALL(MatDiagonalScale(B, s, s));
  // λ_min(B) = λ_min(m⁻¹m̃) by shift-and-invert, ρ(A) = 1 − λ_min(B); where B is singular on
  // the active rows (its factorisation fails), ρ(A) = λ_max(I − B) as the serial code.
  try {
    out.min_eig_minv_mt = extreme_eigenvalue(B, tol, true, "m^-1/2 m~ m^-1/2");
    out.rho_A = 1 - out.min_eig_minv_mt;
  } catch (const NumericalError&) {
    SMPM_PETSC_CALL(MatScale(B, -1.0));
    SMPM_PETSC_CALL(MatShift(B, 1.0));
    out.rho_A = extreme_eigenvalue(B, tol, false, "I - m^-1/2 m~ m^-1/2");
    out.min_eig_minv_mt = 1 - out.rho_A;
  }
  // cond(m̃) = λ_max / λ_min on the active rows; λ_min by shift-and-invert, or where m̃ is
  // singular there (its factorisation fails) by λ_max − λ_max(λ_max I − m̃), as the serial code.
  const double lmax = extreme_eigenvalue(K, tol, false, "m~");
  double lmin = 0;
  try {
    lmin = extreme_eigenvalue(K, tol, true, "m~");
  } catch (const NumericalError&) {
    SMPM_PETSC_CALL(MatScale(K, -1.0));
    SMPM_PETSC_CALL(MatShift(K, lmax));
    lmin = lmax - extreme_eigenvalue(K, tol, false, "lambda_max I - m~");
  }
  out.cond_mt = lmin > 0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  return out;
}

} // namespace smpm::petsc
