// SPDX-License-Identifier: BSD-3-Clause
// Heat transport as a part of the step (FMPM 2026 §3.5, transport.hpp): the particles carry
// temperatures (T_ref of their material to start), the stages run the transport on the step's
// transport operators, and the strain update takes the materials' thermal couplings (its strain
// hooks: the isentropic heating of the deformation).
#include "parts.hpp"

#include "sparsempm/transport.hpp"

namespace smpm::parts {
namespace {

class Heat final : public StepPart {
public:
  void start(Model& model) override {
    Particles& P = model.particles;
    if (P.temperature.size() != P.size()) // no temperatures yet: T_ref
      set_reference_temperatures(P, model.materials);
  }
  void begin(StepStart& s) override {
    Particles& P = s.model.particles;
    TransportContext& t = transport_;
    t.update = s.options.transport.update;
    t.fmpm = transport_fmpm_options(s.options);
    t.ops = &s.prep.transport;
    t.ct = uses_consistent_capacity(s.options) ? &s.prep.consistent_capacity() : nullptr;
    // Made on first use: the linearised step asks the part and never steps.
    if (!solver_ && t.update == TransportUpdate::Exact)
      solver_ = s.options.exact_solver(transport_solver_options(s.options));
    t.solver = solver_.get();
    t.bcs = &s.prep.temperature_bcs;
    t.temperature = &P.temperature;
    t.energy = uses_shock_physics(s.model.materials) ? &P.energy : nullptr;
    t.materials = &s.model.materials;
    t.material = &P.material;
    state_ = &s.buffers.heat;
    s.hooks.push_back(this);
    thermal_.temperature = &P.temperature;
    s.strain.thermal = &thermal_;
    usf_ = s.options.scheme == UpdateScheme::USF;
  }
  // τ = Sᵀ 𝗖 T and T = c⁻¹ τ with the temperature conditions (task 1).
  void after_momentum(const StepContext& c, ParticleFields&) override {
    transport_content(*c.ops, transport_, c.time, *state_);
  }
  // q, τ⁺ and θ⁺ (tasks 2–3), with the frictional heat of the velocity solve's contact.
  void after_velocity(const StepContext& c, ParticleFields&) override {
    transport_update(*c.ops, transport_, c.contact_nodes, c.time, c.dt, *state_);
  }
  // The particles' temperatures (task 4).
  void after_particles(const StepContext& c, const Field&, ParticleFields&) override {
    transport_particles(*c.ops, transport_, c.dt, *state_);
  }
  // c of every particle before the deformation, and its isentropic temperature after it.
  void before_deformation(StrainStep& s) override {
    thermal_couplings(s.materials, s.material, s.fields.F, *thermal_.temperature,
                      thermal_.coupling);
  }
  void after_deformation(StrainStep& s) override {
    isentropic_heating(s.materials, s.material, s.fields.F, thermal_.coupling,
                       *thermal_.temperature);
  }
  void end(StepEnd& e) override {
    // USF updates the stresses (and stores W) before the transport changes the temperatures:
    // with thermal expansion that W is of the old temperature, so energies() evaluates it anew.
    if (usf_)
      for (const Material& m : e.model.materials)
        if (m.thermal_expansion != 0)
          e.density.resize(0);
  }

private:
  std::unique_ptr<MassSolver> solver_; // the exact transport update's solver
  TransportContext transport_;
  TransportState* state_ = nullptr; // the transport stages' fields (StepBuffers::heat)
  ThermalStrainState thermal_;
  bool usf_ = false;
};

std::unique_ptr<StepPart> make(const StepOptions& options) {
  if (options.transport.update == TransportUpdate::Off)
    return nullptr;
  return std::make_unique<Heat>();
}

constexpr ParticleColumn kColumns[] = {
    {.name = "temperature",
     .vector = &Particles::temperature,
     .range = ColumnRange::Positive,
     .range_reason = "temperatures are absolute",
     .required = [](const Model& model) { return model.particles.temperature.size() > 0; },
     .why_required = "the run has heat transport",
     .shape = "N",
     .meaning = "absolute temperatures T",
     .needs = "step.transport",
     .xdmf = "temperature"},
    {.name = "heat_source",
     .vector = &Particles::heat_source,
     .in_frames = false, // the input's, every run
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), 1)); },
     .shape = "N",
     .meaning = "heat sources r_p, power per unit mass",
     .needs = "heat_source",
     .xdmf = ""}};
} // namespace

const Entry heat{make, kColumns};

} // namespace smpm::parts
