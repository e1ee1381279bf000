// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The parts of the step (step_part.hpp), one file each; step_parts lists them in this order.

#include "sparsempm/particle_columns.hpp"
#include "sparsempm/step_part.hpp"

#include <span>

namespace smpm::parts {

using Entry = StepPartEntry;

extern const Entry shocks;            // shocks.cpp
extern const Entry heat;              // heat.cpp
extern const Entry gradient_transfer; // gradient_transfer.cpp
extern const Entry plasticity;        // plasticity.cpp
extern const Entry loads;             // loads.cpp
extern const Entry rigid_bodies;      // rigid_bodies.cpp
extern const Entry contact;           // contact.cpp

/// The list, in the order the hooks run (and the columns stand in frames).
inline const Entry* const kList[] = {
    &shocks, &heat, &gradient_transfer, &plasticity, &loads, &rigid_bodies, &contact};

} // namespace smpm::parts
