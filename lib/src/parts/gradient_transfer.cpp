// SPDX-License-Identifier: BSD-3-Clause
// The velocity-gradient transfer as a part of the step (StepOptions::transfer): the particles
// carry L_p, which P2G reads and the particle update sets, and the grid-velocity updates that
// use a consistent mass use m̃_L (assemble_transfer_mass) in place of m̃.
#include "parts.hpp"

namespace smpm::parts {
namespace {

class GradientTransfer final : public StepPart {
public:
  void start(Model& model) override {
    Particles& P = model.particles;
    if (P.gradient.rows() != P.size() || P.gradient.cols() != P.dim * P.dim)
      P.gradient.setZero(P.size(), P.dim * P.dim); // none yet: the start is uniform motion
  }
  void begin(StepStart& s) override {
    s.fields.gradient = &s.model.particles.gradient;
    if (uses_consistent_mass(s.options, s.context.grid_update))
      s.context.mt = &s.prep.transfer_mass(s.model.particles.X);
  }
  std::string not_distributed(const Model&) const override {
    return "the velocity-gradient transfer (step.transfer)";
  }
};

std::unique_ptr<StepPart> make(const StepOptions& options) {
  if (options.transfer != Transfer::VelocityGradient)
    return nullptr;
  return std::make_unique<GradientTransfer>();
}

constexpr ParticleColumn kColumns[] = {
    {.name = "gradient",
     .field = &Particles::gradient,
     .width = ColumnWidth::Tensor,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), P.dim * P.dim)); },
     .shape = "N x d^2",
     .meaning = "velocity gradients L_p (row-major)",
     .needs = "step.transfer",
     .xdmf = "velocity_gradient"}};
} // namespace

const Entry gradient_transfer{make, kColumns};

} // namespace smpm::parts
