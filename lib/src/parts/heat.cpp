// SPDX-License-Identifier: BSD-3-Clause
// Heat transport as a part of the step (FMPM 2026 §3.5, transport.hpp): the particles carry
// temperatures (T_ref of their material to start), the step's preparation adds the transport
// operators and the temperature conditions, the stages run the transport on them, the strain
// update takes the materials' thermal couplings (its strain hooks: the isentropic heating of the
// deformation), and a run writes the thermal sums of every step as its series.
#include "parts.hpp"

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/transport.hpp"

#include <algorithm>
#include <iterator>
#include <limits>
#include <span>

namespace smpm {
namespace parts {
namespace {

class Heat final : public StepPart {
public:
  Heat(TransportUpdate update, Shape shape) : update_(update), shape_(shape) {}
  void start(Model& model) override {
    if (!model.temperature_bcs.conditions.empty())
      if (const std::string why = held_temperature_refusal(shape_); !why.empty())
        throw InputError("temperature condition '" + model.temperature_bcs.conditions[0].label +
                         "': " + why);
    Particles& P = model.particles;
    if (P.temperature.size() != P.size()) // no temperatures yet: T_ref
      set_reference_temperatures(P, model.materials);
  }
  void prepare(const Model& model, StepPreparation& prep) override {
    prepare_heat_transport(model, prep, update_);
  }
  std::string not_distributed(const Model&) const override {
    return "heat transport"; // its node sums (c, τ, K T, c~ products) are one process's
  }
  void begin(StepStart& s) override {
    Particles& P = s.model.particles;
    TransportContext& t = transport_;
    t.update = s.options.transport.update;
    t.fmpm = transport_fmpm_options(s.options);
    t.limiter = s.options.transport.limiter;
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
  TransportUpdate update_;
  Shape shape_;
  std::unique_ptr<MassSolver> solver_; // the exact transport update's solver
  TransportContext transport_;
  TransportState* state_ = nullptr; // the transport stages' fields (StepBuffers::heat)
  ThermalStrainState thermal_;
  bool usf_ = false;
};

std::unique_ptr<StepPart> make(const StepOptions& options) {
  if (options.transport.update == TransportUpdate::Off)
    return nullptr;
  return std::make_unique<Heat>(options.transport.update, options.shape);
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

// The thermal sums of the state (ThermalSums, diagnostics.hpp), one series each, in its order.
constexpr PartSeries kSeries[] = {
    {"temperature_min", "lowest particle temperature", "step.transport"},
    {"temperature_max", "highest particle temperature", "step.transport"},
    {"temperature_mean", "capacity-weighted mean temperature", "step.transport"},
    {"heat", "thermal energy Q = sum M C_V (T - T_ref)", "step.transport"},
    {"internal", "internal energy U = W + Q (+ T c of thermal expansion)", "step.transport"},
    {"entropy", "entropy S = sum M C_V ln(T / T_ref) (+ c)", "step.transport"},
    {"helmholtz", "free energy A = U - sum T S", "step.transport"}};

void series_values(const SeriesInput& in, std::span<double> out) {
  const Model& model = in.model;
  if (model.particles.temperature.size() != model.particles.size()) { // none: not a number
    std::fill(out.begin(), out.end(), std::numeric_limits<double>::quiet_NaN());
    return;
  }
  const ThermalSums t = thermal_sums(model, in.energies.strain);
  const double values[] = {t.temperature_min, t.temperature_max, t.temperature_mean, t.heat,
                           t.internal,        t.entropy,         t.helmholtz};
  std::copy(std::begin(values), std::end(values), out.begin());
}
} // namespace

const Entry heat{make, kColumns, kSeries, series_values};

} // namespace parts

void prepare_heat_transport(const Model& model, StepPreparation& s, TransportUpdate update) {
  PhaseClock clock;
  prepare_transport(s.ops, model.particles, model.materials, s.transport,
                    update == TransportUpdate::Exact ? kMassTolerance : 0.0);
  clock.lap(s.times.transport);
  model.temperature_bcs.step_conditions(s.ops.grid, s.transport.nodes.active, model.time,
                                        s.temperature_bcs);
  s.transport_ = true;
  s.ct_current_ = false; // c̃ of these operators on first use
  clock.lap(s.times.conditions);
}

} // namespace smpm
