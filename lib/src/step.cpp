// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/step.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/scheme.hpp"
#include "sparsempm/step_part.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <thread>

namespace smpm {

struct Stepper::Buffers {
  StepBuffers step;
  std::vector<std::unique_ptr<StepPart>> parts; ///< the parts of the step (step_parts)
  std::vector<StageHooks*> hooks;               ///< the parts with stage hooks in this step
  std::vector<double> condition_mass;           ///< Σ m_i on each condition's nodes
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
  buf_->parts = step_parts(opt_);
}

Stepper::Stepper(const StepOptions& options, NodeSums& sums) : Stepper(options) {
  if (opt_.velocity == VelocityUpdate::XPIC)
    throw InputError("a step across processes is FLIP, PIC, FMPM(k) or the exact update (not "
                     "XPIC) for now");
  if (solver_ && !solver_->across_processes())
    throw InputError("the exact update across processes needs a MassSolver that solves across "
                     "them with each step's m~ (sparsempm::petsc's step_mass_solver_factory), "
                     "not one process's");
  sums_ = &sums;
  prep_.ops.node_range = NodeRange::Particles;
}

void Stepper::release_others(const std::exception_ptr& failure) const {
  if (!sums_)
    return;
  try {
    std::rethrow_exception(failure);
  } catch (const FailedElsewhere&) { // the others know
  } catch (...) {
    sums_->fail();
  }
}

Stepper::~Stepper() = default;
Stepper::Stepper(Stepper&&) noexcept = default;
Stepper& Stepper::operator=(Stepper&&) noexcept = default;

Energies Stepper::energies(const Model& model) const {
  const bool stored = buf_->density.size() == model.particles.size();
  return smpm::energies(model, stored ? &buf_->density : nullptr);
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

void Stepper::prepare_configuration(const Model& model) {
  prepare_step(model, opt_.shape, prep_, sums_);
  for (const std::unique_ptr<StepPart>& part : buf_->parts)
    part->prepare(model, prep_);
}

const StepPreparation& Stepper::prepare(const Model& model) {
  const Exclusive hold(*this);
  prepared_ = {};
  try {
    prepare_configuration(model);
  } catch (const FailedElsewhere&) {
    throw;
  } catch (const NumericalError& e) { // the next step's failure
    release_others(std::current_exception());
    throw at_step(e, model.step + 1, model.time);
  } catch (...) {
    release_others(std::current_exception());
    throw;
  }
  prepared_ = prepared_of(model);
  return prep_;
}

namespace {

// dt and the model's clock must be positive and finite.
void check_clock(const Model& model, double dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw InputError("step: the time step must be positive and finite, got " + number_text(dt));
  if (!std::isfinite(model.time))
    throw InputError("step: the model's time must be finite, got " + number_text(model.time));
}

// Each condition's reaction along its direction and the mass on its nodes, summed over its
// nodes in every field (in its own field, for a condition on one). The conditions name nodes of
// the whole grid; R and m are on the step's nodes (a window of it).
void condition_sums(const StepPreparation& prep, const Field& R, std::vector<double>& reactions,
                    std::vector<double>& mass, const NodeSums* sums) {
  const BoundaryConditions& bcs = prep.bcs;
  const Grid& sg = prep.ops.grid;
  const Index ng = sg.num_nodes();
  const size_t nc = bcs.conditions.size();
  reactions.assign(nc, 0.0);
  mass.assign(nc, 0.0);
  // Across processes each node's terms go in a row of `terms` (reaction and mass of each
  // condition), summed over every node once by the node sums.
  thread_local Field terms;
  if (sums)
    terms.setZero(prep.ops.num_nodes(), Index(2 * nc));
  for (size_t c = 0; c < nc && R.rows() > 0; ++c) {
    const VelocityCondition& bc = bcs.conditions[c];
    for (const Index whole : bc.nodes) {
      const Index i = sg.is_window() ? sg.node_of_whole(whole) : whole;
      if (i < 0)
        continue; // outside the window: no mass, no reaction
      for (Index row = bc.field < 0 ? i : bc.field * ng + i; row < R.rows();
           row += bc.field < 0 ? ng : R.rows()) {
        double& reaction = sums ? terms(row, Index(c)) : reactions[c];
        for (int a = 0; a < R.cols(); ++a)
          reaction += bc.direction[a] * R(row, a);
        (sums ? terms(row, Index(nc + c)) : mass[c]) += prep.ops.m[row];
      }
    }
  }
  if (sums) { // the totals over every node once
    std::vector<double> totals(2 * nc);
    sums->sum_rows(terms, totals.data());
    std::copy(totals.begin(), totals.begin() + Index(nc), reactions.begin());
    std::copy(totals.begin() + Index(nc), totals.end(), mass.begin());
  }
}

} // namespace

bool Stepper::grid_velocity_step(const Model& model, double dt) {
  // Periodic FMPM (§3.3): the grid-velocity update on steps that cross the budget C_X, FLIP on
  // the others.
  if (opt_.velocity == VelocityUpdate::FLIP)
    return false;
  if (opt_.periodic_cx <= 0)
    return true;
  const double courant = courant_of(model, dt); // the largest over the processes
  return periodic_fmpm_step(opt_.periodic_cx, sums_ ? sums_->maximum(courant) : courant,
                            state_.courant_budget);
}

StepContext Stepper::stage_context(const Model& model, double dt) const {
  return {.options = &opt_,
          .ops = &prep_.ops,
          .solver = solver_.get(),
          .grid = &prep_.ops.grid, // the step's nodes: the particles' window or the grid
          .bcs = &prep_.bcs,
          .gravity = model.gravity,
          .time = model.time,
          .dt = dt,
          .grid_update = grid_update_,
          .sums = sums_};
}

void Stepper::start(Model& model) {
  const Exclusive hold(*this);
  for (const std::unique_ptr<StepPart>& part : buf_->parts)
    part->start(model); // the columns the parts carry, where the particles have none yet
}

void Stepper::step(Model& model, double dt) {
  const Exclusive hold(*this);
  check_clock(model, dt);
  Particles& P = model.particles;
  if (sums_) // the same answer on every process: nothing collective has begun
    check_distributed(buf_->parts, model, "a step");
  try {
    bool prepared = prepared_.model && prepared_ == prepared_of(model);
    if (sums_) // every process prepares again when one must (the preparation is collective)
      prepared = sums_->maximum(prepared ? 0.0 : 1.0) == 0.0;
    prepared_ = {};
    start(model);
    if (!prepared)
      prepare_configuration(model);
    PhaseClock clock;
    grid_update_ = grid_velocity_step(model, dt);
    StepContext context = stage_context(model, dt); // the parts add theirs
    ParticleFields fields{P.X, P.V, P.F, P.stress, P.volume0};
    StrainCouplings strain;
    buf_->hooks.clear();
    StepStart start{model, opt_, prep_, context, fields, strain, buf_->step, buf_->hooks};
    for (const std::unique_ptr<StepPart>& part : buf_->parts)
      part->begin(start);
    context.hooks = buf_->hooks;
    if (!context.mt && uses_consistent_mass(opt_, grid_update_))
      context.mt = &prep_.consistent_mass();
    clock.lap(prep_.times.mass_matrix);
    buf_->density.resize(0);
    MaterialStrainUpdate update(model.materials, P.material, opt_.deformation, &buf_->density,
                                strain, buf_->hooks);
    scheme_step(context, fields, update, buf_->step);
    clock.lap(prep_.times.update);
    condition_sums(prep_, buf_->step.g.reaction, reactions_, buf_->condition_mass, sums_);
    StepEnd end{model, dt, prep_, reactions_, buf_->condition_mass, buf_->density, state_};
    for (const std::unique_ptr<StepPart>& part : buf_->parts)
      part->end(end);
    clock.lap(prep_.times.reactions);
  } catch (const FailedElsewhere&) {
    throw;
  } catch (const NumericalError& e) {
    release_others(std::current_exception());
    throw at_step(e, model.step + 1, model.time + dt);
  } catch (...) {
    release_others(std::current_exception());
    throw;
  }
  model.time += dt;
  ++model.step;
}

} // namespace smpm
