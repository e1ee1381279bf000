#pragma once
// smpm stability and smpm spectrum: the stability study of FMPM 2026 §3.3 (Fig. 12).

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace smpm::app {

struct StabilityArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40, 80};
  std::vector<std::string> blends{"1:0.8", "2:0.8"}; ///< m:α ("none": no rows)
  std::vector<std::string> periodic{"2"};            ///< C_X values ("none": no rows)
  std::string method = "spectral";                   ///< spectral | simulation | both
  int shifts = 4;                                    ///< lattice shifts per sweep
  std::string frames;                                ///< run file whose frames are swept too
  int frame_stride = 1;
  std::string output = "stability.csv";
  bool quiet = false;
  bool exact = true;                    ///< also the exact consistent-mass row
  double position_alpha = std::nan(""); ///< NaN: the input's (or each row's default)
  double max_energy_change = std::numeric_limits<double>::infinity(); ///< simulation criterion
};

struct SpectrumArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40, 80};
  std::vector<double> alphas{1.0, 0.9, 0.8};
  std::vector<int> every{1, 2}; ///< blend_every values m
  double courant = 0;           ///< > 0: also ρ(T(C)) of FMPM for each (k, α, m)
  std::string output = "spectrum.csv";
};

/// ρ(A), λ_min(m⁻¹m̃), cond(m̃) at t = 0, and the truncation error of FMPM(k) (and ρ(T(C)))
/// for every k, α, m: a table on stdout and a CSV (scalars as '# name = value' lines).
int spectrum_command(const SpectrumArgs& args);

/// Writes the table (CSV header scheme,k,alpha,blend_every,periodic_cx,position_alpha,
/// c_spectral,config_spectral,spectral_status,c_simulation,energy_change) and prints it.
/// Returns the exit status.
int stability_command(const StabilityArgs& args);

} // namespace smpm::app
