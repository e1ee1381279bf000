// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The notes of an input (RunConfig::notes: the earlier names it used, accepted in this release
// only), one line each on standard error.

#include <sparsempm/input.hpp>

#include <cstdio>

namespace smpm::app {

inline void print_notes(const RunConfig& cfg) {
  for (const std::string& note : cfg.notes)
    std::fprintf(stderr, "smpm: note: %s\n", note.c_str());
}

} // namespace smpm::app
