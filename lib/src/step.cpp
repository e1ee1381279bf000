#include "sparsempm/step.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace smpm {

namespace {
constexpr std::array<std::pair<UpdateScheme, std::string_view>, 5> kSchemes{
    {{UpdateScheme::USL, "USL"},
     {UpdateScheme::USF, "USF"},
     {UpdateScheme::USLPlus, "USL+"},
     {UpdateScheme::USAVG, "USAVG"},
     {UpdateScheme::USAVGPlus, "USAVG+"}}};
constexpr std::array<std::pair<VelocityUpdate, std::string_view>, 5> kVelocities{
    {{VelocityUpdate::FLIP, "FLIP"},
     {VelocityUpdate::PIC, "PIC"},
     {VelocityUpdate::FMPM, "FMPM"},
     {VelocityUpdate::XPIC, "XPIC"},
     {VelocityUpdate::Exact, "exact"}}};
} // namespace

std::string_view to_string(UpdateScheme s) {
  for (const auto& [v, name] : kSchemes)
    if (v == s)
      return name;
  return "?";
}
std::string_view to_string(VelocityUpdate u) {
  for (const auto& [v, name] : kVelocities)
    if (v == u)
      return name;
  return "?";
}

UpdateScheme update_scheme_from_string(std::string_view name) {
  for (const auto& [v, n] : kSchemes)
    if (n == name)
      return v;
  throw InputError("unknown update scheme '" + std::string(name) +
                   "' (expected USL | USF | USL+ | USAVG | USAVG+)");
}

VelocityUpdate velocity_update_from_string(std::string_view name) {
  for (const auto& [v, n] : kVelocities)
    if (n == name)
      return v;
  throw InputError("unknown velocity update '" + std::string(name) +
                   "' (expected FLIP | PIC | FMPM | XPIC | exact)");
}

double stable_time_step(const Model& model, double courant) {
  if (!(courant > 0) || !std::isfinite(courant))
    throw InputError("courant number must be positive, got " + std::to_string(courant));
  const double c = max_wave_speed(model.materials, model.particles);
  const double vmax = model.particles.size() ? model.particles.V.rowwise().norm().maxCoeff() : 0;
  const double speed = std::max(c, vmax);
  if (!(speed > 0))
    throw InputError("cannot choose a time step: no wave speed and no particle velocity");
  return courant * model.grid.min_cell_size() / speed;
}

Stepper::Stepper(const StepOptions& options) : opt_(options) {
  validate(opt_.fmpm);
  if (opt_.velocity == VelocityUpdate::Exact && !opt_.solver)
    throw InputError("the exact velocity update needs a MassSolver (see exact.hpp)");
  if (!(opt_.periodic_cx >= 0))
    throw InputError("periodic_cx must be non-negative");
  if (!(opt_.position_alpha >= 0 && opt_.position_alpha <= 1))
    throw InputError("position_alpha must lie in [0, 1]");
}

void Stepper::step(Model& model, double dt) {
  try {
    run_step(model, dt); // the stages check X, V (particle update) and det F (F update)
  } catch (const NumericalError& e) {
    throw at_step(e, model.step + 1, model.time + dt);
  }
  model.time += dt;
  ++model.step;
}

// Velocity gradient, F and stress from grid velocities v (Buzzi Fig. 7; FMPM 2026 task 5).
void Stepper::strain_update(Model& model, const Field& v, double t, double dt) {
  const Field* vs = &v;
  if (opt_.bc_ordering == BCOrdering::Improper) { // BC3: BC velocity only for the strains
    v_strain_ = v;
    model.bcs.constrain_velocity(model.grid, t, v_strain_, &ops_.active);
    vs = &v_strain_;
  }
  update_deformation_from_velocity(ops_, *vs, dt, model.particles); // L, F, det F > 0
  update_stress(model.materials, model.particles);
}

// v = m̃_k⁻¹ p with this step's mass inverse (tasks 1.c, 3.b, 4.c of FMPM 2026 Fig. 1).
void Stepper::grid_velocity(const Model& model, const Field& p, double t, Field& v) {
  const LoopConstraints bc{&model.grid, &model.bcs, t};
  if (full_mass_now_ && opt_.velocity == VelocityUpdate::Exact) {
    opt_.solver->solve(ops_, mt_.matrix, bc, p, v);
    return;
  }
  lumped_solve(ops_, p, v); // v⁺(1) = m⁻¹ p
  if (full_mass_now_ && opt_.velocity == VelocityUpdate::FMPM && opt_.fmpm.order > 1)
    report_ = fmpm_loop(ops_, mt_.matrix, opt_.fmpm, bc, v, fw_);
}

// Particle velocity and position (FMPM 2026 task 4): Eq. (8) for FLIP steps, Eq. (9) for
// PIC, FMPM(k) and exact, Eq. (35) of contact 2020 for XPIC(m).
void Stepper::particle_update(Model& model, double dt) {
  Particles& P = model.particles;
  const double alpha = opt_.position_alpha;
  if (!fmpm_step_) { // FLIP, or a FLIP step of periodic FMPM
    update_particles_flip(ops_, g_, dt, alpha, P, w_);
    return;
  }
  switch (opt_.velocity) {
  case VelocityUpdate::XPIC:
    if (full_mass_now_) {
      xpic_grid_velocity(ops_, mt_.matrix, opt_.fmpm.order, g_.v, xpic_, fw_);
      xpic_.noalias() += dt * g_.a; // V' = S (m (v − v*) + a Δt)
    } else {
      xpic_ = g_.v_plus; // XPIC(1) = PIC
    }
    update_particles_pic(ops_, xpic_, dt, alpha, P, w_);
    return;
  default:
    update_particles_pic(ops_, g_.v_plus, dt, alpha, P, w_);
  }
}

void Stepper::run_step(Model& model, double dt) {
  Particles& P = model.particles;
  const UpdateScheme s = opt_.scheme;
  assemble(model.grid, P, opt_.shape, ops_);
  // Periodic FMPM (§3.3): the grid-velocity update on steps that cross the budget C_X, FLIP on
  // the others.
  fmpm_step_ = opt_.velocity != VelocityUpdate::FLIP;
  if (fmpm_step_ && opt_.periodic_cx > 0) {
    const double speed = std::max(max_wave_speed(model.materials, P),
                                  P.size() ? P.V.rowwise().norm().maxCoeff() : 0.0);
    courant_budget_ += dt * speed / model.grid.min_cell_size();
    fmpm_step_ = courant_budget_ >= opt_.periodic_cx * (1 - 1e-12);
    if (fmpm_step_)
      courant_budget_ = 0;
  }
  full_mass_now_ =
      fmpm_step_ &&
      (opt_.velocity == VelocityUpdate::Exact ||
       ((opt_.velocity == VelocityUpdate::FMPM || opt_.velocity == VelocityUpdate::XPIC) &&
        opt_.fmpm.order > 1));
  report_ = FmpmReport{};
  if (full_mass_now_)
    assemble_consistent_mass(ops_, mt_);

  // Task 1: p = Sᵀ M V, BC1.
  map_momentum(ops_, P, g_.p, w_);
  if (opt_.bc_ordering == BCOrdering::Correct)
    model.bcs.constrain_momentum(model.grid, ops_.m, model.time, g_.p);
  lumped_solve(ops_, g_.p, g_.v);
  // Task 1.c: stresses first (USF, USAVG, USAVG+).
  if (s == UpdateScheme::USF || s == UpdateScheme::USAVG || s == UpdateScheme::USAVGPlus) {
    grid_velocity(model, g_.p, model.time, v_re_);
    strain_update(model, v_re_, model.time, s == UpdateScheme::USF ? dt : 0.5 * dt);
  }
  // Tasks 2–3: forces, BC2 (with reaction forces), p⁺ = p + f Δt.
  internal_force(ops_, P, g_.f, w_);
  add_body_force(ops_, model.body_force, g_.f);
  if (opt_.bc_ordering == BCOrdering::Improper) {
    model.bcs.zero_directions(g_.f); // BC2 alone: zero rate of momentum (Buzzi Eq. 28)
    g_.p_plus.noalias() = g_.p + dt * g_.f;
  } else {
    g_.p_plus.noalias() = g_.p + dt * g_.f;
    // Task 2.a: p⁺ takes the BC velocity at t + Δt and f the reaction f^(BC) = Δp/Δt; the
    // velocity method of §3.1 skips it on full-mass steps and corrects v⁺(k) afterwards.
    const bool skip = full_mass_now_ && opt_.velocity == VelocityUpdate::FMPM &&
                      opt_.fmpm.bc_method == BCMethod::Velocity;
    if (!skip)
      model.bcs.constrain_update(model.grid, ops_.m, model.time + dt, dt, g_.p_plus, g_.f);
  }
  lumped_solve(ops_, g_.f, g_.a);
  // Task 3.b: v⁺ = m̃_k⁻¹ p⁺.
  if (opt_.velocity == VelocityUpdate::FMPM || opt_.velocity == VelocityUpdate::Exact)
    grid_velocity(model, g_.p_plus, model.time + dt, g_.v_plus);
  else
    lumped_solve(ops_, g_.p_plus, g_.v_plus);
  // Task 4: particle velocity and position.
  particle_update(model, dt);
  // Task 5: stresses last (USL, USL+, USAVG, USAVG+).
  if (s == UpdateScheme::USF)
    return;
  const double dt_last = (s == UpdateScheme::USL || s == UpdateScheme::USLPlus) ? dt : 0.5 * dt;
  if (s == UpdateScheme::USLPlus || s == UpdateScheme::USAVGPlus) {
    // Tasks 4.a–4.c: re-extrapolate the updated particle momenta with the same S.
    map_momentum(ops_, P, p_re_, w_);
    if (opt_.bc_ordering == BCOrdering::Correct)
      model.bcs.constrain_momentum(model.grid, ops_.m, model.time + dt, p_re_);
    grid_velocity(model, p_re_, model.time + dt, v_re_);
    strain_update(model, v_re_, model.time + dt, dt_last);
  } else {
    strain_update(model, g_.v_plus, model.time + dt, dt_last);
  }
}

} // namespace smpm
