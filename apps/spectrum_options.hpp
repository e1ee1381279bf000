// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The options of smpm spectrum, shared with smpm-mpi spectrum.

#include "stability_command.hpp"

#include <CLI/CLI.hpp>

namespace smpm::app {

/// The input, --set, --order, --blend-alpha, --blend-every, --courant and -o of `spectrum`.
inline void add_spectrum_options(CLI::App& spec, SpectrumArgs& sp) {
  spec.add_option("input", sp.input, "input file (TOML)")->required();
  spec.add_option("--set", sp.sets, "override an input entry")->allow_extra_args(false);
  spec.add_option("--order", sp.orders, "FMPM orders k")->delimiter(',')->capture_default_str();
  spec.add_option("--blend-alpha", sp.blend_alphas, "blending fractions alpha")
      ->delimiter(',')
      ->capture_default_str();
  spec.add_option("--blend-every", sp.blend_every, "blend every m-th pass")
      ->delimiter(',')
      ->capture_default_str();
  spec.add_option("--courant", sp.courant, "also rho(T(C)) at this Courant number");
  spec.add_option("-o,--output", sp.output, "CSV table")->capture_default_str();
}

} // namespace smpm::app
