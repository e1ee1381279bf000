// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// smpm transport-stability: the critical Fourier number of heat transport against the FMPM
// order (transport_stability.hpp).

#include <string>
#include <vector>

namespace smpm::app {

struct TransportStabilityArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40}; ///< FMPM orders k of the transport (--order)
  int shifts = 4;                              ///< lattice shifts (--shifts)
  bool no_exact = false;                       ///< leave out the exact capacity row
  std::string output = "transport_stability.csv";
};

/// The columns of the table: the results under their names in C++ and Python
/// (CriticalFourier::critical_fourier, rho_T and evaluations, the configuration of the smallest
/// F*; the stable_from of the configuration whose small F are the worst and the words of
/// small_courant_text with that configuration; python/sparsempm/tables.py reads the earlier
/// f_spectral and config_spectral too).
inline constexpr const char* kTransportStabilityColumns =
    "transport,order,critical_fourier,rho_T,configuration,evaluations,stable_from,small_fourier";

/// F* = max{F : ρ(𝒯(F)) ≤ 1 + 10⁻⁶} (critical_fourier, the smallest over the lattice shifts) of
/// the lumped transport, FMPM(k) on c̃ for each order and the exact solve: a table on stdout and
/// a CSV (kTransportStabilityColumns). Returns the exit status.
int transport_stability_command(const TransportStabilityArgs& args);

} // namespace smpm::app
