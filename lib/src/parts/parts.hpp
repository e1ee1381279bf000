// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The parts of the step (step_part.hpp), one file each; step_parts lists them in this order.

#include "sparsempm/step_part.hpp"

namespace smpm::parts {

/// Each returns its part for a Stepper with `options`, or null when the options leave its
/// capability off.
using Factory = std::unique_ptr<StepPart> (*)(const StepOptions& options);

std::unique_ptr<StepPart> gradient_transfer(const StepOptions& options); // gradient_transfer.cpp
std::unique_ptr<StepPart> heat(const StepOptions& options);              // heat.cpp
std::unique_ptr<StepPart> shocks(const StepOptions& options);            // shocks.cpp
std::unique_ptr<StepPart> plasticity(const StepOptions& options);        // plasticity.cpp
std::unique_ptr<StepPart> loads(const StepOptions& options);             // loads.cpp
std::unique_ptr<StepPart> rigid_bodies(const StepOptions& options);      // rigid_bodies.cpp
std::unique_ptr<StepPart> contact(const StepOptions& options);           // contact.cpp

/// The list, in the order the hooks run.
inline constexpr Factory kList[] = {gradient_transfer, heat,   shocks, plasticity, loads,
                                    rigid_bodies,      contact};

} // namespace smpm::parts
