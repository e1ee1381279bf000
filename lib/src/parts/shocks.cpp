// SPDX-License-Identifier: BSD-3-Clause
// Shock physics as a part of the step (contact 2020 §4, material.hpp): Mie–Grüneisen particles
// carry their internal energy U (0 to start), which the strain update advances with the
// pressure and the artificial viscosity (its strain hooks), whose work heats the particles with
// heat transport and the run tallies.
#include "parts.hpp"

#include "../parallel.hpp"

#include <Eigen/LU>

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
    s.hooks.push_back(this);
  }
  // J and p + q of every particle before the update (contact 2020 Eqs. 51–52); a plastic
  // particle's shear term is G dev(b̄ᵉ)/J.
  void before_deformation(StrainStep& s) override {
    ParticleFields& f = s.fields;
    const Index N = f.F.rows();
    const int d = int(f.X.cols());
    state_.J_old.resize(N);
    state_.p_old.resize(N);
    state_.pressure.resize(N);
    detail::parallel_for(N, [&](Index p) {
      state_.J_old[p] = embed_3d(f.F.data() + p * f.F.outerStride(), d).determinant();
    });
    shock_pressure(s.materials, s.material, f.F, f.stress, state_.p_old);
    if (const PlasticState* plastic = s.couplings.plastic)
      plastic_shock_pressure(s.materials, s.material, f.F, f.stress, *plastic->elastic_cauchy_green,
                             state_.p_old);
  }
  // The shock stresses and energies after the elastic ones; the viscosity's work is heat.
  void after_stress(StrainStep& s) override {
    ParticleFields& f = s.fields;
    ThermalStrainState* thermal = s.couplings.thermal;
    state_.viscous_work += update_shock_stress(
        s.materials, s.material, f.F, f.volume0, state_.J_old, state_.p_old, s.dt, state_.dx,
        *state_.energy, state_.pressure, f.stress, thermal ? &state_.work : nullptr);
    if (thermal)
      heat_of_work(s.materials, s.material, f.volume0, state_.work, *thermal->temperature);
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

// The run's tally of the artificial viscosity's work (StepperState::viscous_work), 0 without
// Mie–Grüneisen materials: a series of every run, so that energy balances read alike.
constexpr PartSeries kSeries[] = {{"viscous", "work of the artificial viscosity since t = 0", ""}};
void series_values(const SeriesInput& in, std::span<double> out) {
  out[0] = in.state.viscous_work;
}
} // namespace

const Entry shocks{make, kColumns, kSeries, series_values};

} // namespace smpm::parts
