// SPDX-License-Identifier: BSD-3-Clause
// The affine transfers as a part of the step (StepOptions::transfer): the particles carry an
// affine velocity L_p, P2G adds Σ_b D_bᵀ M L_{·b} with D_b = S ∘ Δ_b over S's pattern
// (affine_offsets, once per step), the particle update sets L_p = Σ_i u_i ⊗ g_pi from the grid
// velocity u the particles took, and the grid-velocity updates that use a consistent mass use
// the transfer's own mass operator in place of m̃. The two transfers differ only in g:
// - velocity_gradient (Wallstedt & Guilkey 2007): g = ∇S, L_p = G u, the mass m̃_L
//   (assemble_transfer_mass, not symmetric);
// - apic (Jiang et al. 2015): g = Ĝ = D_p⁻¹ S Δ (apic_weights), L_p = C_p = B_p D_p⁻¹, the mass
//   m̃_A (assemble_affine_mass, symmetric). The particles carry C_p with D_p at the G2P's
//   positions, where Jiang et al. carry B_p and divide by D_p at the next P2G's: the same for
//   their B-splines (D_p = h²/4 I), but for GIMP and CPDI, whose D_p moves with the particle,
//   C_p keeps an affine velocity field affine as the particles move (carrying B_p, the spinning
//   block of tests/analysis/test_gradient_transfer.cpp loses 0.75% of its angular momentum in
//   200 steps with CPDI, against 1.4e-4 to 1.6e-4).
// The linearised step takes either with L in its state.
#include "parts.hpp"

namespace smpm::parts {
namespace {

class GradientTransfer final : public StepPart {
public:
  explicit GradientTransfer(const StepOptions& options)
      : apic_(options.transfer == Transfer::Apic), shape_(options.shape) {}
  void start(Model& model) override {
    Particles& P = model.particles;
    if (P.gradient.rows() != P.size() || P.gradient.cols() != P.dim * P.dim)
      P.gradient.setZero(P.size(), P.dim * P.dim); // none yet: the start is uniform motion
  }
  void begin(StepStart& s) override {
    Particles& P = s.model.particles;
    // Δ_b at the positions S was assembled at, the step's start: the P2G of task 1 and the
    // re-extrapolation of USL+ and USAVG+ use that S, for which Σ_i S_pi x_i = X_p holds.
    const ParticleOperators op = particle_operators(s.prep.ops);
    affine_offsets(op, s.prep.ops.grid, P.X, offsets_);
    if (apic_) {
      apic_weights(op, offsets_, shape_, weights_);
      g_ = weights_.pointers();
    }
    L_ = &P.gradient;
    term_ = {&offsets_, L_};
    s.context.affine = &term_;
    if (uses_consistent_mass(s.options, s.context.grid_update))
      s.context.mt = &s.prep.transfer_mass(P.X, apic_ ? &g_ : nullptr);
    s.hooks.push_back(this);
  }
  void begin_linearised(StepStart& s) override {
    start(s.model);
    begin(s);
    s.linear_state->push_back(&s.model.particles.gradient); // P2G reads L: it is state
  }
  // L_p = G u (velocity_gradient) or C_p = Σ_i u_i ⊗ Ĝ_pi (apic), u the grid velocity the
  // particles took.
  void after_particles(const StepContext& c, const Field& u, ParticleFields&) override {
    const ParticleOperators op = particle_operators(*c.ops);
    velocity_gradient(apic_ ? with_weights(op, weights_) : op, u, *L_);
  }
  std::string not_distributed(const Model&) const override {
    return apic_ ? "the APIC transfer (step.transfer)"
                 : "the velocity-gradient transfer (step.transfer)";
  }

private:
  bool apic_;
  Shape shape_;
  ApicWeights weights_;
  std::array<const double*, 3> g_{};
  AffineOffsets offsets_;
  AffineMomentum term_;
  Field* L_ = nullptr;
};

std::unique_ptr<StepPart> make(const StepOptions& options) {
  if (options.transfer == Transfer::Standard)
    return nullptr;
  return std::make_unique<GradientTransfer>(options);
}

constexpr ParticleColumn kColumns[] = {
    {.name = "gradient",
     .field = &Particles::gradient,
     .width = ColumnWidth::Tensor,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), P.dim * P.dim)); },
     .shape = "N x d^2",
     .meaning = "affine velocities L_p (row-major): G v, or APIC's B_p D_p^-1",
     .needs = "step.transfer",
     .xdmf = "velocity_gradient"}};
} // namespace

const Entry gradient_transfer{make, kColumns};

} // namespace smpm::parts
