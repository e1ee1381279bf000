// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// smpm stability and smpm spectrum: the stability study of FMPM 2026 §3.3 (Fig. 12).

#include <sparsempm/fmpm.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace smpm::app {

struct StabilityArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40, 80}; ///< FMPM orders k (--order)
  /// Blending fractions α (--blend-alpha; "none": no blended rows), each with every blend_every.
  std::vector<std::string> blend_alphas{"0.8"};
  std::vector<int> blend_every{1, 2};        ///< blending periods m (--blend-every)
  std::vector<std::string> blends;           ///< m:α pairs (--blend, the earlier form)
  std::vector<std::string> periodic_cx{"2"}; ///< C_X values (--periodic-cx; "none": no rows)
  /// The other members of the polynomial family (--polynomial: chebyshev, least_squares), a row
  /// for each with every --order k > 1.
  std::vector<std::string> polynomials;
  /// λ_lo of their interval (--interval-low); NaN: the input's step.interval_low when it is
  /// positive, else λ_min(m⁻¹m̃) of the configuration at t = 0.
  double interval_low = std::nan("");
  std::string method = "spectral"; ///< spectral | simulation | both
  int shifts = 4;                  ///< lattice shifts per sweep
  std::string frames;              ///< run file whose frames are swept too
  int frame_stride = 1;
  std::string output = "stability.csv";
  bool quiet = false;
  bool no_exact = false;                ///< leave out the exact consistent-mass row
  double position_alpha = std::nan(""); ///< --position-alpha ...
  bool position_alpha_given = false;    ///< ... when given (else the input's, or each row's)
  double max_energy_change = std::numeric_limits<double>::infinity(); ///< simulation criterion
};

struct SpectrumArgs {
  std::string input;
  std::vector<std::string> sets;
  std::vector<int> orders{1, 2, 4, 8, 16, 40, 80}; ///< --order
  std::vector<double> blend_alphas{1.0, 0.9, 0.8}; ///< --blend-alpha
  std::vector<int> blend_every{1, 2};              ///< --blend-every
  double courant = 0; ///< > 0: also ρ(T(C)) of FMPM for each (k, α, m)
  std::string output = "spectrum.csv";
};

/// The columns of the stability table: the results under their names in C++ and Python
/// (CriticalCourant::critical_courant, ConfigurationSweep::configuration, stable_from of
/// ConfigurationSweep::lowest, small_courant (small_courant_text of it, with
/// lowest_configuration when an unstable C lies below, and ": no C stable on every
/// configuration" when stable_from exceeds the smallest C*), SimulationCourant::simulation_courant
/// and energy_change; python/sparsempm/tables.py reads the earlier c_spectral, config_spectral and
/// c_simulation too).
inline constexpr const char* kStabilityColumns =
    "velocity,order,blend_alpha,blend_every,periodic_cx,position_alpha,critical_courant,"
    "configuration,spectral_status,stable_from,small_courant,simulation_courant,energy_change,"
    "interval_low";
/// The columns of the spectrum table: every row the same CSV (no comment lines; csv readers and
/// numpy.genfromtxt take it as it is), the configuration's ρ(A), λ_min(m⁻¹m̃), cond(m̃) and
/// active nodes repeated on each.
inline constexpr const char* kSpectrumColumns =
    "order,blend_alpha,blend_every,truncation_error,courant,rho_T,rho_A,min_eig_minv_mt,cond_mt,"
    "active_nodes";

/// ρ(A), λ_min(m⁻¹m̃), cond(m̃) at t = 0, and the truncation error of FMPM(k) (and ρ(T(C)))
/// for every k, α, m: a table on stdout and a CSV (kSpectrumColumns).
int spectrum_command(const SpectrumArgs& args);
/// Throws InputError for spectrum arguments out of their ranges, a table path that would
/// overwrite an input, or an input that is not a readable regular file.
void validate(const SpectrumArgs& args);
/// The CSV of `smpm spectrum` (kSpectrumColumns) for the spectrum `ms` and, for every (k, α, m)
/// of `args`, truncation(FMPM options) and, with --courant, rho(FMPM options); with `print` the
/// same table on stdout. Shared by smpm spectrum and smpm-mpi spectrum.
std::string spectrum_table(const SpectrumArgs& args, const MassSpectrum& ms,
                           const std::function<double(const FmpmOptions&)>& truncation,
                           const std::function<double(const FmpmOptions&)>& rho, bool print);

/// Where stability_command computes the spectral C*: on every core of this process (the
/// default: critical_courant, a task per series and configuration), or across MPI ranks
/// (smpm-mpi stability: `search` is the distributed critical_courant, every rank running every
/// search in the same order; only the root prints and writes).
struct StabilityEngine {
  CriticalSearch search; ///< null: critical_courant on every core
  bool root = true;      ///< this process prints progress and the table and writes the file
};

/// Writes the table (CSV with kStabilityColumns) and prints it. Returns the exit status.
int stability_command(const StabilityArgs& args, const StabilityEngine& engine = {});
/// Throws InputError for stability arguments out of their ranges, a table path that would
/// overwrite an input, or an input that is not a readable regular file.
void validate(const StabilityArgs& args);

} // namespace smpm::app
