#include "sparsempm/step_preparation.hpp"

#include "sparsempm/stages.hpp"

namespace smpm {

const SparseRowMatrix& StepPreparation::consistent_mass() {
  if (!mt_current_) {
    assemble_consistent_mass(ops, mt_);
    mt_current_ = true;
  }
  return mt_.matrix;
}

void prepare_step(const Model& model, Shape shape, StepPreparation& s) {
  const Particles& P = model.particles;
  s.mt_current_ = false;
  const int nf = model.contact.fields();
  if (nf > 1) { // multimaterial: the fields as blocks of columns of S (contact.hpp)
    model.contact.particle_fields(P.material, s.field);
    assemble(model.grid, P, shape, s.ops, nf, &s.field);
  } else {
    s.field.resize(0);
    assemble(model.grid, P, shape, s.ops);
  }
  // The conditions of the step on its nodes (the particles' window or the grid, ops.grid); the
  // walls move (FMPM 2026 §3.1).
  model.bcs.step_conditions(s.ops.grid, s.ops.active, model.time, s.bcs);
  if (nf > 1) {
    P.jacobian(s.volume);
    s.volume.array() *= P.volume0.array();
    const ContactParticles cp{P.X, P.F, P.half_length, s.volume};
    find_contact_nodes(s.ops.grid, s.ops, particle_operators(s.ops), model.contact, cp, s.contact,
                       &s.bcs);
  }
}

} // namespace smpm
