// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// smpm info: what a run file holds (its description, energies and every object of its last
// frame, walked against the layout of output.hpp), or with --layout the layout itself, or with
// --keys the keys of the input files (input.hpp's input_keys, as TOML).

#include <string>

namespace smpm::app {

/// Prints the run file `path`, or the layout of every run file when `layout`, or every key of
/// the input files when `keys`. Returns the exit status.
int info_command(const std::string& path, bool layout, bool keys = false);

} // namespace smpm::app
