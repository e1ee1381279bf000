// SPDX-License-Identifier: BSD-3-Clause
#include "parts.hpp"

namespace smpm {

std::vector<std::unique_ptr<StepPart>> step_parts(const StepOptions& options) {
  std::vector<std::unique_ptr<StepPart>> list;
  for (const parts::Factory make : parts::kList)
    if (std::unique_ptr<StepPart> part = make(options))
      list.push_back(std::move(part));
  return list;
}

} // namespace smpm
