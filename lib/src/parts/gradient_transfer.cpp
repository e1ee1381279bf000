// SPDX-License-Identifier: BSD-3-Clause
// The velocity-gradient transfer as a part of the step (StepOptions::transfer; Wallstedt &
// Guilkey 2007): the particles carry L_p, P2G adds Σ_b D_bᵀ M L_{·b} with D_b = S ∘ Δ_b over S's
// pattern (affine_offsets, once per step), the particle update sets L_p = G u, and the
// grid-velocity updates that use a consistent mass use m̃_L (assemble_transfer_mass) in place of
// m̃. The linearised step takes it with L in its state.
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
    Particles& P = s.model.particles;
    // Δ_b at the positions S was assembled at, the step's start: the P2G of task 1 and the
    // re-extrapolation of USL+ and USAVG+ use that S, for which Σ_i S_pi x_i = X_p holds.
    affine_offsets(particle_operators(s.prep.ops), s.prep.ops.grid, P.X, offsets_);
    L_ = &P.gradient;
    term_ = {&offsets_, L_};
    s.context.affine = &term_;
    if (uses_consistent_mass(s.options, s.context.grid_update))
      s.context.mt = &s.prep.transfer_mass(P.X);
    s.hooks.push_back(this);
  }
  void begin_linearised(StepStart& s) override {
    start(s.model);
    begin(s);
    s.linear_state->push_back(&s.model.particles.gradient); // P2G reads L: it is state
  }
  // L_p = G u, u the grid velocity the particles took.
  void after_particles(const StepContext& c, const Field& u, ParticleFields&) override {
    velocity_gradient(particle_operators(*c.ops), u, *L_);
  }
  std::string not_distributed(const Model&) const override {
    return "the velocity-gradient transfer (step.transfer)";
  }

private:
  AffineOffsets offsets_;
  AffineMomentum term_;
  Field* L_ = nullptr;
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
