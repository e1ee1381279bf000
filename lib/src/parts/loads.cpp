// SPDX-License-Identifier: BSD-3-Clause
// Loads as a part of the step (loads.hpp): the external forces of Model::loads at the step's
// start, on its configuration, which the force stage adds.
#include "parts.hpp"

#include "sparsempm/loads.hpp"

namespace smpm::parts {
namespace {

class Loads final : public StepPart {
public:
  explicit Loads(const StepOptions& options)
      : domains_(options.shape == Shape::CPDI || options.shape == Shape::B2CPDI) {}
  void begin(StepStart& s) override {
    if (s.model.loads.empty())
      return;
    external_forces(s.model.loads, s.model.particles, s.model.time, domains_, forces_);
    s.context.external = &forces_;
  }

private:
  bool domains_; // CPDI domains: the loaded faces are those of the deformed domains
  ExternalForces forces_;
};

std::unique_ptr<StepPart> make(const StepOptions& options) {
  return std::make_unique<Loads>(options);
}

} // namespace

const Entry loads{make, {}};

} // namespace smpm::parts
