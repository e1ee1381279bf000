#include "sparsempm/step.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace smpm {

std::string_view to_string(UpdateScheme s) {
  return s == UpdateScheme::USL ? "USL" : "USF";
}
std::string_view to_string(VelocityUpdate v) {
  return v == VelocityUpdate::FLIP ? "FLIP" : "PIC";
}

UpdateScheme update_scheme_from_string(std::string_view name) {
  if (name == "USL")
    return UpdateScheme::USL;
  if (name == "USF")
    return UpdateScheme::USF;
  throw InputError("unknown update scheme '" + std::string(name) + "' (expected USL | USF)");
}

VelocityUpdate velocity_update_from_string(std::string_view name) {
  if (name == "FLIP")
    return VelocityUpdate::FLIP;
  if (name == "PIC")
    return VelocityUpdate::PIC;
  throw InputError("unknown velocity update '" + std::string(name) + "' (expected FLIP | PIC)");
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

void Stepper::step(Model& model, double dt) {
  try {
    if (opt_.scheme == UpdateScheme::USL)
      step_usl(model, dt);
    else
      step_usf(model, dt);
    check_particles(model.particles);
  } catch (const NumericalError& e) {
    throw at_step(e, model.step + 1, model.time + dt);
  }
  model.time += dt;
  ++model.step;
}

// Velocity gradient, F and stress from grid velocities v (Buzzi Fig. 7; FMPM 2026 task 5).
void Stepper::strain_update(Model& model, const Field& v, double dt) {
  const Field* vs = &v;
  if (opt_.bc_ordering == BCOrdering::Improper) { // BC3: BC velocity only for the strains
    v_strain_ = v;
    model.bcs.constrain_velocity(model.grid, model.time, v_strain_);
    vs = &v_strain_;
  }
  velocity_gradient(ops_, *vs, L_);
  update_deformation_gradient(L_, dt, model.particles);
  update_stress(model.materials, model.particles);
}

// Forces, BC2, p⁺ = p + f Δt and the particle update (FMPM 2026 tasks 2–4).
namespace {
void momentum_update(const Model& model, const Operators& ops, GridState& g, double dt,
                     BCOrdering ordering, StageWorkspace& w) {
  internal_force(ops, model.particles, g.f, w);
  add_body_force(ops, model.body_force, g.f);
  if (ordering == BCOrdering::Improper) {
    model.bcs.zero_directions(g.f); // BC2 alone: zero rate of momentum (Buzzi Eq. 28)
    g.p_plus.noalias() = g.p + dt * g.f;
  } else {
    // BC2: p⁺ takes the BC velocity at t + Δt and f the reaction f^(BC) = Δp/Δt that does it
    // (FMPM 2026 task 2.a); for a fixed direction with BC1 applied this is Buzzi's zeroing of
    // the rate of momentum (Eq. 28).
    g.p_plus.noalias() = g.p + dt * g.f;
    model.bcs.constrain_update(model.grid, ops.m, model.time + dt, dt, g.p_plus, g.f);
  }
  lumped_solve(ops, g.p_plus, g.v_plus);
  lumped_solve(ops, g.f, g.a);
}
} // namespace

void Stepper::step_usl(Model& model, double dt) {
  Particles& P = model.particles;
  assemble(model.grid, P, opt_.shape, ops_);
  map_momentum(ops_, P, g_.p, w_);
  if (opt_.bc_ordering == BCOrdering::Correct)
    model.bcs.constrain_momentum(model.grid, ops_.m, model.time, g_.p); // BC1 (Buzzi Eq. 27)
  lumped_solve(ops_, g_.p, g_.v);
  momentum_update(model, ops_, g_, dt, opt_.bc_ordering, w_);
  if (opt_.velocity == VelocityUpdate::FLIP)
    update_particles_flip(ops_, g_, dt, opt_.position_alpha, P, w_);
  else
    update_particles_pic(ops_, g_.v_plus, dt, opt_.position_alpha, P, w_);
  strain_update(model, g_.v_plus, dt);
}

void Stepper::step_usf(Model& model, double dt) {
  Particles& P = model.particles;
  assemble(model.grid, P, opt_.shape, ops_);
  map_momentum(ops_, P, g_.p, w_);
  if (opt_.bc_ordering == BCOrdering::Correct)
    model.bcs.constrain_momentum(model.grid, ops_.m, model.time, g_.p); // BC1
  lumped_solve(ops_, g_.p, g_.v);
  strain_update(model, g_.v, dt);
  momentum_update(model, ops_, g_, dt, opt_.bc_ordering, w_);
  if (opt_.velocity == VelocityUpdate::FLIP)
    update_particles_flip(ops_, g_, dt, opt_.position_alpha, P, w_);
  else
    update_particles_pic(ops_, g_.v_plus, dt, opt_.position_alpha, P, w_);
}

} // namespace smpm
