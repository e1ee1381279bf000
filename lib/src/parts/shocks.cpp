// SPDX-License-Identifier: BSD-3-Clause
// Shock physics as a part of the step (contact 2020 §4, material.hpp): Mie–Grüneisen particles
// carry their internal energy U (0 to start), which the strain update advances with the
// pressure and the artificial viscosity, whose work the run tallies.
#include "parts.hpp"

namespace smpm::parts {
namespace {

class Shocks final : public StepPart {
public:
  void start(Model& model) override {
    Particles& P = model.particles;
    if (uses_shock_physics(model.materials) && P.energy.size() != P.size())
      P.energy.setZero(P.size()); // no energy column: U = 0
  }
  void begin(StepStart& s) override {
    on_ = uses_shock_physics(s.model.materials);
    if (!on_)
      return;
    state_.energy = &s.model.particles.energy;
    state_.dx = s.model.grid.min_cell_size();
    state_.viscous_work = 0;
    s.strain.shock = &state_;
  }
  void end(StepEnd& e) override {
    if (on_)
      e.state.viscous_work += state_.viscous_work;
  }

private:
  ShockState state_;
  bool on_ = false;
};

std::unique_ptr<StepPart> make(const StepOptions&) {
  return std::make_unique<Shocks>();
}

constexpr ParticleColumn kColumns[] = {
    {.name = "energy",
     .vector = &Particles::energy,
     .always = true,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), 1)); },
     .required = [](const Model& model) { return uses_shock_physics(model.materials); },
     .why_required = "the Mie-Gruneisen materials need it",
     .shape = "N",
     .meaning = "internal energy per unit mass U (mie-gruneisen)",
     .needs = "",
     .xdmf = "energy"}};
} // namespace

const Entry shocks{make, kColumns};

} // namespace smpm::parts
