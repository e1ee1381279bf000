// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/step_preparation.hpp"

#include "parallel.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/fmpm.hpp"
#include "sparsempm/stages.hpp"

#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace smpm {

const SparseRowMatrix& StepPreparation::consistent_mass() {
  if (!mt_current_) {
    assemble_consistent_mass(ops, mt_);
    mt_current_ = true;
  }
  return mt_.matrix;
}

const SparseRowMatrix& StepPreparation::transfer_mass(const ConstFieldRef& X,
                                                      const std::array<const double*, 3>* weights) {
  if (!mtL_current_) {
    if (weights)
      assemble_affine_mass(ops, X, *weights, mtL_);
    else
      assemble_transfer_mass(ops, X, mtL_);
    mtL_current_ = true;
  }
  return mtL_.matrix;
}

const SparseRowMatrix& StepPreparation::consistent_capacity() {
  SMPM_VERIFY(transport_, "StepPreparation: c~ needs a preparation with heat transport");
  if (!ct_current_) {
    assemble_consistent_capacity(ops, transport.capacity, ct_);
    ct_current_ = true;
  }
  return ct_.matrix;
}

namespace {

// Masses and initial volumes must stay positive and finite (a program, or Python through the
// arrays' views, can set any value between steps). Each particle range is checked by vectorised
// reductions: its smallest value > 0, its largest < ∞, its sum finite (a NaN makes the sum NaN;
// a sum of finite values too large for a double only sends the check to the scan), both arrays
// in one parallel region. The first bad particle is then found by a serial scan, masses first,
// so the message does not depend on the threads.
void check_amounts(const Eigen::VectorXd& mass, const Eigen::VectorXd& volume0) {
  const std::array<std::pair<const Eigen::VectorXd*, const char*>, 2> amounts{
      {{&mass, "mass"}, {&volume0, "volume0"}}};
  const Index n = mass.size();
  SMPM_VERIFY(volume0.size() == n, "check_amounts: one mass and one volume0 per particle");
  std::atomic<bool> suspect{false};
  detail::parallel_segments(n, [&](Index p0, Index count) {
    if (count == 0)
      return;
    for (const auto& [amount, name] : amounts) {
      const auto range = amount->segment(p0, count);
      if (!(range.minCoeff() > 0 && range.maxCoeff() < std::numeric_limits<double>::infinity() &&
            std::isfinite(range.sum())))
        suspect.store(true, std::memory_order_relaxed);
    }
  });
  if (!suspect.load())
    return;
  for (const auto& [amount, name] : amounts)
    for (Index p = 0; p < n; ++p)
      if (!((*amount)[p] > 0 && std::isfinite((*amount)[p])))
        throw InputError("particle " + std::to_string(p) + ": " + name + " " +
                         number_text((*amount)[p]) + " must be positive and finite");
}

} // namespace

void complete_masses(NodeSums& sums, Operators& ops) {
  sums.bind(ops.grid, ops.fields);
  Field m = ops.m;
  sums.add(m);
  ops.m = m.col(0);
  const Index n = ops.m.size(), ng = ops.grid_node_count;
  const double largest = sums.maximum(largest_total_mass(ops.m, ops.fields, ng, 0, ng));
  active_nodes_of(ops.m, largest, 0, n, ops.active, ops.m_inv);
}

void prepare_step(const Model& model, Shape shape, StepPreparation& s, NodeSums* sums) {
  PhaseClock clock;
  const Particles& P = model.particles;
  check_amounts(P.mass, P.volume0);
  s.mt_current_ = false;
  s.mtL_current_ = false;
  s.ct_current_ = false;
  s.transport_ = false;
  const int nf = model.contact.fields();
  if (nf > 1) { // multimaterial: the fields as blocks of columns of S (contact.hpp)
    model.contact.particle_fields(P.material, s.field);
    assemble(model.grid, P, shape, s.ops, nf, &s.field);
    activate_bonded_fields(model.contact, s.ops);
  } else {
    s.field.resize(0);
    assemble(model.grid, P, shape, s.ops);
  }
  if (sums) // the totals over the processes, before the conditions select active nodes
    complete_masses(*sums, s.ops);
  clock.lap(s.times.assemble);
  // The conditions of the step on its nodes (the particles' window or the grid, ops.grid); the
  // walls move (FMPM 2026 §3.1).
  model.bcs.step_conditions(s.ops.grid, s.ops.active, model.time, s.bcs);
  add_rigid_conditions(model.rigid, P, model.contact.material_field, s.ops, model.time, s.bcs,
                       sums); // rigid.hpp
  clock.lap(s.times.conditions);
  if (nf > 1) {
    rigid_fields(model.rigid, model.contact.material_field, nf, s.contact.rigid);
    P.jacobian(s.volume);
    s.volume.array() *= P.volume0.array();
    const ContactParticles cp{P.X, P.F, P.half_length, s.volume};
    find_contact_nodes(s.ops.grid, s.ops, particle_operators(s.ops), model.contact, cp, s.contact,
                       &s.bcs);
    clock.lap(s.times.contact);
  }
}

} // namespace smpm
