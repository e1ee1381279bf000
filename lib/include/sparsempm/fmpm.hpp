// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file fmpm.hpp
/// The approximate full-mass inverse FMPM(k) (Nairn 2026, §2.2, Table 1) and XPIC(m)
/// (Nairn, Hammerquist & Smith 2020, Eqs. 36, 41–43), as products with the assembled m̃.
///
///   v⁺(k) = m̃_k⁻¹ p⁺ = Σ_{ℓ=1}^{k} Δv(ℓ),  Δv(1) = m⁻¹ p⁺,  Δv(ℓ) = A Δv(ℓ−1)   (Eqs. 5–6)
///   A = I − m⁻¹ m̃ = I − S⁺ S                                                     (Eq. 1)

#include "sparsempm/boundary.hpp"
#include "sparsempm/operators.hpp"

#include <functional>
#include <string_view>
#include <vector>

namespace smpm {

/// Velocity-BC methods compared in FMPM 2026 §3.1.
enum class BCMethod {
  Incremental, ///< lumped BCs on v⁺(1), then zero BC directions of every Δv(ℓ) (the paper's new
               ///< method)
  Lumped,   ///< lumped BCs on v⁺(1) only
  Velocity, ///< no lumped BCs; set the BC velocities on v⁺(k) after the loop
  Combined  ///< lumped BCs on v⁺(1) and the BC velocities set on v⁺(k) after the loop
};
/// Convergence metrics of dynamic FMPM (FMPM 2026 §3.4).
enum class ConvergenceMetric {
  None,  ///< run to the order k
  Means, ///< Σ_i |Δv_i(ℓ)| / Σ_i |v⁺_i(ℓ)|
  Changes ///< mean over active nodes of |Δv_i(ℓ)| / (|v⁺_i(ℓ)| + ε), ε = 1% of max_i |v⁺_i(ℓ)|
};

/// The polynomial q of the approximate inverse m̃_k⁻¹ = q(m⁻¹m̃) m⁻¹ that k − 1 products with m̃
/// apply (docs/studies/polynomials.md). Each member keeps v⁺(1) = m⁻¹ p⁺ and takes its first
/// residual r(2) = A v⁺(1) as the series' first increment, so its residual polynomial
/// R_k(λ) = 1 − λ q(λ) on the spectrum λ of m⁻¹m̃ is (1 − λ) R̂_{k−1}(λ), R̂(0) = 1 (R_k(1) = 0:
/// uniform motion is kept exactly; each member is optimal among polynomials of that form), and
/// Table 2's BC methods act on the increments as in the series:
///   - Series: R̂ = (1 − λ)^{k−1}, FMPM 2026 Eqs. 5–6 (and its blends, §3.3);
///   - Chebyshev: R̂ = T_{k−1}((θ − λ)/δ) / T_{k−1}(θ/δ) on [λ_lo, 1], θ = (1 + λ_lo)/2,
///     δ = (1 − λ_lo)/2: the smallest max |R̂| on the interval (Golub & Varga 1961; Saad,
///     "Iterative methods for sparse linear systems", 2nd ed. 2003, §12.3);
///   - LeastSquares: the R_k of that form with the smallest ∫ R_k(λ)² w(λ) dλ on [λ_lo, 1], w the
///     Chebyshev weight 1/√((λ − λ_lo)(1 − λ)) (Saad 1985, "Practical use of polynomial
///     preconditionings for the conjugate gradient method", SIAM J. Sci. Stat. Comput. 6:865);
///   - ChebyshevSquared: R̂ = C_m(λ)² for k − 1 = 2m (C_m the Chebyshev R̂ of degree m: its passes
///     twice, the second from the residual the first left) and (1 − λ) C_m(λ)² for k − 1 = 2m + 1
///     (one more series pass first).
/// The particle update V = S v⁺ carries the modes of m⁻¹m̃ by 1 − R_k(λ). The series and
/// ChebyshevSquared keep 0 ≤ R_k ≤ 1 on [0, 1], so no mode grows; Chebyshev and LeastSquares
/// change sign on the interval, and 1 − R_k > 1 where R_k < 0 grows those modes at every time
/// step, however small (docs/studies/polynomials.md measures what that does to C*).
enum class Polynomial { Series, Chebyshev, LeastSquares, ChebyshevSquared };

/// Name used in input files: incremental | lumped | velocity | combined.
std::string_view to_string(BCMethod m);
/// Inverse of to_string; throws InputError naming the valid choices.
BCMethod bc_method_from_string(std::string_view name);
/// Name used in input files: none | means | changes.
std::string_view to_string(ConvergenceMetric m);
/// Inverse of to_string; throws InputError naming the valid choices.
ConvergenceMetric convergence_metric_from_string(std::string_view name);
/// Name used in input files and tables: series | chebyshev | least_squares | chebyshev_squared.
std::string_view to_string(Polynomial p);
/// Inverse of to_string; throws InputError naming the valid choices.
Polynomial polynomial_from_string(std::string_view name);

/// Largest order k of FMPM(k) (m of XPIC(m)) and blending period accepted by validate.
inline constexpr int kMaxFmpmOrder = 100000;
/// Largest order k of the least-squares polynomial (its recurrence costs O(k²) per loop).
inline constexpr int kMaxLeastSquaresOrder = 2000;

/// The options of the FMPM(k) loop of FMPM 2026 Table 1 (and the order m of XPIC(m)): the
/// order k, blending (§3.3), the velocity-BC method (§3.1) and dynamic FMPM (§3.4).
struct FmpmOptions {
  int order = 1;            ///< k, the number of terms (the maximum order when dynamic)
  double blend_alpha = 1.0; ///< α of the blended recursion (FMPM 2026 §3.3); 1: no blending
  int blend_every = 1;      ///< m: scale by α when ℓ mod m = 1 or m = 1 (FMPM 2026 §3.3)
  BCMethod bc_method = BCMethod::Incremental;         ///< velocity BCs in the loop (§3.1)
  ConvergenceMetric metric = ConvergenceMetric::None; ///< dynamic FMPM (§3.4); None: run to k
  double dynamic_limit = 0;                   ///< stop at the first ℓ whose metric is below this
  Polynomial polynomial = Polynomial::Series; ///< the member of the family (Polynomial)
  /// λ_lo of the Chebyshev and least-squares intervals [λ_lo, 1]: λ_min(m⁻¹m̃) as `smpm
  /// spectrum` prints it covers the spectrum; a larger λ_lo leaves the modes below it less
  /// converged. The Chebyshev members need λ_lo > 0.
  double interval_low = 0;
};

/// Throws OptionError (an InputError naming the option) unless 1 ≤ order ≤ kMaxFmpmOrder,
/// 0 ≤ α ≤ 1, 1 ≤ m ≤ kMaxFmpmOrder, the dynamic limit is ≥ 0 and finite and 0 ≤ λ_lo < 1; for
/// the other members of the family, unless there is no blending, λ_lo > 0 (Chebyshev), no
/// dynamic metric for ChebyshevSquared (its R_k is non-negative only at its order; Chebyshev and
/// least squares are nested families, so stopping at ℓ gives their member of order ℓ) and the
/// least-squares order is at most kMaxLeastSquaresOrder.
void validate(const FmpmOptions& opt);

/// Scale factor of pass ℓ ≥ 2: α if m = 1 or ℓ mod m = 1, else 1 (FMPM 2026 §3.3).
double blend_factor(const FmpmOptions& opt, int ell);

/// The passes of a Chebyshev or least-squares loop: with r(1) = Δv(1) = v⁺(1), pass ℓ ≥ 2 is
///     r(ℓ) = r(ℓ−1) − m⁻¹m̃ Δv(ℓ−1),   Δv(ℓ) = a_ℓ r(ℓ) + b_ℓ Δv(ℓ−1),   v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ),
/// r(ℓ) the residual of v⁺(ℓ−1) on the free directions. The series is a_ℓ = 1, b_ℓ = 0.
struct PolynomialPasses {
  std::vector<double> a;                      ///< a_ℓ at index ℓ − 2, for ℓ = 2 … k
  std::vector<double> b;                      ///< b_ℓ at index ℓ − 2 (b_2 = 0)
  Polynomial polynomial = Polynomial::Series; ///< the member they were made for (the cache's key)
  int order = 0;                              ///< its k
  double interval_low = 0;                    ///< its λ_lo
};
/// a_ℓ and b_ℓ of `opt`'s member from the three-term recurrence of the orthogonal polynomials
/// whose values at 0 normalise R̂ (Chebyshev: its closed form; least squares: the discretised
/// Stieltjes procedure on 2k + 6 Gauss–Chebyshev points, exact for the degrees involved).
/// Empty for the series.
PolynomialPasses polynomial_passes(const FmpmOptions& opt);
/// `cache`, remade by polynomial_passes(opt) unless it was made for the same member, order and
/// interval: what a loop calls on every step.
const PolynomialPasses& polynomial_passes(const FmpmOptions& opt, PolynomialPasses& cache);
/// R_k(λ) = 1 − λ q(λ) of `opt`'s member (blended series included), by the loop's own
/// recurrence on scalars: |R_k| on the spectrum of m⁻¹m̃ is what the member leaves of each mode.
double residual_polynomial(const FmpmOptions& opt, double lambda);

/// Node sums over processes: a process holds the partial sums of its own particles on the nodes
/// of its window of the grid (m = Sᵀ M, p = Sᵀ M V, f, m̃ x); add() replaces them by the sums over
/// every process, on every node of the window (ghost nodes included), so that each process
/// holds its window's totals. The distributed component implements it on PETSc
/// (sparsempm::petsc); where it is null a step runs in one process. Every call is collective:
/// the processes make the same calls in the same order. A process whose step fails
/// calls fail() in place of its next call, and the others' next call throws FailedElsewhere
/// (errors.hpp), so that no process waits for one that stopped.
class NodeSums {
public:
  virtual ~NodeSums() = default;
  /// Takes the columns of a step's operators as the rows of the fields add() sums: `fields`
  /// blocks of the nodes of `window` (Operators::grid and Operators::fields), each process its
  /// own window. Every step's preparation binds its operators before the first sum.
  virtual void bind(const Grid& window, int fields) = 0;
  /// Replaces the partial sums in `window` (one row per column of the operators, any columns)
  /// by the sums over the processes.
  virtual void add(Field& window) const = 0;
  /// The largest of `value` over the processes.
  virtual double maximum(double value) const = 0;
  /// Replaces each of values[0 .. count) by its sum over the processes.
  virtual void sum(double* values, int count) const = 0;
  /// The sum over every node of the grid of the rows of `window` (a field of totals: the same
  /// row on every process whose window holds the node), each node counted once whichever windows
  /// hold it: one total per column, into totals[0 .. window.cols()).
  virtual void sum_rows(const Field& window, double* totals) const = 0;
  /// Said by a process whose step failed, in place of its next collective call: the other
  /// processes' pending call throws FailedElsewhere.
  virtual void fail() const = 0;
};

/// What the velocity BCs of the loop need.
struct LoopConstraints {
  const Grid* grid = nullptr;              ///< the grid of the loop's nodes (Operators::grid)
  const BoundaryConditions* bcs = nullptr; ///< null: no velocity BCs
  double time = 0;                         ///< time at which BC values are evaluated
  /// Across processes: the loop's m̃ holds this process's particles only, and each product
  /// m̃ Δv is summed over the processes (NodeSums) before m⁻¹; null: one process.
  const NodeSums* sums = nullptr;
};

/// How the loop ended.
struct FmpmReport {
  int order = 1;     ///< ℓ reached (k unless dynamic FMPM converged earlier)
  double metric = 0; ///< convergence metric at that ℓ (0 when none was computed)
};

/// Scratch storage of the loop (n × d each).
struct FmpmWorkspace {
  /// Δv(ℓ), the increment of the pass in hand (XPIC: v*_k)
  Field prev, next; ///< the next increment, then swapped with prev (XPIC: S⁺S v*_k)
  Field dv;         ///< XPIC's Δv*_k (multimaterial); across processes, the summed product m̃ Δv
  Field residual;   ///< r(ℓ) of the Chebyshev and least-squares members (PolynomialPasses)
  PolynomialPasses passes;     ///< their coefficients, made once per loop
  std::vector<double> metrics; ///< metric of passes ℓ = 2, 3, ... of the last loop (dynamic FMPM)
};

/// The per-pass corrections of FMPM 2026 Table 1, called on every pass ℓ ≥ 2 after
/// Δv(ℓ) = A Δv(ℓ−1) and the blending factor. An empty hook does nothing.
struct FmpmHooks {
  /// Line (1): velocity BCs on the increment Δv(ℓ) (Table 2, bottom block).
  std::function<void(int ell, Field& dv)> velocity_bcs;
  /// Line (2): contact, correcting Δv(ℓ) given the evolving v⁺(ℓ − 1).
  std::function<void(int ell, Field& dv, const Field& v)> contact;
  /// Line (3): after v⁺(ℓ) = v⁺(ℓ − 1) + Δv(ℓ), true stops the loop (dynamic FMPM); may set
  /// the reported metric.
  std::function<bool(int ell, const Field& dv, const Field& v, double& metric)> converged;
  /// Across processes (LoopConstraints::sums): each pass sums m̃ Δv over the processes before
  /// m⁻¹; null: one process (the fused sweep of fmpm_pass).
  const NodeSums* sums = nullptr;
};

/// y = S⁺S x = m⁻¹ m̃ x (n × d): the product of every FMPM pass (FMPM 2026 Eq. 6), one pass over
/// the CSR rows of m̃; m_inv is 1/m_i on active nodes and 0 elsewhere.
void reverse_map_product(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, const Field& x,
                         Field& y);
/// One pass of FMPM 2026 Table 1 in one sweep over the rows of m̃:
/// next = c (dv − m⁻¹ m̃ dv) = c A dv (Eq. 6, blended by c, §3.3) and, when v is given,
/// v += next (Eq. 5). The same bits as reverse_map_product followed by those vector operations.
/// `next` must not be `dv`.
void fmpm_pass(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, double c, const Field& dv,
               Field& next, Field* v = nullptr);

/// The control of FMPM 2026 Table 1's loop, for any storage of the vectors: the Eigen fields of
/// fmpm_loop and the PETSc Vecs of the distributed component (sparsempm::petsc) run this one
/// function. `loop` supplies the algebra of its storage:
///   - loop.corrects(): whether hooks (1) or (2) change Δv(ℓ) between Eqs. 6 and 5;
///   - loop.pass(c, fused): Δv(ℓ) = c A Δv(ℓ−1) into the increment (Eq. 6, §3.3), and when
///     `fused` also v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ) (Eq. 5) in the same sweep;
///   - loop.passes() and loop.polynomial_pass(a, b, first, fused): the other members of the
///     family (PolynomialPasses), r(ℓ) = r(ℓ−1) − S⁺S Δv(ℓ−1) with r(1) = Δv(1) when `first`,
///     then Δv(ℓ) = a r(ℓ) + b Δv(ℓ−1), and v⁺(ℓ) when `fused`;
///   - loop.correct(ℓ): hooks (1) and (2) on Δv(ℓ);
///   - loop.accumulate(): v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ) (Eq. 5) when not fused;
///   - loop.tests_convergence() and loop.converged(ℓ, metric): hook (3).
/// `metrics` receives the metric of every pass that hook (3) tested.
template <class Loop>
FmpmReport fmpm_recursion(const FmpmOptions& opt, Loop& loop, std::vector<double>& metrics) {
  FmpmReport report;
  metrics.clear();
  // Without corrections between Eqs. 6 and 5, one pass over the rows does both.
  const bool fused = !loop.corrects();
  const bool series = opt.polynomial == Polynomial::Series;
  const PolynomialPasses* passes = series ? nullptr : &loop.passes();
  for (int ell = 2; ell <= opt.order; ++ell) {
    if (series) // Δv(ℓ) = A Δv(ℓ−1) = Δv(ℓ−1) − S⁺S Δv(ℓ−1), blended       (Eq. 6, §3.3)
      loop.pass(blend_factor(opt, ell), fused);
    else // r(ℓ) = r(ℓ−1) − S⁺S Δv(ℓ−1), Δv(ℓ) = a_ℓ r(ℓ) + b_ℓ Δv(ℓ−1)    (PolynomialPasses)
      loop.polynomial_pass(passes->a[size_t(ell - 2)], passes->b[size_t(ell - 2)], ell == 2, fused);
    loop.correct(ell); // (1), (2)
    if (!fused)
      loop.accumulate(); // v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ)                   (Eq. 5)
    report.order = ell;
    if (loop.tests_convergence()) { // (3)
      const bool done = loop.converged(ell, report.metric);
      metrics.push_back(report.metric);
      if (done)
        break;
    }
  }
  return report;
}

/// The BC method's sequence around the loop (FMPM 2026 §3.1, Table 2), for any storage of the
/// vectors: the Eigen fields of fmpm_velocity and the PETSc Vecs of the distributed component
/// (sparsempm::petsc) run this one function. `seq` supplies:
///   - seq.loop(): the loop of Table 1 (fmpm_recursion) from v⁺(1), with the method's hooks;
///   - seq.constrain_velocity(): the BC velocities set on v⁺(k).
/// The loop runs, then the Velocity and Combined methods set the BC velocities on v⁺(k); `bcs`
/// says whether there are velocity conditions.
template <class Sequence>
FmpmReport fmpm_bc_sequence(const FmpmOptions& opt, bool bcs, Sequence& seq) {
  const FmpmReport report = seq.loop();
  if (bcs && (opt.bc_method == BCMethod::Velocity || opt.bc_method == BCMethod::Combined))
    seq.constrain_velocity();
  return report;
}

/// Tasks 2.a and 3.b of FMPM 2026 Fig. 1 with the BC method of §3.1, for any storage of the
/// vectors (as fmpm_bc_sequence; updated_velocity and its distributed twin run this one
/// function). Besides seq.loop() and seq.constrain_velocity(), `seq` supplies:
///   - seq.constrain_momentum(): Table 2's top block in momentum form on p⁺;
///   - seq.lumped_solve(): v⁺(1) = m⁻¹ p⁺.
/// With `lumped_bcs` and velocity conditions (`bcs`), the top block acts on p⁺ except for the
/// Velocity method of a solve with k > 1, which sets v⁺(k) instead; then v⁺(1); then for k > 1
/// fmpm_bc_sequence.
template <class Sequence>
FmpmReport grid_velocity_bc_sequence(const FmpmOptions& opt, bool bcs, bool lumped_bcs,
                                     Sequence& seq) {
  const bool loop = opt.order > 1;
  if (lumped_bcs && bcs && !(loop && opt.bc_method == BCMethod::Velocity))
    seq.constrain_momentum(); // Table 2, top block
  seq.lumped_solve();         // v⁺(1) = m⁻¹ p⁺
  return loop ? fmpm_bc_sequence(opt, bcs, seq) : FmpmReport{};
}

/// The FMPM loop of FMPM 2026 Table 1 (fmpm_recursion on Eigen fields). On entry `v` holds v⁺(1) =
/// m⁻¹ p⁺ (with whatever lumped corrections the caller applied); on return v⁺(ℓ) at the last pass ℓ
/// ≤ k, and w.metrics holds the metric hook (3) gave on each pass (FMPM 2026 Fig. 13A). Each pass:
///     Δv(ℓ) = c_ℓ (Δv(ℓ−1) − S⁺S Δv(ℓ−1))        (Eq. 6; c_ℓ = blend_factor(ℓ), §3.3)
///     hooks (1) and (2) correct Δv(ℓ);  v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ)   (Eq. 5);  hook (3).
FmpmReport fmpm_loop(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt,
                     const FmpmOptions& opt, const FmpmHooks& hooks, Field& v, FmpmWorkspace& w);

/// The hooks that `opt` and the velocity BCs ask for: (1) zeroes the BC directions when the BC
/// method is Incremental (FMPM 2026 §3.1); (3) stops at the first ℓ whose convergence metric is
/// below opt.dynamic_limit (§3.4). Contact (2) is left empty.
FmpmHooks fmpm_hooks(const Operators& ops, const FmpmOptions& opt, const LoopConstraints& bc);

/// v⁺(k) = m̃_k⁻¹ p⁺ with the BC method of `opt`: on entry `v` holds v⁺(1) (with the lumped
/// BCs of Table 2's top block already applied unless the method is Velocity); runs fmpm_loop
/// with fmpm_hooks, then sets the BC velocities on v⁺(k) for the Velocity and Combined methods.
/// `contact`, when given, is the loop's contact hook (Table 1, line 2; contact_increment).
FmpmReport
fmpm_velocity(const Operators& ops, const SparseRowMatrix& mt, const FmpmOptions& opt,
              const LoopConstraints& bc, Field& v, FmpmWorkspace& w,
              const std::function<void(int ell, Field& dv, const Field& v)>& contact = {});

/// Tasks 2.a and 3.b of FMPM 2026 Fig. 1 with the BC method of §3.1: the grid velocity
/// v⁺ = m̃_k⁻¹ p⁺ from the updated momentum, the one sequence of the step (scheme.hpp) and of
/// Python's fmpm_velocity:
///   1. with `lumped_bcs`, Table 2's top block in momentum form on p⁺ (constrain_momentum; with
///      `reaction`, constrain_update, which adds f^(BC) = Δp/Δt to *reaction), except for the
///      Velocity method of a solve with k > 1, which sets v⁺(k) instead (§3.1);
///   2. v⁺(1) = m⁻¹ p⁺;
///   3. for k > 1, the loop of Table 1 with the method's BCs (fmpm_velocity; `contact` is its
///      line 2), for which `mt` is required.
/// With k = 1 this is the lumped update of FLIP, PIC and XPIC.
FmpmReport
updated_velocity(const Operators& ops, const SparseRowMatrix* mt, const FmpmOptions& opt,
                 const LoopConstraints& bc, bool lumped_bcs, double dt, Field& p_plus,
                 Field* reaction, Field& v, FmpmWorkspace& w,
                 const std::function<void(int ell, Field& dv, const Field& v)>& contact = {});

/// The convergence metric of FMPM 2026 §3.4 for an increment dv and the evolving v⁺(ℓ); across
/// processes (`sums`, collective then) the sums over every node once (NodeSums::sum_rows), with
/// ε from the largest |v⁺_i| over the processes, so that every process stops at the same pass.
double convergence_metric(ConvergenceMetric metric, const Field& dv, const Field& v,
                          const Operators& ops, const NodeSums* sums = nullptr);

/// The sums of a convergence metric over some of the nodes (convergence_sums): a metric over
/// nodes held in parts (the ranks of the distributed component) adds the parts' sums.
struct MetricSums {
  double numerator = 0;   ///< Means: Σ |Δv_i|; Changes: Σ_active |Δv_i| / (|v⁺_i| + ε)
  double denominator = 0; ///< Means: Σ |v⁺_i|; Changes: the count of active nodes
};
/// The sums of `metric` over the rows of dv and v (|·| the Euclidean norm of a row), in row
/// order; `active` marks the active rows (Changes) and eps is ε = 1% of the largest |v⁺_i| over
/// every node (Changes).
MetricSums convergence_sums(ConvergenceMetric metric, const Field& dv, const Field& v,
                            const Eigen::Array<bool, Eigen::Dynamic, 1>& active, double eps);
/// The metric of FMPM 2026 §3.4 from its sums: numerator / denominator, 0 when that is 0.
inline double convergence_ratio(const MetricSums& s) {
  return s.denominator > 0 ? s.numerator / s.denominator : 0.0;
}

/// XPIC(m) projection (contact 2020 Eqs. 36, 41–44):
///     P V = m S (v − v*),  v* = Σ_{k=2}^{m} (−1)^k (v*_k + ((m − 1)/m) Δv*_{k−1}),
///     v*_1 = v,  v*_k = ((m + 1 − k)/k) S⁺S v*_{k−1},
///     Δv*_1 = Δv,  Δv*_k = ((m − k)/k) S⁺S Δv*_{k−1},
/// for the lumped grid velocity v = m⁻¹ p of the particle velocities. In multimaterial mode
/// (block columns, S⁺S = S^{+α}S per field) v is the contact-corrected v^α and `dv` the
/// correction Δv^α of the contact after P2G (Eq. 26), which gives Eq. (37):
///     P V = (I − (I − S S^{+α})^m) V + (I − S S^{+α})^{m−1} S Δv^α;
/// without `dv` it is single-material XPIC (Eq. 36). Returns the n × d grid field
/// u = m (v − v*), so that P V = S u; XPIC(1) gives u = v (PIC).
void xpic_grid_velocity(const Operators& ops, const SparseRowMatrix& mt, int m, const Field& v,
                        Field& u, FmpmWorkspace& w, const Field* dv = nullptr);

/// For analysis on small problems: m̃_k⁻¹ = (Σ_{ℓ=1}^{k} c_ℓ A^{ℓ−1}) m⁻¹ with the blending
/// coefficients c_1 = 1, c_ℓ = c_{ℓ−1} blend_factor(ℓ), assembled as an n × n sparse matrix
/// (rows and columns of inactive nodes zero). Without blending this is Σ_{j<k} Aʲ m⁻¹. For the
/// Chebyshev and least-squares members, q(m⁻¹m̃) m⁻¹ by the loop's passes on matrices.
SparseMatrix fmpm_inverse(const Operators& ops, const FmpmOptions& opt);

} // namespace smpm
