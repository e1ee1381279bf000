// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file exact.hpp
/// The exact consistent-mass inverse v = m̃⁻¹ p ("FMPM(∞)") with a CHOLMOD Cholesky factor
/// of m̃ (or of m̃_A of the APIC transfer) restricted to the active, unconstrained nodes, or
/// UMFPACK's LU for the non-symmetric m̃_L of the velocity-gradient transfer.

#include "sparsempm/step_options.hpp"

#include <memory>

namespace smpm {

/// CHOLMOD's Cholesky factorisation of a symmetric m̃_FF (the back end of CholmodSolver; defined
/// in exact.cpp, so that no CHOLMOD header is included here).
struct CholmodBackend;
/// UMFPACK's sparse LU factorisation of a general m̃_FF (the back end of UmfpackSolver).
struct UmfpackBackend;
/// The preconditioned conjugate gradient on a symmetric m̃_FF (the back end of PcgSolver).
struct PcgBackend;

/// Solves m̃_FF v_F = p_F − m̃_FC v_C for each velocity component, F the active nodes free in
/// that component and C those whose component is prescribed (v_C = v_b). This is the k → ∞
/// limit of the incremental BC method of FMPM 2026 §3.1: (I − ΦA)⁻¹ v⁺(1). Velocity
/// conditions must be along axes. The symbolic factorisation is reused while the pattern of
/// m̃ and the sets F are unchanged; the numeric one is redone every call. `Backend` factors
/// m̃_FF: CholmodBackend (CholmodSolver) or UmfpackBackend (UmfpackSolver), the only two
/// instances (exact.cpp).
///
/// Two documented departures from m̃⁻¹ remedy a m̃_FF that cannot be factored (ExactOptions;
/// docs/studies/stability.md, "The exact inverse"): with regularization ε ∈ (0, 1] the solver
/// factors the blended mass (1 − ε) m̃ + ε m of FMPM 2026 §3.3 (rows still sum to m, so a uniform
/// translation keeps its velocity; the k → ∞ limit of FMPM(k) blended with α = 1 − ε, m = 1); with
/// mass_cutoff τ > 0 nodes lighter than τ max m take their lumped velocity p_i/m_i and enter the
/// equations of the others as known values (like velocity BCs).
template <class Backend>
class FactoredMassSolver final : public MassSolver {
public:
  /// Throws OptionError for settings outside their ranges (validate of step_options.hpp).
  explicit FactoredMassSolver(const ExactOptions& options = {});
  ~FactoredMassSolver() override;
  FactoredMassSolver(const FactoredMassSolver&) = delete;
  FactoredMassSolver& operator=(const FactoredMassSolver&) = delete;

  /// v = m̃⁻¹ p by the equations above, one set per group of components with the same free
  /// nodes (v = 0 on inactive nodes). Throws NumericalError when m̃_FF cannot be factored.
  void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
             const Field& p, Field& v) override;
  /// m̃_FF x_F = r_F with the factors of the last solve, x = 0 off F (no refactorisation).
  void solve_again(const Field& r, Field& v) override;

  /// The settings the solver was made with.
  const ExactOptions& options() const { return options_; }
  /// Number of symbolic analyses (cholmod_analyze, umfpack_di_symbolic) so far: one per change
  /// of pattern.
  long analyses() const;
  /// Number of numeric factorisations (cholmod_factorize, umfpack_di_numeric) so far.
  long factorizations() const;
  /// The back end's reciprocal condition estimate of the last factorisation: CHOLMOD's
  /// (min diag L / max diag L)², UMFPACK's RCOND.
  double last_rcond() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ExactOptions options_;
};

/// The exact inverse of the symmetric m̃ (and of the capacity matrix c̃) with a CHOLMOD Cholesky
/// factor of m̃_FF. When m̃_FF is not positive definite a NumericalError names the matrix
/// (ExactOptions::system), the node where CHOLMOD found a non-positive pivot and the nodes of
/// smallest lumped mass (or capacity). A solver made for m̃_L (NodalSystem::GradientMass, not
/// symmetric) throws UsageError.
using CholmodSolver = FactoredMassSolver<CholmodBackend>;
/// The same equations (velocity BCs, regularisation, mass cutoff) for a general, non-symmetric
/// m̃: m̃_L of the velocity-gradient transfer (Transfer::VelocityGradient), by UMFPACK's sparse
/// LU of m̃_FF. Its rows still sum to m, so the regularised (1 − ε) m̃_L + ε m keeps uniform
/// motion. Throws NumericalError naming the lightest nodes when m̃_FF is singular.
using UmfpackSolver = FactoredMassSolver<UmfpackBackend>;

/// The same equations for a symmetric m̃ (m̃, m̃_A, c̃) by Eigen's ConjugateGradient, preconditioned
/// by the diagonal of m̃_FF or its IncompleteCholesky (ExactOptions::preconditioner), from
/// v_F = 0 to the relative residual ExactOptions::tolerance: m̃⁻¹ to that tolerance, not to
/// round-off. It keeps no factor: solve_again iterates again. A NumericalError names the
/// residual and iterations reached when it does not converge in max(100, 10 |F|) iterations.
using PcgSolver = FactoredMassSolver<PcgBackend>;

extern template class FactoredMassSolver<CholmodBackend>;
extern template class FactoredMassSolver<UmfpackBackend>;
extern template class FactoredMassSolver<PcgBackend>;

/// The known velocities of the exact solve: the prescribed velocity of every (active node, axis)
/// with a condition of `bc` (FMPM 2026 Table 2's superposition rule, boundary.hpp; directions
/// within round-off of an axis taken as the axis), NaN where the component is free; active nodes
/// with m_i < `light` take their lumped velocity p_i / m_i in their free components (light ≤ 0:
/// none). Rows: the nodes of bc.grid (times the fields) with `active` and `m`; p: n × d.
/// Shared by the serial solvers and the distributed one (sparsempm::petsc) on its owned nodes.
Field prescribed_components(const LoopConstraints& bc,
                            const Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                            const Eigen::VectorXd& m, const Field& p, double light);

/// The factory of CholmodSolvers for StepOptions::exact_solver: every Stepper (and every copy of
/// the options it runs with) gets a solver of its own, with the settings StepOptions::exact.
/// Symmetric matrices only (a solver made for NodalSystem::GradientMass throws).
MassSolverFactory cholmod_solver_factory();
/// The factory the reader, the command line and Python use: with ExactOptions::method PCG a
/// PcgSolver; else a CholmodSolver for symmetric matrices (m̃, m̃_A, the capacity matrix), an
/// UmfpackSolver otherwise (m̃_L; the Stepper sets ExactOptions::system from
/// StepOptions::transfer, velocity_solver_options).
MassSolverFactory exact_solver_factory();

} // namespace smpm
