#pragma once
// smpm stability and smpm spectrum: the stability study of FMPM 2026 §3.3 (Fig. 12).

#include <string>
#include <vector>

namespace smpm::app {

struct StabilityArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40, 80};
  std::vector<std::string> blends{"1:0.8", "2:0.8"}; ///< m:α
  std::vector<double> periodic{2.0};                 ///< C_X values
  std::string method = "spectral";                   ///< spectral | simulation | both
  int shifts = 4;                                    ///< lattice shifts per sweep
  std::string frames;                                ///< run file whose frames are swept too
  int frame_stride = 1;
  std::string output = "stability.csv";
  bool quiet = false;
};

/// Writes the table (CSV header scheme,k,alpha,blend_every,periodic_cx,c_spectral,
/// config_spectral,c_simulation,energy_change) and prints it. Returns the exit status.
int stability_command(const StabilityArgs& args);

} // namespace smpm::app
