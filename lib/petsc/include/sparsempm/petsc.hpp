// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file petsc.hpp
/// The operators of FMPM 2026 §2.1 and the FMPM(k) loop of Table 1 across MPI ranks, on PETSc
/// (the component sparsempm::petsc; find_package(sparsempm COMPONENTS petsc)).
///
/// The structured grid maps one to one onto a PETSc DMDA, which distributes its nodes in boxes;
/// a rank owns the particles whose cell it owns (the cell whose lowest corner node it owns) and
/// assembles S, G and M of those particles on their window of the grid with the serial library
/// (assemble with NodeRange::Particles: its owned nodes and the ghost nodes its particles reach).
/// The node sums are PETSc's: m = Sᵀ M and p = Sᵀ M V are added into distributed Vecs, and
/// m̃ = Sᵀ diag(M) S into an MPIAIJ matrix, each rank adding its particles' terms and PETSc's
/// assembly sending the rows other ranks own. Every node and field is one row of m and m̃ (row
/// AO(i)·fields + α for node i of field α, AO the DMDA's natural-to-PETSc ordering); a node field
/// of d components is a Vec of d entries per row (interlaced), on which m̃ acts as a MAIJ matrix.
///
/// Results equal the serial library's to round-off, not to the bit: the sums run in another
/// order across ranks.

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/fmpm.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/spectrum.hpp"
#include "sparsempm/stability.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/step_options.hpp"

#include <petscdmda.h>
#include <petscmat.h>
#include <petscvec.h>

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

/// The distributed component: the operators and FMPM(k) on PETSc across MPI ranks.
namespace smpm::petsc {

/// Throws NumericalError "<call>: <PETSc's message>" unless `code` is 0.
void check(PetscErrorCode code, const char* call);
/// Calls a PETSc function and throws NumericalError naming it when it fails.
#define SMPM_PETSC_CALL(call) ::smpm::petsc::check((call), #call)

/// PETSc and SLEPc for the life of the object: SlepcInitialize (which initialises PETSc and MPI)
/// and SlepcFinalize. One per process, before any other function of this component.
class Session {
public:
  /// Initialises with the program's arguments (PETSc reads its -options from them).
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

/// Sole owner of a PETSc object, destroyed with it (Vec, Mat, IS, VecScatter, KSP, ...).
template <class T, PetscErrorCode (*Destroy)(T*)>
class Owned {
public:
  Owned() = default;
  /// Takes `handle` over.
  explicit Owned(T handle) : h_(handle) {}
  ~Owned() { reset(); }
  Owned(Owned&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Owned& operator=(Owned&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  /// The handle (null when empty).
  T get() const { return h_; }
  /// The handle, for PETSc calls.
  operator T() const { return h_; }
  /// Destroys the object held, and returns where a Create call puts the new one.
  T* out() {
    reset();
    return &h_;
  }
  /// Destroys the object held.
  void reset() {
    if (h_)
      Destroy(&h_);
    h_ = nullptr;
  }

private:
  T h_ = nullptr;
};
/// An owned PETSc Vec.
using OwnedVec = Owned<Vec, VecDestroy>;
/// An owned PETSc Mat.
using OwnedMat = Owned<Mat, MatDestroy>;
/// An owned PETSc DM.
using OwnedDM = Owned<DM, DMDestroy>;
/// An owned PETSc IS.
using OwnedIS = Owned<IS, ISDestroy>;
/// An owned PETSc VecScatter.
using OwnedScatter = Owned<VecScatter, VecScatterDestroy>;

/// A structured grid distributed over the ranks of a communicator by a PETSc DMDA with one degree
/// of freedom per velocity field: each rank owns a box of nodes (owned()).
class DistributedGrid {
public:
  /// The DMDA of `grid` (a whole grid, not a window) with `fields` unknowns per node, its boxes
  /// chosen by PETSc (PETSC_DECIDE) unless `ranks_per_axis` gives them. Collective.
  DistributedGrid(const Grid& grid, int fields = 1, MPI_Comm comm = PETSC_COMM_WORLD,
                  const std::array<int, 3>& ranks_per_axis = {0, 0, 0});
  /// The whole grid.
  const Grid& grid() const { return grid_; }
  /// The window of the nodes this rank owns.
  const Grid& owned() const { return owned_; }
  /// Velocity fields (unknowns per node).
  int fields() const { return fields_; }
  /// The DMDA.
  DM dm() const { return dm_; }
  /// The communicator.
  MPI_Comm comm() const { return comm_; }
  /// This rank and the number of ranks.
  int rank() const { return rank_; }
  /// Number of ranks of the communicator.
  int size() const { return size_; }
  /// Rows (nodes × fields) this rank owns, and the first of them.
  PetscInt owned_rows() const { return PetscInt(owned_.num_nodes()) * fields_; }
  /// The PETSc row of this rank's first owned row.
  PetscInt first_row() const { return first_row_; }
  /// Rows of the whole grid: nodes × fields.
  PetscInt global_rows() const { return PetscInt(grid_.whole_num_nodes()) * fields_; }
  /// The PETSc rows of whole nodes `nodes` of field `field` (AO(i) · fields + field), written
  /// into `rows`. Collective (every rank calls it, with lists of any length).
  void petsc_rows(const std::vector<PetscInt>& nodes, int field, std::vector<PetscInt>& rows) const;
  /// Whether this rank owns the cell (i, j, k): it owns the cell's lowest corner node.
  bool owns_cell(const std::array<int, 3>& cell) const;
  /// The rank that owns the cell (i, j, k) (the DMDA's box of its lowest corner node).
  int owner_of_cell(const std::array<int, 3>& cell) const;
  /// The cell holding position x (clamped to the grid's cells).
  std::array<int, 3> cell_of(const double* x) const;
  /// The particles of `all` whose cell this rank owns, ascending.
  std::vector<Index> owned_particles(const Particles& all) const;

private:
  Grid grid_, owned_;
  std::array<std::vector<int>, 3> box_starts_; // each box's first node along each axis, ascending
  int fields_ = 1;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  PetscInt first_row_ = 0;
  OwnedDM dm_;
};

/// The rows `ids` of `all` (every per-particle column that is not empty).
Particles select_particles(const Particles& all, const std::vector<Index>& ids);

/// The operators of one configuration across ranks (FMPM 2026 §2.1).
struct DistributedOperators {
  Operators local;              ///< S, G, M of this rank's particles on their window
  std::vector<Index> particles; ///< the particle (in the whole set) of each row of local.S
  std::vector<PetscInt> rows;   ///< the PETSc row of each column of local.S
  int dim = 1;                  ///< d
  OwnedVec m;                   ///< lumped masses m = Sᵀ M (one entry per row)
  OwnedVec m_inv;               ///< 1/m on active rows, 0 elsewhere
  OwnedVec m_inv_d;             ///< m_inv repeated for the d components of a node field
  OwnedMat mt;                  ///< m̃ = Sᵀ diag(M) S, MPIAIJ, rows × rows
  OwnedMat mt_d;                ///< m̃ acting on node fields of d components (MAIJ)
  Eigen::Array<bool, Eigen::Dynamic, 1> active; ///< the owned rows' activity (owned layout)
  double max_mass = 0; ///< the largest total nodal mass Σ_α m^α_i over every node
};

/// Assembles the operators of `particles` (this rank's particles, ids their index in the whole
/// set) on the distributed grid: m, m̃ and the active set as in the serial assemble (a row is
/// active when m^α_i > kMassTolerance max_j Σ_α m^α_j). `field`: the velocity field of each of
/// these particles (one field when null). Collective.
void assemble(const DistributedGrid& grid, const Particles& particles,
              const std::vector<Index>& ids, Shape shape, DistributedOperators& ops,
              const Eigen::VectorXi* field = nullptr);
/// The same for a whole particle set known on every rank: each rank takes the particles whose
/// cell it owns (owned_particles). `field` has one entry per particle of `all`.
void assemble(const DistributedGrid& grid, const Particles& all, Shape shape,
              DistributedOperators& ops, const Eigen::VectorXi* field = nullptr);

class WindowSums;

/// The distributed operators of one step across ranks (a Stepper with NodeSums) from each rank's
/// share: `local`, the step's operators on its window with the total masses (complete_masses),
/// and `mt`, its particles' m̃ on the window, `sums` bound to that window: m from the window's
/// totals, m̃ the ranks' m̃ added into an MPIAIJ matrix, the active rows by the serial rule.
/// ops.local and ops.particles are left empty. Collective.
void assemble_step(const DistributedGrid& grid, const WindowSums& sums, const Operators& local,
                   const SparseRowMatrix& mt, int dim, DistributedOperators& ops);

/// A node field of `components` entries per row (rows × components), zero. Collective.
OwnedVec node_vector(const DistributedGrid& grid, int components);
/// p = Sᵀ M V of this rank's particles (V: one row per row of ops.local.S) added over ranks.
/// Collective.
OwnedVec momentum(const DistributedGrid& grid, const DistributedOperators& ops,
                  const ConstFieldRef& V);

/// The rows this rank owns of a node field `x` in the serial layout on the window owned():
/// row α n_o + i for node i of the window and field α (n_o its nodes), `components` columns.
void get_owned(const DistributedGrid& grid, Vec x, int components, Field& out);
/// Writes the owned rows of `x` from a field in get_owned's layout.
void set_owned(const DistributedGrid& grid, const Field& in, Vec x);
/// The whole node field on rank 0 in the serial layout on the whole grid (row α n_g + i, as
/// the serial operators with NodeRange::Grid number it); empty on the other ranks. Collective.
Field gather(const DistributedGrid& grid, Vec x, int components);
/// The whole matrix (rows × rows) on rank 0 in the serial numbering α n_g + i; empty (0 × 0)
/// on the other ranks. Collective.
SparseMatrix gather(const DistributedGrid& grid, Mat a);

/// Scratch vectors of the distributed loop.
struct DistributedFmpmWorkspace {
  OwnedVec prev, next, product; ///< Δv(ℓ), Δv(ℓ + 1) and m̃ Δv(ℓ)
  OwnedVec residual;            ///< r(ℓ) of the Chebyshev and least-squares members
  PolynomialPasses passes;      ///< their coefficients (polynomial_passes)
  Field owned;                  ///< the owned rows of a vector for the velocity BCs
  std::vector<double> metrics;  ///< the metric of each pass (dynamic FMPM)
};

/// v⁺(k) = m̃_k⁻¹ p⁺ across ranks: FMPM 2026 Table 1 by fmpm_recursion (the serial loop's own
/// control, fmpm.hpp) with m̃'s MatMult; on entry v holds v⁺(1). The velocity BCs of `bc` (whose
/// grid is ignored: each rank applies them on the nodes it owns) zero the BC directions of
/// every increment for the Incremental method, and are set on v⁺(k) for the Velocity and
/// Combined methods; dynamic FMPM's metric is summed over the ranks. Collective.
FmpmReport fmpm_velocity(const DistributedGrid& grid, const DistributedOperators& ops,
                         const FmpmOptions& opt, const LoopConstraints& bc, Vec v,
                         DistributedFmpmWorkspace& w);
/// The grid velocity from the updated momentum p⁺, as the serial updated_velocity: the lumped
/// BCs on p⁺ (Table 2's top block, unless the method is Velocity with k > 1), v⁺(1) = m⁻¹ p⁺,
/// then for k > 1 fmpm_velocity. `p_plus` is changed by the lumped BCs. Collective.
FmpmReport updated_velocity(const DistributedGrid& grid, const DistributedOperators& ops,
                            const FmpmOptions& opt, const LoopConstraints& bc, Vec p_plus, Vec v,
                            DistributedFmpmWorkspace& w);

/// The linear solvers of the distributed exact solve (exact_solve): conjugate gradients with a
/// preconditioner, or a parallel sparse Cholesky factorisation.
enum class ExactMethod {
  CgJacobi,         ///< CG, Jacobi (diagonal) preconditioner
  CgBlockJacobiIcc, ///< CG, block Jacobi with one block per rank, each an ICC(0) factor
  CgGamg,           ///< CG, PETSc's algebraic multigrid GAMG
  MumpsCholesky     ///< MUMPS's parallel sparse Cholesky factorisation (a direct solve)
};
/// Names: cg-jacobi | cg-bjacobi-icc | cg-gamg | mumps-cholesky.
std::string_view to_string(ExactMethod m);
/// Inverse of to_string; throws InputError naming the valid choices.
ExactMethod exact_method_from_string(std::string_view name);

/// The settings of exact_solve.
struct DistributedExactOptions {
  ExactOptions exact{}; ///< regularisation ε and mass cutoff τ, as the serial CholmodSolver's
  ExactMethod method = ExactMethod::CgBlockJacobiIcc; ///< the linear solver
  double rtol = 1e-13;         ///< CG: stop at ‖r‖ ≤ rtol ‖b‖ (preconditioned norm)
  int max_iterations = 100000; ///< CG: the most iterations of one system
};

/// What exact_solve did.
struct ExactSolveReport {
  int systems = 0;     ///< linear systems solved: one per group of components with one free set
  int iterations = 0;  ///< CG iterations over every system (1 per system for MUMPS)
  double residual = 0; ///< the largest ‖b_F − K_FF x_F‖ / ‖b_F‖ of the systems
};

/// v = m̃⁻¹ p across ranks with the equations of the serial CholmodSolver (exact.hpp): for each
/// velocity component, m̃_FF v_F = p_F − m̃_FC v_C on the active nodes F free in that component,
/// the prescribed components (velocity conditions along axes, and with mass cutoff τ > 0 the
/// lumped velocity of nodes lighter than τ max m) known, v = 0 on inactive nodes; with
/// regularisation ε > 0 the blended mass (1 − ε) m̃ + ε m. The system is K_FF, the submatrix of
/// the free rows and columns (MatCreateSubMatrix); components with the same free set share one
/// KSP (and one factorisation), and CG starts from the lumped velocity p_F / m_F. PETSc options
/// with the prefix exact_ (-exact_ksp_type, -exact_pc_type, ...) override the method. Throws
/// NumericalError naming the solver's reason when it does not converge. Collective.
ExactSolveReport exact_solve(const DistributedGrid& grid, const DistributedOperators& ops,
                             const DistributedExactOptions& options, const LoopConstraints& bc,
                             Vec p, Vec v);

/// The spectrum of the mass matrices across ranks (the serial mass_spectrum of spectrum.hpp,
/// FMPM 2026 §2.2) on the active rows: λ_min(m⁻¹m̃) as the smallest eigenvalue of the symmetric
/// B = m^{-1/2} m̃ m^{-1/2} (the generalised problem m̃ x = λ m x in symmetric form) and
/// ρ(A) = 1 − λ_min(B); cond(m̃) = λ_max / λ_min of m̃. By SLEPc's Krylov–Schur (EPS_HEP,
/// tolerance `tol`, options prefix mass_): the largest eigenvalues directly, the smallest by
/// shift-and-invert with a MUMPS Cholesky factor, so that they keep their relative accuracy
/// however ill-conditioned m̃ is. Where B or m̃ is singular on the active rows (the factorisation
/// fails) the smallest is λ_max − λ_max(λ_max I − ·), as the serial code computes it. Throws
/// NumericalError when an eigensolve does not converge. Collective.
MassSpectrum mass_spectrum(const DistributedGrid& grid, const DistributedOperators& ops,
                           double tol = 1e-12);

/// The node sums of a step across ranks (NodeSums, fmpm.hpp) on a window of the grid (this rank's
/// particles' window): add() adds every rank's window rows into a distributed Vec (a VecScatter
/// in reverse with ADD_VALUES) and scatters the totals back to each window, ghost nodes included
/// (the same scatter forward). The window is bound by bind() (each step's preparation binds its
/// operators) or at construction from a DistributedOperators. Every collective call starts with
/// one MPI_Allreduce of two flags (a rank failed, a window changed), so that a rank's fail()
/// meets the others' next call. Collective.
class WindowSums final : public NodeSums {
public:
  /// Sums over the ranks of `grid` (which must outlive this), bound to no window yet.
  explicit WindowSums(const DistributedGrid& grid);
  /// Sums on the window of `ops` over the ranks of `grid` (both must outlive this).
  WindowSums(const DistributedGrid& grid, const DistributedOperators& ops);
  ~WindowSums() override;
  WindowSums(const WindowSums&) = delete;
  WindowSums& operator=(const WindowSums&) = delete;
  /// Binds the window's PETSc rows (AO(node · fields + α)); its scatters are remade on every rank
  /// when any rank's window changed. `fields` must be the grid's.
  void bind(const Grid& window, int fields) override;
  /// The totals over the ranks of every row of `window` (rows: the window's columns).
  void add(Field& window) const override;
  /// The largest of `value` over the ranks.
  double maximum(double value) const override;
  /// Each of values[0 .. count) summed over the ranks (MPI_Allreduce).
  void sum(double* values, int count) const override;
  /// The window's rows inserted into a distributed Vec (the scatter in reverse, inserting: every
  /// node reaches its owner, held in its window or not), summed per column over the owned rows
  /// and over the ranks.
  void sum_rows(const Field& window, double* totals) const override;
  /// This rank's step failed: the other ranks' pending collective call throws FailedElsewhere.
  void fail() const override;
  /// A window field of totals (the same on every rank that holds a row) into the owners' rows of
  /// `global`, a node_vector of window.cols() components (the scatter in reverse, inserting).
  void to_global(const Field& window, Vec global) const;
  /// Every row of the window, ghost rows included, from `global` (the scatter forward).
  void to_window(Vec global, Field& window) const;
  /// The PETSc row of each column of the bound window.
  const std::vector<PetscInt>& rows() const;
  /// The bytes this rank sent and received through the scatters so far: each scatter moves the
  /// window rows another rank owns (8 bytes per component); the reductions' few values are
  /// not counted. For the benchmarks' communicated bytes per step.
  double communicated_bytes() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The exact update's m̃⁻¹ in a step across ranks (StepOptions::exact_solver) whose node sums are
/// `sums` (on the window of `ops`): each solve takes the window's momentum totals into a
/// distributed Vec (WindowSums::to_global), solves m̃ v = p by exact_solve (the velocity BCs of
/// the step, the factory's ε and τ) with the m̃ of `ops` (assembled on the step's particles in
/// the same configuration) and returns v on the window (WindowSums::to_window). The arguments
/// must outlive the solvers. Collective, as every solve.
MassSolverFactory distributed_mass_solver_factory(const DistributedGrid& grid,
                                                  const DistributedOperators& ops,
                                                  const WindowSums& sums, ExactMethod method);
/// The exact update's m̃⁻¹ in a simulation across ranks (a Stepper with `sums`, whose window
/// changes from step to step): each solve assembles the distributed m̃ of the step's operators
/// (assemble_step, from the m̃ the step hands it) and solves as distributed_mass_solver_factory's
/// solvers do. The arguments must outlive the solvers. Collective, as every solve.
MassSolverFactory step_mass_solver_factory(const DistributedGrid& grid, const WindowSums& sums,
                                           ExactMethod method);

/// ρ(T) of the one-step update linearised at the model's frozen configuration (LinearizedStep,
/// stability.hpp) across ranks: each rank's LinearizedStep acts on its particles' (V, σ) with the
/// step's node sums over the ranks (WindowSums), as a PETSc MATSHELL, by the serial
/// spectral_radius's rule: up to kDenseRadiusRows rows SLEPc's Krylov–Schur finds the dominant
/// eigenvalue (EPS_NHEP, largest magnitude, tolerance `tol`, options prefix rho_); above,
/// kPowerApplications power iterations (from the serial power_start, the same for any number
/// of ranks) measure the growth, reported as ρ = 1 within kUnitGrowthBand, and Krylov–Schur
/// starts from the power iterate when the growth exceeds that. `model` is the whole model on
/// every rank (a rank may own no particle). The status is the serial spectral_radius's:
/// Converged, NotConverged (ρ is NaN up to the dense limit, SLEPc keeping no estimate of an
/// unconverged eigenvalue, and the measured growth above it), or NonFinite (the step met a
/// non-finite value on some rank; ρ = +inf). FLIP, PIC, FMPM(k) (plain, blended, periodic) and the
/// exact update (its m̃⁻¹ by distributed_mass_solver_factory with `exact`, in place of
/// options.exact_solver) in single material mode. Collective.
SpectralRadius spectral_radius(const DistributedGrid& grid, const Model& model,
                               const StepOptions& options, double dt, double tol = 1e-10,
                               ExactMethod exact = ExactMethod::CgBlockJacobiIcc);
/// The critical Courant number of the serial critical_courant (the same search,
/// critical_courant_search: bracketing, bisection, the hint) with ρ(T(C)) across ranks
/// (spectral_radius above, eigensolver tolerance 1e-10; the step's operators assembled once).
/// Collective.
CriticalCourant critical_courant(const DistributedGrid& grid, const Model& model,
                                 const StepOptions& options, double tol = 1e-6, double c_max = 2.0,
                                 double resolution = 1e-3, double hint = 0,
                                 ExactMethod exact = ExactMethod::CgBlockJacobiIcc);

} // namespace smpm::petsc
