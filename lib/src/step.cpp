// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/step.hpp"

#include "sparsempm/advance.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/scheme.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

namespace smpm {

struct Stepper::Buffers {
  StepBuffers step;
  TransportContext transport;              ///< the transport stages' context (heat transport)
  ThermalStrainState thermal;              ///< the strain update's couplings (heat transport)
  std::unique_ptr<MassSolver> heat_solver; ///< the exact transport update's solver
  ShockState shock;
  PlasticState plastic;           ///< the J2 return's state pointers and scratch
  ExternalForces external;        ///< the loads of the step
  Field x_start;                  ///< the positions at the step's start (rigid materials)
  std::vector<double> rigid_mass; ///< Σ m_i on each rigid condition's nodes (free bodies)
  std::vector<Eigen::Vector3d> rigid_velocity; ///< each rigid motion's velocity at t
  Eigen::VectorXd density; ///< W(F_p) of the last stress update (empty: none in the last step)
  std::atomic<std::thread::id> owner{}; ///< the thread holding the Stepper (Exclusive); none: {}
};

std::vector<std::string> reaction_labels(const Model& model) {
  std::vector<std::string> labels;
  for (const VelocityCondition& c : model.bcs.conditions)
    labels.push_back(c.label);
  for (const RigidMotion& m : model.rigid)
    for (int a = 0; a < model.grid.dim(); ++a)
      labels.push_back(m.label + "." + std::string(1, "xyz"[a]));
  return labels;
}

Stepper::Exclusive::Exclusive(const Stepper& stepper) {
  std::atomic<std::thread::id>& owner = stepper.buf_->owner;
  const std::thread::id me = std::this_thread::get_id();
  std::thread::id none{};
  if (owner.compare_exchange_strong(none, me, std::memory_order_acquire)) {
    held_ = &stepper;
    return;
  }
  if (none != me)
    throw UsageError("Stepper: called from a second thread while another thread is stepping it "
                     "(a Stepper belongs to one thread at a time; give each thread its own)");
}

Stepper::Exclusive::~Exclusive() {
  if (held_)
    held_->buf_->owner.store(std::thread::id{}, std::memory_order_release);
}

Stepper::Stepper(const StepOptions& options) : opt_(options), buf_(std::make_unique<Buffers>()) {
  validate(opt_);
  prep_.ops.node_range = opt_.nodes;
  if (opt_.velocity == VelocityUpdate::Exact)
    solver_ = opt_.exact_solver(velocity_solver_options(opt_));
  if (opt_.transport.update == TransportUpdate::Exact)
    buf_->heat_solver = opt_.exact_solver(opt_.exact);
}

Stepper::~Stepper() = default;
Stepper::Stepper(Stepper&&) noexcept = default;
Stepper& Stepper::operator=(Stepper&&) noexcept = default;

Energies Stepper::energies(const Model& model) const {
  const bool stored = buf_->density.size() == model.particles.size();
  return smpm::energies(model, stored ? &buf_->density : nullptr);
}

bool Stepper::heat() const {
  return opt_.transport.update != TransportUpdate::Off;
}

const TransportContext& Stepper::transport_context(Model& model) {
  TransportContext& t = buf_->transport;
  t.update = opt_.transport.update;
  t.fmpm = transport_fmpm_options(opt_);
  t.ops = &prep_.transport;
  t.ct = uses_consistent_capacity(opt_) ? &prep_.consistent_capacity() : nullptr;
  t.solver = buf_->heat_solver.get();
  t.bcs = &prep_.temperature_bcs;
  t.temperature = &model.particles.temperature;
  t.energy = uses_shock_physics(model.materials) ? &model.particles.energy : nullptr;
  t.materials = &model.materials;
  t.material = &model.particles.material;
  return t;
}

const TransportState& Stepper::transport_state() const {
  return buf_->step.heat;
}

const GridState& Stepper::grid_state() const {
  return buf_->step.g;
}
const FmpmReport& Stepper::last_fmpm() const {
  return buf_->step.report;
}
const std::vector<double>& Stepper::last_fmpm_metrics() const {
  return buf_->step.fmpm.metrics;
}

Stepper::Prepared Stepper::prepared_of(const Model& model) {
  return {&model,
          model.step,
          model.time,
          model.particles.size(),
          model.particles.X.data(),
          model.particles.F.data()};
}

const StepPreparation& Stepper::prepare(const Model& model) {
  const Exclusive hold(*this);
  prepared_ = {};
  try {
    prepare_step(model, opt_.shape, prep_, opt_.transport.update);
  } catch (const NumericalError& e) { // the next step's failure
    throw at_step(e, model.step + 1, model.time);
  }
  prepared_ = prepared_of(model);
  return prep_;
}

void Stepper::step(Model& model, double dt) {
  const Exclusive hold(*this);
  if (!(dt > 0) || !std::isfinite(dt))
    throw InputError("step: the time step must be positive and finite, got " + number_text(dt));
  if (!std::isfinite(model.time))
    throw InputError("step: the model's time must be finite, got " + number_text(model.time));
  Particles& P = model.particles;
  try {
    const bool prepared = prepared_.model && prepared_ == prepared_of(model);
    prepared_ = {};
    if (heat() && P.temperature.size() != P.size()) // no temperatures yet: T_ref
      set_reference_temperatures(P, model.materials);
    if (!prepared)
      prepare_step(model, opt_.shape, prep_, opt_.transport.update);
    PhaseClock clock;
    // Periodic FMPM (§3.3): the grid-velocity update on steps that cross the budget C_X, FLIP
    // on the others.
    grid_update_ = opt_.velocity != VelocityUpdate::FLIP;
    if (grid_update_ && opt_.periodic_cx > 0)
      grid_update_ =
          periodic_fmpm_step(opt_.periodic_cx, courant_of(model, dt), state_.courant_budget);
    const bool contact = prep_.has_contact();
    const ExternalForces* external = nullptr; // the loads at t, the step's configuration
    if (!model.loads.empty()) {
      external_forces(model.loads, P, model.time,
                      opt_.shape == Shape::CPDI || opt_.shape == Shape::B2CPDI, buf_->external);
      external = &buf_->external;
    }
    const StepContext context{
        .options = &opt_,
        .ops = &prep_.ops,
        .mt = !uses_consistent_mass(opt_, grid_update_)     ? nullptr
              : opt_.transfer == Transfer::VelocityGradient ? &prep_.transfer_mass(P.X)
                                                            : &prep_.consistent_mass(),
        .solver = solver_.get(),
        .grid = &prep_.ops.grid, // the step's nodes: the particles' window or the grid
        .bcs = &prep_.bcs,
        .gravity = model.gravity,
        .external = external,
        .contact_nodes = contact ? &prep_.contact : nullptr,
        .time = model.time,
        .dt = dt,
        .grid_update = grid_update_,
        .transport = heat() ? &transport_context(model) : nullptr};
    clock.lap(prep_.times.mass_matrix);
    ParticleFields fields{P.X, P.V, P.F, P.stress, P.volume0};
    if (opt_.transfer == Transfer::VelocityGradient) {
      if (P.gradient.rows() != P.size() || P.gradient.cols() != P.dim * P.dim)
        P.gradient.setZero(P.size(), P.dim * P.dim); // none yet: the start is uniform motion
      fields.gradient = &P.gradient;
    }
    const bool shock = uses_shock_physics(model.materials);
    if (shock) {
      if (P.energy.size() != P.size()) // no energy column: U = 0
        P.energy.setZero(P.size());
      buf_->shock.energy = &P.energy;
      buf_->shock.dx = model.grid.min_cell_size();
      buf_->shock.viscous_work = 0;
    }
    const bool plastic = uses_plasticity(model.materials);
    if (plastic) {
      initial_plastic_state(P); // none yet: b̄ᵉ of F, ε̄ᵖ = 0
      buf_->plastic.elastic_cauchy_green = &P.elastic_cauchy_green;
      buf_->plastic.plastic_strain = &P.plastic_strain;
      buf_->plastic.plastic_work = 0;
    }
    buf_->density.resize(0);
    buf_->thermal.temperature = &P.temperature;
    MaterialStrainUpdate strain(
        model.materials, P.material, opt_.deformation, shock ? &buf_->shock : nullptr,
        &buf_->density, heat() ? &buf_->thermal : nullptr, plastic ? &buf_->plastic : nullptr);
    if (!model.rigid.empty()) {
      buf_->x_start = P.X; // the rigid particles' positions at t (storage reused)
      check_rigid_motions(model.rigid, model.contact.material_field, opt_);
      start_rigid_motion(model.rigid, model.time, P, buf_->rigid_velocity);
    }
    scheme_step(context, fields, strain, buf_->step);
    clock.lap(prep_.times.update);
    // USF updates the stresses (and stores W) before the transport changes the temperatures:
    // with thermal expansion that W is of the old temperature, so energies() evaluates it anew.
    if (heat() && opt_.scheme == UpdateScheme::USF)
      for (const Material& m : model.materials)
        if (m.thermal_expansion != 0)
          buf_->density.resize(0);
    // Each condition's reaction along its direction, summed over its nodes in every field (in
    // its own field, for a condition on one). The conditions name nodes of the whole grid; R is
    // on the step's nodes (a window of it).
    const Field& R = buf_->step.g.reaction;
    const BoundaryConditions& bcs = prep_.bcs;
    const Grid& sg = prep_.ops.grid;
    const Index ng = sg.num_nodes();
    // The rigid materials' conditions come last (add_rigid_conditions); their nodes' mass is
    // a free body's inertia.
    const size_t first_rigid =
        bcs.conditions.size() - model.rigid.size() * size_t(model.grid.dim());
    reactions_.assign(bcs.conditions.size(), 0.0);
    buf_->rigid_mass.assign(bcs.conditions.size() - first_rigid, 0.0);
    for (size_t c = 0; c < bcs.conditions.size() && R.rows() > 0; ++c) {
      const VelocityCondition& bc = bcs.conditions[c];
      for (const Index whole : bc.nodes) {
        const Index i = sg.is_window() ? sg.node_of_whole(whole) : whole;
        if (i < 0)
          continue; // outside the window: no mass, no reaction
        for (Index row = bc.field < 0 ? i : bc.field * ng + i; row < R.rows();
             row += bc.field < 0 ? ng : R.rows()) {
          for (int a = 0; a < R.cols(); ++a)
            reactions_[c] += bc.direction[a] * R(row, a);
          if (c >= first_rigid)
            buf_->rigid_mass[c - first_rigid] += prep_.ops.m[row];
        }
      }
    }
    if (!model.rigid.empty()) // rigid.hpp: the prescribed or free motion, whatever the grid did
      move_rigid_particles(model.rigid, buf_->x_start, model.time, dt, buf_->rigid_velocity,
                           reactions_.data() + first_rigid, buf_->rigid_mass.data(), P);
    clock.lap(prep_.times.reactions);
    if (contact)
      state_.friction_work += prep_.contact.friction_work;
    if (shock)
      state_.viscous_work += buf_->shock.viscous_work;
    if (plastic)
      state_.plastic_work += buf_->plastic.plastic_work;
  } catch (const NumericalError& e) {
    throw at_step(e, model.step + 1, model.time + dt);
  }
  model.time += dt;
  ++model.step;
}

} // namespace smpm
