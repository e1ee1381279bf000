// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The options of smpm stability and smpm spectrum, shared with smpm-mpi's commands.

#include "stability_command.hpp"

#include <CLI/CLI.hpp>

namespace smpm::app {

/// Every option of `stability` (the earlier names are smpm's aliases).
inline void add_stability_options(CLI::App& stab, StabilityArgs& st) {
  stab.add_option("input", st.input, "input file (TOML)")->required();
  stab.add_option("--set", st.sets, "override an input entry")->allow_extra_args(false);
  stab.add_option("--order", st.orders, "FMPM orders k")->delimiter(',')->capture_default_str();
  stab.add_option("--blend-alpha", st.blend_alphas,
                  "blending fractions alpha of the blended rows (none: no blended rows)")
      ->delimiter(',')
      ->capture_default_str();
  stab.add_option("--blend-every", st.blend_every, "blend every m-th pass, for every alpha")
      ->delimiter(',')
      ->capture_default_str();
  stab.add_option("--periodic-cx", st.periodic_cx, "periodic FMPM budgets C_X (none: no rows)")
      ->delimiter(',')
      ->capture_default_str();
  stab.add_option("--polynomial", st.polynomials,
                  "rows of the other polynomials of the same k - 1 products, for every order k "
                  "> 1: chebyshev, least_squares, chebyshev_squared")
      ->delimiter(',');
  stab.add_option("--interval-low", st.interval_low,
                  "lambda_lo of their interval [lambda_lo, 1] (default: the input's "
                  "step.interval_low if positive, else min eig(m^-1 m~) at t = 0)");
  stab.add_option("--method", st.method, "spectral | simulation | both")->capture_default_str();
  stab.add_option("--shifts", st.shifts, "lattice shifts in the spectral sweep")
      ->capture_default_str();
  stab.add_option("--frames", st.frames, "also sweep the frames of this run file");
  stab.add_option("--frame-stride", st.frame_stride, "use every n-th frame")->capture_default_str();
  stab.add_option("-o,--output", st.output, "CSV table")->capture_default_str();
  stab.add_flag("-q,--quiet", st.quiet, "no progress lines");
  stab.add_flag("--no-exact", st.no_exact, "leave out the exact consistent-mass row");
  stab.add_option("--position-alpha", st.position_alpha,
                  "alpha of the position update (FMPM 2026 Eqs. 8-9) for every row (default: "
                  "the input's, else 1 for FLIP and 1/2 for the others)");
  stab.add_option("--max-energy-change", st.max_energy_change,
                  "simulation: also fail a run whose total energy changes by more than this "
                  "fraction (default: no limit)");
}

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
