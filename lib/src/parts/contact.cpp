// SPDX-License-Identifier: BSD-3-Clause
// Multimaterial contact as a part of the step (contact.hpp): the step's contact nodes, found
// by its preparation, go to the stages, and the run tallies the work of Coulomb friction.
#include "parts.hpp"

namespace smpm::parts {
namespace {

class Contact final : public StepPart {
public:
  void begin(StepStart& s) override {
    on_ = s.prep.has_contact();
    if (on_)
      s.context.contact_nodes = &s.prep.contact;
  }
  void end(StepEnd& e) override {
    if (on_)
      e.state.friction_work += e.prep.contact.friction_work;
  }

  std::string not_linearised(const Model& model) const override {
    if (model.contact.fields() > 1)
      return "the linearised step needs one velocity field: contact detection switches with the "
             "state ([[contact]]), which is not a linear map";
    return {};
  }
  std::string not_distributed(const Model& model) const override {
    return model.contact.fields() > 1 ? "contact ([[contact]])" : "";
  }

private:
  bool on_ = false;
};

std::unique_ptr<StepPart> make(const StepOptions&) {
  return std::make_unique<Contact>();
}

// The run's tally of Coulomb friction's work (StepperState::friction_work), 0 without contact: a
// series of every run.
constexpr PartSeries kSeries[] = {{"friction", "work of Coulomb friction since t = 0", ""}};
void series_values(const SeriesInput& in, std::span<double> out) {
  out[0] = in.state.friction_work;
}
} // namespace

const Entry contact{make, {}, kSeries, series_values};

} // namespace smpm::parts
