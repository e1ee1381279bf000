// SPDX-License-Identifier: BSD-3-Clause
// A capability added from outside the library as one part in one file (step_part.hpp): each
// particle's path length s_p = ∫ |V_p| dt, carried by the particles as a column of their own,
// advanced in a stage hook after the particle update (s_p += |V_p| Δt), with its series, the
// mass-weighted mean Σ M_p s_p / Σ M_p. Registered once (register_step_part), the part is in
// every Stepper of the program it is linked into: its tests (test_toy_part.cpp) and a Python
// module built with it (tests/python/test_toy_part.py). No file of the library names it.

#include "toy_part.hpp"

#include <sparsempm/particle_columns.hpp>

#include <memory>
#include <string>

namespace smpm::toy {
namespace {

constexpr ParticleColumn kColumns[] = {
    {.name = "path_length",
     .range = ColumnRange::NonNegative,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), 1)); },
     .required = [](const Model&) { return true; },
     .why_required = "the run carries path lengths",
     .shape = "N",
     .meaning = "path length of each particle since t = 0",
     .needs = "",
     .xdmf = "path_length"}};

constexpr PartSeries kSeries[] = {{.name = "path_length_mean",
                                   .meaning = "mass-weighted mean path length",
                                   .needs = "the program's part"}};

class PathLength final : public StepPart {
public:
  void start(Model& model) override {
    Particles& P = model.particles;
    if (!has_column(P, kColumns[0])) // none yet: 0
      set_column(P, kColumns[0], Field::Zero(P.size(), 1));
  }
  void begin(StepStart& s) override {
    length_ = &s.model.particles.columns.find(kColumns[0].name)->second; // start gave it
    s.hooks.push_back(this);
  }
  // s_p += |V_p| Δt with the velocities the particle update gave.
  void after_particles(const StepContext& c, const Field&, ParticleFields& f) override {
    for (Index p = 0; p < f.V.rows(); ++p)
      (*length_)(p, 0) += f.V.row(p).norm() * c.dt;
  }
  std::string not_linearised(const Model&) const override {
    return "the particles' path lengths are not linear in the step's state";
  }

private:
  Field* length_ = nullptr;
};

} // namespace

const ParticleColumn& path_length = kColumns[0];

void path_length_mean(const SeriesInput& in, std::span<double> out) {
  const Particles& P = in.model.particles;
  out[0] = (P.mass.array() * column_values(P, kColumns[0]).col(0).array()).sum() / P.mass.sum();
}

namespace {
// The part's one line: registered before main, so in every Stepper of the program.
const bool registered = [] {
  register_step_part({.make = [](const StepOptions&) -> std::unique_ptr<StepPart> {
                        return std::make_unique<PathLength>();
                      },
                      .columns = kColumns,
                      .series = kSeries,
                      .series_values = path_length_mean});
  return true;
}();
} // namespace

} // namespace smpm::toy
