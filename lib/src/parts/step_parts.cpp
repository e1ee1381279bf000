// SPDX-License-Identifier: BSD-3-Clause
#include "parts.hpp"

namespace smpm {

std::vector<std::unique_ptr<StepPart>> step_parts(const StepOptions& options) {
  std::vector<std::unique_ptr<StepPart>> list;
  for (const parts::Entry* entry : parts::kList)
    if (std::unique_ptr<StepPart> part = entry->make(options))
      list.push_back(std::move(part));
  return list;
}

const std::vector<ParticleColumn>& particle_columns() {
  static const std::vector<ParticleColumn> columns = [] {
    std::vector<ParticleColumn> all;
    for (const parts::Entry* entry : parts::kList)
      all.insert(all.end(), entry->columns.begin(), entry->columns.end());
    return all;
  }();
  return columns;
}

} // namespace smpm
