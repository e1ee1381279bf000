// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The toy part of toy_part.cpp as its tests see it: its column and its series' values.

#include <sparsempm/step_part.hpp>

#include <span>

namespace smpm::toy {

/// The part's one column: each particle's path length since t = 0 (path_length).
extern const ParticleColumn& path_length;
/// Its series' values as a run computes them: path_length_mean = Σ M_p s_p / Σ M_p.
void path_length_mean(const SeriesInput& in, std::span<double> out);

} // namespace smpm::toy
