#pragma once
/// \file step.hpp
/// One explicit MPM time step: the scheme is the order of the stages in stages.hpp, with the
/// grid-velocity solve (lumped, FMPM(k), XPIC(m) or exact) where FMPM 2026 Fig. 1 places it.

#include "sparsempm/fmpm.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/shape.hpp"
#include "sparsempm/stages.hpp"

#include <memory>
#include <string_view>

namespace smpm {

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
/// sparsempm::exact (exact.hpp).
class MassSolver {
public:
  virtual ~MassSolver() = default;
  virtual void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
                     const Field& p, Field& v) = 0;
};

struct StepOptions {
  Shape shape = Shape::Linear;
  UpdateScheme scheme = UpdateScheme::USL;
  VelocityUpdate velocity = VelocityUpdate::FLIP;
  double position_alpha = 1.0; ///< α of FMPM 2026 Eqs. (8)–(9) (½ is Eq. 9's consistent choice)
  BCOrdering bc_ordering = BCOrdering::Correct;
  FmpmOptions fmpm{};     ///< order k (FMPM) or m (XPIC), blending, BC method, dynamic
  double periodic_cx = 0; ///< C_X of periodic FMPM (§3.3); 0: FMPM on every step
  std::shared_ptr<MassSolver> solver{}; ///< required by VelocityUpdate::Exact
};

/// Advances a Model by one time step; owns the operators, m̃ and the grid fields and reuses
/// their storage from step to step.
class Stepper {
public:
  /// Throws InputError for inconsistent options (bad FMPM options, Exact without a solver).
  explicit Stepper(const StepOptions& options);
  /// One step of length dt. Throws NumericalError naming the step, time and particle when the
  /// state becomes invalid (a particle leaves the grid, NaN, det F ≤ 0).
  void step(Model& model, double dt);

  const StepOptions& options() const { return opt_; }
  /// The operators assembled for the last step (configuration at its start).
  const Operators& operators() const { return ops_; }
  /// The grid fields of the last step; v_plus is the velocity used by the particle update.
  const GridState& grid_state() const { return g_; }
  /// m̃ of the last step (assembled only when the step used it).
  const ConsistentMass& consistent_mass_storage() const { return mt_; }
  /// Whether the last step updated particles from grid velocities (PIC, FMPM, XPIC, exact)
  /// rather than FLIP (false on the FLIP steps of periodic FMPM).
  bool last_step_was_fmpm() const { return fmpm_step_; }
  /// How the last FMPM loop ended (order reached, metric).
  const FmpmReport& last_fmpm() const { return report_; }

private:
  void run_step(Model& model, double dt);
  void strain_update(Model& model, const Field& v, double t, double dt);
  void grid_velocity(const Model& model, const Field& p, double t, Field& v);
  void particle_update(Model& model, double dt);

  StepOptions opt_;
  Operators ops_;
  ConsistentMass mt_;
  GridState g_;
  StageWorkspace w_;
  FmpmWorkspace fw_;
  FmpmReport report_;
  Field v_strain_, L_, p_re_, v_re_, xpic_;
  double courant_budget_ = 0;
  bool fmpm_step_ = false;     // grid-velocity (non-FLIP) particle update this step
  bool full_mass_now_ = false; // this step uses m̃
};

} // namespace smpm
