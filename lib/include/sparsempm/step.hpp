#pragma once
/// \file step.hpp
/// The options of an explicit MPM time step and the Stepper that advances a Model with them.
/// The stages of the step are written once, in scheme.hpp (scheme_step); the Stepper assembles
/// the operators of the current configuration and calls it.

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/fmpm.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/shape.hpp"
#include "sparsempm/stages.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string_view>

namespace smpm {

struct GridState; // scheme.hpp

/// When the particle stress is updated (Buzzi Figs. 2–3 and 5–7; FMPM 2026 §2.1, Fig. 1).
enum class UpdateScheme {
  USL,      ///< update stress last, from v⁺ (task 5; the recommended method)
  USF,      ///< update stress first, from v = m̃_k⁻¹ p before the forces (task 1.c)
  USLPlus,  ///< USL from velocities re-extrapolated after the particle update (task 4.c)
  USAVG,    ///< half Δt first (task 1.c) and half Δt last from v⁺ (task 3.b)
  USAVGPlus ///< half Δt first (task 1.c) and half Δt last, re-extrapolated (task 4.c)
};
/// How particle velocities are updated from the grid.
enum class VelocityUpdate {
  FLIP, ///< increment by the extrapolated lumped acceleration (FMPM 2026 Eq. 8)
  PIC,  ///< V = S v⁺(1), i.e. FMPM(1) (FMPM 2026 Eq. 9)
  FMPM, ///< V = S v⁺(k) with the FMPM loop of Table 1 (FMPM 2026 Eq. 9)
  XPIC, ///< V = S m(v − v*) + S a Δt (contact 2020 Eqs. 35, 41–43)
  Exact ///< V = S m̃⁻¹ p⁺, the consistent-mass inverse ("FMPM(∞)")
};
/// Where zero-velocity conditions are imposed (Buzzi §5.5).
enum class BCOrdering {
  Correct, ///< zero the fixed momentum after P2G (BC1) and its rate before the update (BC2)
  Improper ///< BC2 and zero velocity only in the strain update (BC3), without BC1 (Fig. 22)
};

std::string_view to_string(UpdateScheme s);
std::string_view to_string(VelocityUpdate v);
UpdateScheme update_scheme_from_string(std::string_view name);
VelocityUpdate velocity_update_from_string(std::string_view name);

/// Solves the consistent-mass system m̃ v = p on the active nodes, with the velocity BCs of
/// `bc` imposed (the limit k → ∞ of the incremental method). Implemented with CHOLMOD in
/// sparsempm::exact (exact.hpp). A solver keeps state (its factorisation): each Stepper and
/// each linearised step makes its own from StepOptions::exact_solver.
class MassSolver {
public:
  virtual ~MassSolver() = default;
  virtual void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
                     const Field& p, Field& v) = 0;
  /// The response v = m̃⁻¹ r to a momentum change r with the matrix of the last solve and
  /// homogeneous conditions (zero on the components that solve prescribed): what the contact
  /// of the exact update in multimaterial mode needs. The default throws InputError.
  virtual void solve_again(const Field& r, Field& v);
};
/// Makes a new MassSolver (e.g. cholmod_solver_factory() of exact.hpp).
using MassSolverFactory = std::function<std::unique_ptr<MassSolver>()>;

struct StepOptions {
  Shape shape = Shape::Linear;
  UpdateScheme scheme = UpdateScheme::USL;
  VelocityUpdate velocity = VelocityUpdate::FLIP;
  /// α of FMPM 2026 Eqs. (8)–(9); unset: default_position_alpha(velocity).
  std::optional<double> position_alpha{};
  BCOrdering bc_ordering = BCOrdering::Correct;
  FmpmOptions fmpm{};     ///< order k (FMPM) or m (XPIC), blending, BC method, dynamic
  double periodic_cx = 0; ///< C_X of periodic FMPM (§3.3); 0: FMPM on every step
  DeformationUpdate deformation = DeformationUpdate::Linear; ///< F ← (I + LΔt)F or exp(LΔt)F
  /// Multimaterial XPIC(m): add the contact term (I − S S^{+α})^{m−1} S Δv^α of contact 2020
  /// Eq. (37); false gives the "uncorrected XPIC" of its Fig. 7 (for comparison only).
  bool xpic_contact_term = true;
  MassSolverFactory exact_solver{}; ///< required by VelocityUpdate::Exact
  /// The nodes of a step: the particles' window of the grid (storage and time proportional to
  /// the particles and the nodes they reach) or every node of the grid. The results are the same
  /// bits either way; only the numbering of the grid fields differs (Stepper::operators()).
  NodeRange nodes = NodeRange::Particles;
};

/// α of Eqs. (8)–(9) when the options leave it unset: 1 for FLIP (the usual choice, FMPM 2026
/// footnote to Eq. 8), ½ for grid-velocity updates (Eq. 9's consistent choice, §2.3).
double default_position_alpha(VelocityUpdate velocity);
/// The α a step with these options uses.
double position_alpha(const StepOptions& options);

/// Throws InputError for option values outside their ranges (FMPM options, α ∉ [0, 1],
/// C_X < 0) and UsageError for Exact without a solver factory. The only check of StepOptions:
/// the Stepper and the linearised step call it.
void validate(const StepOptions& options);

/// Whether a step assembles m̃ (FMPM 2026 §2.2): on steps that update particles from grid
/// velocities (`grid_update`) with the exact inverse, or with FMPM(k) or XPIC(m) of order > 1.
bool uses_consistent_mass(const StepOptions& options, bool grid_update);

/// Advances a Model by one time step; owns the operators, m̃ and the grid fields and reuses
/// their storage from step to step.
class Stepper {
public:
  /// Validates the options (validate) and makes the exact solver when one is needed.
  explicit Stepper(const StepOptions& options);
  ~Stepper();
  Stepper(Stepper&&) noexcept;
  Stepper& operator=(Stepper&&) noexcept;

  /// One step of length dt: assembles S, G, m (and m̃ when used) at the current configuration
  /// and runs scheme_step. Throws NumericalError naming the step, time and particle when the
  /// state becomes invalid (a particle leaves the grid, NaN, det F ≤ 0).
  void step(Model& model, double dt);

  /// energies(model) after a step, with the strain energy densities W(F_p) its stress update
  /// stored: the same bits without evaluating W again. The particles must be as the last step
  /// left them; when no step has run (or the strain update stored nothing) this is
  /// energies(model).
  Energies energies(const Model& model) const;

  const StepOptions& options() const { return opt_; }
  /// The operators assembled for the last step (configuration at its start). Their nodes are
  /// those of the particles' window of the model's grid, operators().grid (NodeRange::Particles):
  /// node i is node operators().grid.whole_node(i) of the grid.
  const Operators& operators() const { return ops_; }
  /// The grid fields of the last step, on the nodes of operators().grid; v_plus is the velocity
  /// used by the particle update.
  const GridState& grid_state() const;
  /// m̃ of the last step (assembled only when the step used it).
  const ConsistentMass& consistent_mass_storage() const { return mt_; }
  /// Whether the last step updated particles from grid velocities (PIC, FMPM, XPIC, exact)
  /// rather than FLIP (false on the FLIP steps of periodic FMPM).
  bool last_step_was_fmpm() const { return grid_update_; }
  /// How the last FMPM loop ended (order reached, metric).
  const FmpmReport& last_fmpm() const;
  /// The convergence metric of each pass ℓ = 2, 3, ... of the last step's last FMPM loop
  /// (dynamic FMPM, FMPM 2026 §3.4 and Fig. 13A; empty without a metric or a loop, as on the
  /// FLIP steps of periodic FMPM). With USL+ and USAVG+ the last loop is that of the
  /// re-extrapolated velocities (task 4.c). With dynamic_limit = 0 the loop runs to the order k
  /// and this is the whole curve.
  const std::vector<double>& last_fmpm_metrics() const;
  /// Periodic FMPM: the Courant number accumulated since the last FMPM step (§3.3). Part of
  /// the stepper's state: a restart sets it back with set_courant_budget.
  double courant_budget() const { return courant_budget_; }
  void set_courant_budget(double budget) { courant_budget_ = budget; }
  /// Work dissipated since the start of the run (or the last set_dissipation): by Coulomb
  /// friction at contact nodes (contact_friction_work, the momentum-update correction) and by
  /// the artificial viscosity of Mie–Grüneisen materials (part of their internal energy U).
  double friction_work() const { return friction_work_; }
  double viscous_work() const { return viscous_work_; }
  void set_dissipation(double friction, double viscous) {
    friction_work_ = friction;
    viscous_work_ = viscous;
  }

private:
  struct Buffers;
  StepOptions opt_;
  std::unique_ptr<MassSolver> solver_;
  Operators ops_;
  ConsistentMass mt_;
  std::unique_ptr<Buffers> buf_;
  double courant_budget_ = 0;
  double friction_work_ = 0, viscous_work_ = 0;
  bool grid_update_ = false;
};

} // namespace smpm
