#pragma once
/// \file step.hpp
/// One explicit MPM time step: the scheme is the order of the stages in stages.hpp.

#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/shape.hpp"
#include "sparsempm/stages.hpp"

#include <string_view>

namespace smpm {

/// When the particle stress is updated (Buzzi Figs. 2–3 and 5–7).
enum class UpdateScheme {
  USL, ///< update stress last, from v⁺ (FMPM 2026 §2.1, the recommended method)
  USF  ///< update stress first, from v = m⁻¹ p before the forces
};
/// How particle velocities are updated from the grid.
enum class VelocityUpdate {
  FLIP, ///< increment by the extrapolated acceleration (FMPM 2026 Eq. 8)
  PIC   ///< replace by the extrapolated velocity, i.e. FMPM(1) (FMPM 2026 Eq. 9)
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

struct StepOptions {
  Shape shape = Shape::Linear;
  UpdateScheme scheme = UpdateScheme::USL;
  VelocityUpdate velocity = VelocityUpdate::FLIP;
  double position_alpha = 1.0; ///< α of FMPM 2026 Eqs. (8)–(9)
  BCOrdering bc_ordering = BCOrdering::Correct;
};

/// Advances a Model by one time step; owns the operators and grid fields and reuses their
/// storage from step to step.
class Stepper {
public:
  explicit Stepper(const StepOptions& options) : opt_(options) {}
  /// One step of length dt. Throws NumericalError naming the step, time and particle when the
  /// state becomes invalid (a particle leaves the grid, NaN, det F ≤ 0).
  void step(Model& model, double dt);

  const StepOptions& options() const { return opt_; }
  /// The operators assembled for the last step (configuration at its start).
  const Operators& operators() const { return ops_; }
  /// The grid fields of the last step.
  const GridState& grid_state() const { return g_; }

private:
  void step_usl(Model& model, double dt);
  void step_usf(Model& model, double dt);
  void strain_update(Model& model, const Field& v, double dt);

  StepOptions opt_;
  Operators ops_;
  GridState g_;
  StageWorkspace w_;
  Field v_strain_, L_;
};

} // namespace smpm
