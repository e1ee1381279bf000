// SPDX-License-Identifier: BSD-3-Clause
// J2 plasticity as a part of the step (plasticity.hpp): particles of a plastic material carry
// b̄ᵉ and ε̄ᵖ (b̄ᵉ of F and ε̄ᵖ = 0 to start), which the strain update returns to the yield
// surface (its strain hooks), and the plastic work heats the particles with heat transport and
// the run tallies it.
#include "parts.hpp"

#include "sparsempm/plasticity.hpp"

#include <Eigen/LU>

#include <cmath>

namespace smpm::parts {
namespace {

class Plasticity final : public StepPart {
public:
  void start(Model& model) override {
    if (uses_plasticity(model.materials))
      initial_plastic_state(model.particles); // none yet: b̄ᵉ of F, ε̄ᵖ = 0
  }
  void begin(StepStart& s) override {
    on_ = uses_plasticity(s.model.materials);
    if (!on_)
      return;
    state_.elastic_cauchy_green = &s.model.particles.elastic_cauchy_green;
    state_.plastic_strain = &s.model.particles.plastic_strain;
    state_.plastic_work = 0;
    s.strain.plastic = &state_;
    s.hooks.push_back(this);
  }
  void before_deformation(StrainStep& s) override {
    state_.F_old = s.fields.F; // storage reused from step to step
  }
  // The J2 return from F_old to F after the elastic stress update and the shock's pressure; the
  // plastic work is heat.
  void after_stress(StrainStep& s) override {
    ParticleFields& f = s.fields;
    const ShockState* shock = s.couplings.shock;
    state_.plastic_work +=
        update_plastic_stress(s.materials, s.material, f.F, f.volume0,
                              shock ? &shock->pressure : nullptr, state_, f.stress, s.density);
    if (ThermalStrainState* thermal = s.couplings.thermal)
      heat_of_work(s.materials, s.material, f.volume0, state_.work, *thermal->temperature);
  }
  void end(StepEnd& e) override {
    if (on_)
      e.state.plastic_work += state_.plastic_work;
  }

  // A yielded particle's stress is that of its elastic state b̄ᵉ, not of F: the linearised step
  // takes the elastic branch there (elastic_state_stress under f = I ± εE, b̄ᵉ_tr = f̄ b̄ᵉ f̄ᵀ as
  // the return's trial state): the stiffer branch, and the one NairnMPM's time step assumes for
  // plastic materials (HEIsotropic::WaveSpeed, the elastic √((K + 4G/3)/ρ)). A particle on the
  // yield surface loading further takes the softer plastic branch: not a linear map.
  void tangents(const Model& model, Field& K) const override {
    const Particles& P = model.particles;
    if (!uses_plasticity(model.materials) || P.elastic_cauchy_green.rows() != P.size() ||
        P.elastic_cauchy_green.cols() != 9 || P.plastic_strain.size() != P.size())
      return; // no plastic state yet (initial_plastic_state): b̄ᵉ of F, whose stress is σ(F)
    for (Index q = 0; q < P.size(); ++q) {
      const Material& mat = model.materials[size_t(P.material[q])];
      if (!mat.plastic())
        continue;
      const Eigen::Matrix3d F = embed_3d(P.F.row(q).data(), P.dim);
      const Eigen::Matrix3d be = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
          P.elastic_cauchy_green.row(q).data());
      stress_tangent(
          P.dim,
          [&](const Eigen::Matrix3d& f) {
            const Eigen::Matrix3d fbar = std::cbrt(1 / f.determinant()) * f;
            return elastic_state_stress(mat, f * F, fbar * be * fbar.transpose());
          },
          K.row(q).data());
    }
  }

private:
  PlasticState state_;
  bool on_ = false;
};

std::unique_ptr<StepPart> make(const StepOptions&) {
  return std::make_unique<Plasticity>();
}

constexpr ParticleColumn kColumns[] = {
    {.name = "plastic_strain",
     .vector = &Particles::plastic_strain,
     .range = ColumnRange::NonNegative,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), 1)); },
     .required = [](const Model& model) { return uses_plasticity(model.materials); },
     .why_required = "the run has plastic materials",
     .shape = "N",
     .meaning = "equivalent plastic strains (J2 plasticity)",
     .needs = "yield_stress",
     .xdmf = "plastic_strain"},
    {.name = "elastic_cauchy_green",
     .field = &Particles::elastic_cauchy_green,
     .width = ColumnWidth::Nine,
     // A set without a plastic state starts elastic: b̄ᵉ of its F.
     .absent = [](const Particles& P) { return elastic_state_of(P.F, P.dim); },
     .required = [](const Model& model) { return uses_plasticity(model.materials); },
     .why_required = "the run has plastic materials",
     .shape = "N x 9",
     .meaning = "isochoric elastic left Cauchy-Green tensors (3 x 3 row-major)",
     .needs = "yield_stress",
     .xdmf = ""}};

// The run's tally of plastic work (StepperState::plastic_work), 0 without J2 materials: a series
// of every run.
constexpr PartSeries kSeries[] = {{"plastic", "plastic work since t = 0 (J2 plasticity)", ""}};
void series_values(const SeriesInput& in, std::span<double> out) {
  out[0] = in.state.plastic_work;
}
} // namespace

const Entry plasticity{make, kColumns, kSeries, series_values};

} // namespace smpm::parts
