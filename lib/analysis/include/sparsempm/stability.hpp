// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file stability.hpp
/// Temporal stability of the MPM update (FMPM 2026 §3.3, Fig. 12), by two methods:
///   - spectral: the one-step update linearised at a frozen particle configuration is a linear
///     operator T(C) on the particle state x = (V, σ); the scheme is stable at Courant number
///     C when ρ(T(C)) ≤ 1 + tol (critical_courant);
///   - simulation: bisection on C over full runs (simulation_courant), as in the paper.

#include "sparsempm/advance.hpp"
#include "sparsempm/step.hpp"

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace smpm {

/// One step linearised at a frozen configuration (positions, S, G, M, m, m̃, volumes, F and the
/// material tangent fixed), acting on x = (V, σ) with N d + N d² entries (x = (V, σ, L) with an
/// affine transfer, whose particle terms L_p are state: P2G reads them and the particle update
/// sets them to G u, or APIC's moment B_p, both linear in the state). It runs the Stepper's
/// own stages (scheme_step of scheme.hpp) on the frozen operators with homogeneous velocity
/// BCs (their directions with zero values: the linear part of the step) and no body force; the
/// strain update is σ' = σ + Δt 𝕂 : L with L = Σ_i v_i ⊗ G_pi and 𝕂_p = ∂σ/∂L at F_p (from
/// F' = (I + Δt L) F by central differences; exact for the linear model). Every scheme (USL,
/// USF, USL+, USAVG, USAVG+), velocity update, BC method and ordering is covered; positions are
/// frozen, so α of Eqs. (8)–(9) does not enter T; moving walls are frozen on the nodes they
/// select at the configuration analysed. Periodic FMPM with C_X is the product of one
/// FMPM step and the ceil(C_X / C) − 1 FLIP steps between (the Stepper's period). The operator
/// concept is Spectra's: rows(), cols(), perform_op(x, y).
class LinearizedStep {
public:
  using Scalar = double; ///< the scalar of Spectra's operator concept
  /// Validates the options (validate of step.hpp); throws InputError for dynamic FMPM, whose
  /// state-dependent order is not a linear map.
  LinearizedStep(const Model& model, const StepOptions& options, double dt);
  /// The same across processes (fmpm.hpp, NodeSums): `model` holds this process's particles
  /// (possibly none) and the whole grid; the operators are assembled on the particles' window,
  /// m and the active set are made the totals over the processes, and each application sums the
  /// step's node fields over them (StepContext::sums), so that T acts on the state of this
  /// process's particles. FLIP, PIC, FMPM(k) and the exact update (whose options.exact_solver
  /// must solve across the processes) in single material mode, without moving walls. Collective,
  /// as every perform_op.
  LinearizedStep(const Model& model, const StepOptions& options, double dt, NodeSums& sums);
  ~LinearizedStep();
  /// Takes over the frozen configuration and its operators.
  LinearizedStep(LinearizedStep&&) noexcept;

  /// Changes Δt (and so C) keeping every assembled operator.
  void set_dt(double dt);
  /// The time step Δt of T.
  double dt() const;
  /// Time steps spanned by one application of T (1, or ceil(C_X / C) for periodic FMPM).
  int steps_per_application() const;
  /// N d + N d², the entries of x = (V, σ); N d² more with an affine transfer, whose particle
  /// terms L_p are state (P2G reads them, the particle update sets them): x = (V, σ, L).
  Index rows() const;
  /// rows(): T is square.
  Index cols() const { return rows(); }
  /// y = T x. Throws NumericalError when the stages meet a non-finite value.
  void perform_op(const double* x, double* y) const;
  /// T as a dense matrix (one perform_op per column; for small problems).
  Eigen::MatrixXd dense() const;
  /// The assembled operators of the frozen configuration.
  const Operators& operators() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  void init(const Model& model, const StepOptions& options, double dt, NodeSums* sums);
};

/// How a spectral radius was obtained.
enum class SpectralStatus {
  Converged,    ///< dense eigenvalues, the power-iteration plateau, or converged Arnoldi
  NotConverged, ///< Arnoldi did not converge: rho_T is the measured growth per application
  NonFinite     ///< the iteration overflowed or met NaN: rho_T = +inf (never "stable")
};
/// Name in tables: converged | not converged | non-finite.
std::string_view to_string(SpectralStatus s);

/// A spectral radius ρ(T) and how it was obtained (spectral_radius).
struct SpectralRadius {
  double rho_T = std::numeric_limits<double>::quiet_NaN(); ///< ρ(T); +inf when NonFinite
  SpectralStatus status = SpectralStatus::Converged;       ///< how rho_T was obtained
};

/// The rule of spectral_radius above its dense limit, shared with the ρ(T) across ranks of
/// sparsempm::petsc: the rows up to which T's eigenvalues are computed directly, the power
/// iterations that measure the growth per application (over their second half), and the
/// distance from 1 within which that growth is reported as ρ = 1.
inline constexpr Index kDenseRadiusRows = 1500;
/// Power iterations of spectral_radius above kDenseRadiusRows (the growth over the second half).
inline constexpr int kPowerApplications = 300;
/// A measured growth within this of 1 is reported as ρ = 1.
inline constexpr double kUnitGrowthBand = 1e-3;
/// The start of spectral_radius's power iterations on T of `rows` rows: standard normal draws
/// (std::mt19937 seeded 1), normalised. The ρ(T) across ranks starts from the same vector.
Eigen::VectorXd power_start(Index rows);

/// The rule of ρ(T) for any storage of the vectors: spectral_radius (Eigen vectors, Spectra)
/// and the ρ(T) across ranks of sparsempm::petsc (PETSc Vecs, SLEPc) run this one function.
/// Up to `dense_limit` rows `alg.small()` resolves |λ|max directly. Above, where T crowds the unit
/// circle (eigenvalue 1 of force-free stresses, |λ| ≈ 1 of every elastic mode) and Krylov
/// methods converge very slowly, kPowerApplications power iterations from alg.start() measure the
/// growth per application over their second half: within kUnitGrowthBand of 1 it is ρ = 1, below
/// 1 it is ρ; otherwise an eigenvalue stands out and alg.resolve(rate) resolves it from the power
/// iterate. `alg` supplies:
///   - alg.rows(); alg.small(); alg.start() (x = power_start's vector);
///   - alg.apply() (y = T x; false when a kernel met a non-finite value);
///   - alg.norm() (‖y‖₂); alg.next(g) (x = y / g);
///   - alg.resolve(rate): |λ|max from x (status NotConverged with `rate` when that fails).
template <class Algebra>
SpectralRadius spectral_radius_rule(Algebra& alg, Index dense_limit) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (alg.rows() <= dense_limit)
    return alg.small();
  alg.start();
  double log_growth = 0;
  for (int k = 0; k < kPowerApplications; ++k) {
    if (!alg.apply())
      return {inf, SpectralStatus::NonFinite};
    const double g = alg.norm();
    if (!std::isfinite(g))
      return {inf, SpectralStatus::NonFinite};
    if (!(g > 0))
      return {0.0, SpectralStatus::Converged}; // T x = 0: x was in the null space
    if (k >= kPowerApplications / 2)
      log_growth += std::log(g);
    alg.next(g);
  }
  const double rate = std::exp(log_growth / (kPowerApplications - kPowerApplications / 2));
  if (std::abs(rate - 1) <= kUnitGrowthBand)
    return {1.0, SpectralStatus::Converged};
  if (rate < 1)
    return {rate, SpectralStatus::Converged};
  return alg.resolve(rate);
}

/// ρ(T): dense Eigen eigenvalues when T has at most `dense_limit` rows. Above, matrix-free:
/// 300 power iterations measure the growth per application; growth within 10⁻³ of 1 is
/// reported as ρ = 1 (T has the eigenvalue 1 of force-free stresses, and crowds the unit circle
/// with its elastic modes), otherwise Spectra's GenEigsSolver started from the power iterate
/// returns the dominant |λ| (status NotConverged with the measured growth if it fails).
SpectralRadius spectral_radius(const LinearizedStep& T, Index dense_limit = kDenseRadiusRows);

/// What a stability search found below its C* (CriticalCourant::small): whether every smaller C it
/// examined is stable, down to C → 0. Above the dense limit of spectral_radius a growth within
/// 10⁻³ of 1 per application is reported as ρ = 1, at small C as at any C: Stable there means
/// stable to that band.
enum class SmallCourant {
  Stable,        ///< every C examined below C* is stable, and so is the limit C → 0
  StableToFloor, ///< every C examined below C* down to the floor is stable; no limit examined
  NotExamined,   ///< no C below e_1 = 0.05 examined (C → 0 taken as stable, as bisection did)
  UnstableBelow, ///< an unstable C (or the limit C → 0) lies below the interval [stable_from, C*]
  Unstable       ///< no C examined is stable: C* = 0
};
/// Name in tables: "stable" | "stable to floor" | "not examined" | "unstable below" | "unstable".
std::string_view to_string(SmallCourant s);

/// The lowest point 0.05 / 4^j of the search of critical_courant is the first at or below this
/// floor (7.8·10⁻⁴), where the limit C → 0 takes over.
inline constexpr double kCourantFloor = 1e-3;
/// The limit C → 0 is evaluated at this fraction of the lowest point (T(0) itself has Δt = 0).
inline constexpr double kLimitFraction = 1e-6;

/// What the search of critical_courant examines below its first edge e_1 = min(0.05, c_max):
/// the points e_1 / 4^j (j ≥ 1) down to the first at or below `floor`, and with `limit` the limit
/// C → 0; none when floor ≥ e_1 (SmallCourant::NotExamined). A periodic FMPM's T(C) spans
/// ⌈C_X / C⌉ steps, so that one evaluation at C = 0.0125 costs 160 steps for C_X = 2, as much as
/// the rest of its search: critical_courant examines no small C for it.
struct SmallCourantScan {
  /// the lowest point examined is the first e_1 / 4^j ≤ floor (none when floor ≥ e_1)
  double floor = kCourantFloor;
  bool limit = true; ///< also the limit C → 0 (operators that span one step)
};

/// The critical Courant number C* of critical_courant (the spectral method), with the cost of its
/// search. The names are the tables' columns (critical_courant, rho_T, stable_from,
/// small_courant; `smpm stability`).
struct CriticalCourant {
  /// C*: the upper end of the stable interval [stable_from, C*]: the largest C found with
  /// ρ(T(C)) ≤ 1 + tol (within `resolution`) before the first unstable C above stable_from
  double critical_courant = 0;
  /// The lower end: 0 when every C examined below C* is stable (small = Stable or
  /// StableToFloor) and when none is (Unstable), NaN when small C were not examined
  /// (NotExamined); otherwise the first stable grid point (spacing
  /// ≤ resolution) above the highest unstable C, or the lowest point examined when only the limit
  /// C → 0 is unstable.
  double stable_from = 0;
  SmallCourant small = SmallCourant::Stable; ///< what lies below the interval
  double floor = 0; ///< the lowest C examined (e_1 / 4^j; e_1 when NotExamined), the limit aside
  /// ρ(T) as C → 0 (at kLimitFraction of the floor): the zero-order term. NaN: not examined.
  double rho_limit = std::numeric_limits<double>::quiet_NaN();
  /// γ, the first-order term of ρ(T(C)) ≈ ρ(T(0)) + γ C + a C², i.e. the growth over the time
  /// of one C = 1 step as C → 0: by Richardson extrapolation from the two lowest points c and
  /// 4c, (16 d(c) − d(4c)) / 12c with d = ρ − ρ(T(0)) (the secant d(c) / c when ρ(4c) is not
  /// finite or there is one point). The limit is stable when ρ(T(0)) ≤ 1 + tol and γ ≤ tol (the
  /// bound a step at C = 1 is held to); an instability with γ > 0 grows at the same rate per unit
  /// time however small Δt is, one with a C² term alone does not. An estimate from two points:
  /// where ρ − 1 levels off below c it is smaller than the slope at 0. NaN: not examined.
  double growth_rate = std::numeric_limits<double>::quiet_NaN();
  double rho_T = 0;      ///< ρ(T) at C* (the growth per step, ρ^{1/s})
  int evaluations = 0;   ///< spectral radii computed
  int not_converged = 0; ///< of them, Arnoldi runs that did not converge
  int non_finite = 0;    ///< of them, non-finite results (counted as unstable)
};

/// The words of a table for what lies below C*: "stable to 0" | "stable to 0.0125" (the floor; no
/// limit examined) | "not examined below 0.05" | "unstable below 0.04238" (stable_from) |
/// "unstable" (C* = 0).
std::string small_courant_text(const CriticalCourant& c);
/// The same from its parts (CriticalFourier's of transport_stability.hpp).
std::string small_courant_text(SmallCourant small, double stable_from, double floor);
/// Whether the small values of one search are worse than another's: SmallCourant's order
/// (Stable, StableToFloor, NotExamined, UnstableBelow, Unstable), then the larger stable_from.
/// The choice of ConfigurationSweep::lowest and of the transport stability table.
bool worse_small(SmallCourant a, double stable_from_a, SmallCourant b, double stable_from_b);
/// The cell of a table over configurations (smpm stability's small_courant, smpm
/// transport-stability's small_fourier): small_courant_text's words, with the `configuration`
/// that set them when an unstable value lies below, and ": no <parameter> stable on every
/// configuration" when stable_from exceeds `smallest`, the smallest C* or F* of the row.
std::string small_courant_cell(SmallCourant small, double stable_from, double floor,
                               const std::string& configuration, double smallest,
                               std::string_view parameter);

/// The critical Courant number C* = max{C : ρ(T(C))^{1/s} ≤ 1 + tol}, s the steps spanned by
/// T (the growth per step), over the stable interval that holds the smallest stable C. The
/// search first examines small C from the bottom up: the limit C → 0 (ρ(T(0)) and the
/// first-order term γ, CriticalCourant::growth_rate) and the points e_1 / 4^j (e_1 = 0.05:
/// 0.0125, 0.003125, 7.8·10⁻⁴) down to the first at or below kCourantFloor: 4 evaluations. An
/// unstable point there sets stable_from (bisected to `resolution` against the next stable point;
/// the lowest point when only the limit is unstable) and the status small; an unstable point above
/// a stable one ends the interval there. From the interval's start C* is bracketed by doubling from
/// C = 0.05 up to c_max and refined by bisection on a grid of spacing ≤ resolution in that bracket.
/// A non-finite ρ counts as unstable. With `hint` > 0 (the C* of a neighbouring scheme, e.g. FMPM(k
/// − 1) on the same lattice: C* changes little with k) the bracket search starts there and gallops
/// to the transition: the same C* (the same grid point, if stability is monotone in C) in fewer
/// evaluations; the hint is not used when the interval starts above the small C, or when it lies
/// below the interval's start. Periodic FMPM examines no small C (small_courant_scan). Throws
/// InputError unless tol is non-negative and finite, and Interrupted when `interrupt` (a flag a
/// signal handler sets) is set before an evaluation.
CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol = 1e-6,
                                 double c_max = 2.0, double resolution = 1e-3, double hint = 0,
                                 const std::atomic<int>* interrupt = nullptr);

/// The search of critical_courant for any way of computing ρ(T(C)): `radius(C, steps)` returns
/// ρ(T(C)) and sets the steps T spans (the distributed ρ(T) of sparsempm::petsc uses it). `small`
/// says how far below C = 0.05 it looks.
CriticalCourant
critical_courant_search(const std::function<SpectralRadius(double courant, int& steps)>& radius,
                        double tol = 1e-6, double c_max = 2.0, double resolution = 1e-3,
                        double hint = 0, const std::atomic<int>* interrupt = nullptr,
                        const SmallCourantScan& small = {});

/// What critical_courant examines below C = 0.05 for these options: down to kCourantFloor and
/// the limit C → 0, or, for periodic FMPM, nothing (floor = +∞).
SmallCourantScan small_courant_scan(const StepOptions& options);

/// The model with every particle translated by `shift` (in cells along each axis); boundary
/// conditions stay on their nodes. Throws NumericalError if a particle leaves the grid.
Model shifted(const Model& model, const std::array<double, 3>& shift);

/// C* over a set of particle configurations: the smallest and that of each configuration.
struct ConfigurationSweep {
  CriticalCourant minimum;   ///< the smallest C* found
  std::string configuration; ///< which configuration set it, e.g. "shift 0.25"
  /// The search whose small C are the worst (SmallCourant's order, then the largest
  /// stable_from): every configuration is stable on [lowest.stable_from,
  /// minimum.critical_courant] at the points examined, an interval that is empty when
  /// lowest.stable_from > minimum.critical_courant (no C examined is stable on every
  /// configuration; `smpm stability` says so).
  CriticalCourant lowest;
  std::string lowest_configuration;                ///< which configuration set it
  std::vector<std::pair<std::string, double>> all; ///< every configuration and its C*
};

/// A uniform shift of the particle lattice relative to the grid, in cells along each axis.
struct LatticeShift {
  std::array<double, 3> cells{0, 0, 0}; ///< the shift along each axis, in cells
  std::string name;                     ///< e.g. "shift 0.125" (in cells along x)
};

/// Most shifts of lattice_shifts.
inline constexpr int kMaxLatticeShifts = 1000;
/// The shifts of sweep_shifts: j/shifts (j = 0 … shifts − 1) of the particle spacing 2r⁰ (the
/// lattice's period) along every axis at once. Throws InputError unless 1 ≤ shifts ≤
/// kMaxLatticeShifts.
std::vector<LatticeShift> lattice_shifts(const Model& model, int shifts);

/// A particle configuration the spectral C* is computed at, with its name in tables ("shift
/// 0.125", "frame 12").
struct Configuration {
  Model model;      ///< the model in that configuration
  std::string name; ///< its name in tables
};

/// The model at each of lattice_shifts (shifted), named by the shift.
std::vector<Configuration> lattice_configurations(const Model& model, int shifts);

/// A family of step options searched one after the other at each configuration (FMPM(k) for
/// increasing k with one blending, say). With `hinted`, each search starts from the C* of the
/// previous option at the same configuration (critical_courant's hint: the same C*, fewer
/// evaluations, since C* changes little between neighbouring k, FMPM 2026 Fig. 12A); without
/// (periodic FMPM, whose T(C) spans ⌈C_X/C⌉ steps, a count that jumps with C, so that its
/// stability need not be monotone in C), every search starts from scratch.
struct CourantSeries {
  std::vector<StepOptions> options; ///< searched in this order at each configuration
  bool hinted = true;               ///< start each search from the previous option's C*
};

/// The spectral C* of every option of every series at every configuration, and its minimum over
/// them: out[s][i] is the sweep of option i of series s. One task per (series, configuration),
/// run by run_tasks on `workers` threads (0: threads()); the results do not depend on their
/// number. The spectral column of `smpm stability` and Python's sweep_shifts. `interrupt` as for
/// critical_courant (every task stops at its next evaluation).
std::vector<std::vector<ConfigurationSweep>>
sweep_configurations(const std::vector<Configuration>& configurations,
                     const std::vector<CourantSeries>& series, double tol = 1e-6,
                     double resolution = 1e-3, int workers = 0,
                     const std::atomic<int>* interrupt = nullptr);

/// How sweep_configurations finds the C* of one option at one configuration, starting from
/// `hint` (critical_courant's hint; 0: no hint): critical_courant on this process, or the same
/// search with ρ(T) across MPI ranks (sparsempm::petsc's critical_courant).
using CriticalSearch =
    std::function<CriticalCourant(const Model& model, const StepOptions& options, double hint)>;

/// sweep_configurations with any search. With workers = 1 the tasks run in order on the calling
/// thread, as a search that is collective across MPI ranks needs (every rank makes the same
/// calls in the same order).
std::vector<std::vector<ConfigurationSweep>>
sweep_configurations(const std::vector<Configuration>& configurations,
                     const std::vector<CourantSeries>& series, const CriticalSearch& search,
                     int workers);

/// C* over uniform shifts of the particle lattice relative to the grid (lattice_configurations):
/// the minimum and its shift (named in cells along x, e.g. "shift 0.125").
ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol = 1e-6, double resolution = 1e-3, int workers = 0,
                                const std::atomic<int>* interrupt = nullptr);

/// Runs task(i) for i = 0 … count − 1 on `workers` threads (0: threads()), each with one OpenMP
/// thread: independent analyses on every core. The first failure stops the others (they finish
/// the task in hand) and is rethrown.
void run_tasks(size_t count, const std::function<void(size_t)>& task, int workers = 0);

/// The simulation method of FMPM 2026 §3.3: full runs from t = 0 to `end`, each with the
/// Courant time step held constant (advance with land_on_stops = false).
struct SimulationCourantOptions {
  double end = 0;            ///< length of each run (the paper: five periods)
  double lo = 0.02;          ///< bracket: assumed stable ...
  double hi = 1.5;           ///< ... and tried first as unstable
  double resolution = 0.005; ///< bisection to this width
  FailureTest failure{};     ///< energy growth factor of a failed run
  /// Also fail a run whose total energy changes by more than this fraction of its start
  /// (|E_end − E_0| / E_0): the paper's "largest C with low dissipation". Infinite: off.
  double max_energy_change = std::numeric_limits<double>::infinity();
  /// Stops the runs with Interrupted between steps (AdvanceOptions::interrupt).
  const std::atomic<int>* interrupt = nullptr;
};

/// The critical Courant number C* of simulation_courant (the simulation method). The names are
/// the columns of `smpm stability` (simulation_courant, energy_change).
struct SimulationCourant {
  /// C* by simulation: the largest C whose run does not fail; NaN: unstable even at lo
  double simulation_courant = std::numeric_limits<double>::quiet_NaN();
  double energy_change = std::numeric_limits<double>::quiet_NaN(); ///< (E_end − E_0)/E_0 there
  int runs = 0;                                                    ///< full runs made
};

/// Relative change of total energy of one run at Courant number C, or NaN when it fails (a
/// NumericalError of the stages, the failure test, or the energy-change limit).
double simulation_energy_change(const Model& model, const StepOptions& options, double courant,
                                const SimulationCourantOptions& sim);

/// The largest C in [lo, hi] whose run does not fail, by bisection to ±resolution (hi itself
/// when it does not fail). With a finite max_energy_change the criterion is not monotone in C
/// (dissipation accumulates over the many steps of a small C), so the bracket is first scanned
/// from hi down on 16 intervals and the bisection refines the largest passing point.
SimulationCourant simulation_courant(const Model& model, const StepOptions& options,
                                     const SimulationCourantOptions& sim);

} // namespace smpm
