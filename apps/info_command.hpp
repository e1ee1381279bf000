// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// smpm info: what a run file holds (its description, energies and every object of its last
// frame, walked against the layout of output.hpp), or with --layout the layout itself.

#include <string>

namespace smpm::app {

/// Prints the run file `path`, or the layout of every run file when `layout`. Returns the exit
/// status.
int info_command(const std::string& path, bool layout);

} // namespace smpm::app
