// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file problems.hpp
/// Set-ups of the published validation problems, shared by tests and examples.

#include "sparsempm/model.hpp"

namespace smpm {

/// A 1D bar fixed at x = 0 and free at x = L, started undeformed in its first mode,
/// v(x, 0) = v₀ sin(πx / 2L) (Buzzi Eqs. 34–37; Yang & Sulsky's free-vibrating bar of
/// FMPM 2026 §3.3). Linear elastic, σ = E (F − 1).
struct BarSetup {
  double length = 40;   ///< L
  double cell = 1;      ///< cell size
  int ppc = 2;          ///< particles per cell
  double density = 0.5; ///< ρ
  double youngs = 2;    ///< E
  double v0 = 0.16;     ///< amplitude of the initial velocity
  int cells_left = 2;   ///< grid cells left of x = 0
  int cells_right = 6;  ///< grid cells right of x = L
};

/// The bar model: grid, particles, one linear material and the fixed node at x = 0.
Model vibrating_bar(const BarSetup& setup);
/// First-mode period 4L / √(E/ρ) (80 for the defaults).
double bar_period(const BarSetup& setup);

} // namespace smpm
