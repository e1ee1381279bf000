// SPDX-License-Identifier: BSD-3-Clause
// Rigid bodies as a part of the step (rigid.hpp): before the stages, the particles of each
// prescribed motion take its velocity at t; after them, every rigid material moves by its
// motion (free bodies by the reactions of their conditions on their nodes' mass), whatever the
// grid did.
#include "parts.hpp"

#include "sparsempm/rigid.hpp"

namespace smpm::parts {
namespace {

class RigidBodies final : public StepPart {
public:
  void begin(StepStart& s) override {
    const Model& model = s.model;
    if (model.rigid.empty())
      return;
    x_start_ = model.particles.X; // the rigid particles' positions at t (storage reused)
    check_rigid_motions(model.rigid, model.contact.material_field, s.options);
    start_rigid_motion(model.rigid, model.time, s.model.particles, velocity_, s.context.sums);
  }
  void end(StepEnd& e) override {
    Model& model = e.model;
    if (model.rigid.empty())
      return;
    // The rigid materials' conditions come last (add_rigid_conditions); their nodes' mass is a
    // free body's inertia.
    const size_t first = e.reactions.size() - model.rigid.size() * size_t(model.grid.dim());
    move_rigid_particles(model.rigid, x_start_, model.time, e.dt, velocity_,
                         e.reactions.data() + first, e.condition_mass.data() + first,
                         model.particles);
  }

private:
  Field x_start_;                         // the positions at the step's start
  std::vector<Eigen::Vector3d> velocity_; // each rigid motion's velocity at t
};

std::unique_ptr<StepPart> make(const StepOptions&) {
  return std::make_unique<RigidBodies>();
}

} // namespace

const Entry rigid_bodies{make, {}};

} // namespace smpm::parts
