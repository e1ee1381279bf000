#include "sparsempm/step.hpp"

#include "sparsempm/advance.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/scheme.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace smpm {

struct Stepper::Buffers {
  StepBuffers step;
  Eigen::VectorXi field;  ///< velocity field of each particle (multimaterial mode)
  Eigen::VectorXd volume; ///< current particle volumes (AG contact normals)
  ContactNodes contact;
  ShockState shock;
  Eigen::VectorXd density; ///< W(F_p) of the last stress update (empty: none in the last step)
};

Stepper::Stepper(const StepOptions& options) : opt_(options), buf_(std::make_unique<Buffers>()) {
  validate(opt_);
  ops_.node_range = opt_.nodes;
  if (opt_.velocity == VelocityUpdate::Exact)
    solver_ = opt_.exact_solver(opt_.exact);
}

Stepper::~Stepper() = default;
Stepper::Stepper(Stepper&&) noexcept = default;
Stepper& Stepper::operator=(Stepper&&) noexcept = default;

Energies Stepper::energies(const Model& model) const {
  const bool stored = buf_->density.size() == model.particles.size();
  return smpm::energies(model, stored ? &buf_->density : nullptr);
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

void Stepper::step(Model& model, double dt) {
  Particles& P = model.particles;
  try {
    const int nf = model.contact.fields();
    if (nf > 1) { // multimaterial: the fields as blocks of columns of S (contact.hpp)
      model.contact.particle_fields(P.material, buf_->field);
      assemble(model.grid, P, opt_.shape, ops_, nf, &buf_->field);
    } else {
      assemble(model.grid, P, opt_.shape, ops_);
    }
    // The nodes of the step: the particles' window of the grid or the grid (ops_.grid).
    const Grid& grid = ops_.grid;
    model.bcs.select_wall_nodes(grid, ops_.active, model.time); // walls move (§3.1)
    if (nf > 1) {
      P.jacobian(buf_->volume);
      buf_->volume.array() *= P.volume0.array();
      const ContactParticles cp{P.X, P.F, P.half_length, buf_->volume};
      find_contact_nodes(grid, ops_, particle_operators(ops_), model.contact, cp, buf_->contact,
                         &model.bcs);
    }
    // Periodic FMPM (§3.3): the grid-velocity update on steps that cross the budget C_X, FLIP
    // on the others.
    grid_update_ = opt_.velocity != VelocityUpdate::FLIP;
    if (grid_update_ && opt_.periodic_cx > 0)
      grid_update_ = periodic_fmpm_step(opt_.periodic_cx, courant_of(model, dt), courant_budget_);
    if (uses_consistent_mass(opt_, grid_update_))
      assemble_consistent_mass(ops_, mt_);
    const StepContext context{.options = &opt_,
                              .ops = &ops_,
                              .mt = &mt_.matrix,
                              .solver = solver_.get(),
                              .grid = &grid,
                              .bcs = &model.bcs,
                              .body_force = model.body_force,
                              .contact_nodes = nf > 1 ? &buf_->contact : nullptr,
                              .time = model.time,
                              .dt = dt,
                              .grid_update = grid_update_};
    ParticleFields fields{P.X, P.V, P.F, P.stress, P.volume0};
    const bool shock = uses_shock_physics(model.materials);
    if (shock) {
      if (P.energy.size() != P.size()) // no energy column: U = 0
        P.energy.setZero(P.size());
      buf_->shock.energy = &P.energy;
      buf_->shock.dx = model.grid.min_cell_size();
      buf_->shock.viscous_work = 0;
    }
    buf_->density.resize(0);
    MaterialStrainUpdate strain(model.materials, P.material, opt_.deformation,
                                shock ? &buf_->shock : nullptr, &buf_->density);
    scheme_step(context, fields, strain, buf_->step);
    if (nf > 1)
      friction_work_ += buf_->contact.friction_work;
    if (shock)
      viscous_work_ += buf_->shock.viscous_work;
  } catch (const NumericalError& e) {
    throw at_step(e, model.step + 1, model.time + dt);
  }
  model.time += dt;
  ++model.step;
}

} // namespace smpm
