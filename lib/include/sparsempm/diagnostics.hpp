// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file diagnostics.hpp
/// Energies and momentum of the particle state, and the Courant relation of the time step
/// (FMPM 2026 §3.3), whose particle speed is the energies' max_speed.

#include "sparsempm/model.hpp"

#include <Eigen/Core>
#include <vector>

namespace smpm {

/// The energies, momentum and largest speed of the particles (energies()): the quantities the
/// failure test, the energy series of a run and the Courant relation read.
struct Energies {
  double kinetic = 0;                                 ///< ½ Σ_p M_p |V_p|²
  double strain = 0;                                  ///< Σ_p V_p^(0) W(F_p)
  double total = 0;                                   ///< kinetic + strain
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(); ///< Σ_p M_p V_p (d entries used)
  double max_speed = 0; ///< max_p |V_p|, the particle speed of the Courant relation
};

/// The energies, momentum and largest speed of the particles, in one pass over V and one over
/// the strain energy (strain_energy, with the densities W(F_p) of `density` when given).
Energies energies(const Model& model, const Eigen::VectorXd* density = nullptr);
/// max_p |V_p|: Energies::max_speed alone (the same pass over V).
double max_particle_speed(const Particles& particles);

/// max(c_wave, max_p |V_p|): the speed of the Courant relation (FMPM 2026 §3.3).
double signal_speed(const Model& model);
/// Δt = C Δx_min / speed (FMPM 2026 §3.3) for a known signal speed. Throws InputError for C ≤ 0
/// or a speed that is not positive (no wave speed and no particle velocity).
double stable_time_step(const Model& model, double courant, double speed);
/// Δt = C Δx_min / max(c_wave, max_p |V_p|): the time step of Courant number C, the one
/// relation between C and Δt of runs and analyses alike.
double stable_time_step(const Model& model, double courant);
/// C = Δt max(c_wave, max_p |V_p|) / Δx_min: the Courant number of a time step.
double courant_of(const Model& model, double dt);

/// The thermodynamic sums of a model whose particles have temperatures (heat transport), from
/// the free energy of each particle Ψ_p = Ω_p Ψ_e(F_p, T_p) + M_p C_V ((T_p − T_ref) − T_p ln(T_p /
/// T_ref)) (thermoelastic_stress; Ψ_e = W without thermal expansion): entropy S_p = −∂Ψ/∂T =
/// M_p C_V ln(T_p/T_ref) + Ω_p c_p and internal energy U_p = Ψ_p + T_p S_p = Ω_p W_p +
/// M_p C_V (T_p − T_ref) + T_p Ω_p c_p (c = thermal_coupling, 0 without expansion). A
/// Mie–Grüneisen particle's internal energy is its M U (which takes the heat it receives) and its
/// entropy that of the Grüneisen solid, M C_V (ln(T/T_ref) + γ₀ (J − 1)). For an adiabatic body
/// U + K is conserved and ΔA returns to 0 between equilibrium states (FMPM 2026 Figs. 9, 10).
struct ThermalSums {
  double temperature_min = 0; ///< min_p T_p
  double temperature_max = 0; ///< max_p T_p
  /// Σ M_p C_V T_p / Σ M_p C_V: the capacity-weighted mean, which conduction conserves
  double temperature_mean = 0;
  double heat = 0; ///< Q = Σ M_p C_V (T_p − T_ref), the thermal energy
  /// U = Σ U_p = W + Q + Σ T_p Ω_p c_p, W the strain energy (Energies::strain); the Q and T Ω c
  /// of Mie–Grüneisen particles left out (their U, in W, holds their heat)
  double internal = 0;
  double entropy = 0;   ///< S = Σ S_p = Σ (M_p C_V ln(T_p/T_ref) + Ω_p c_p)
  double helmholtz = 0; ///< A = U − Σ T_p S_p
};
/// The sums of ThermalSums over the particles (in the fixed order of the library's reductions),
/// `strain` the strain energy W of the same state (Energies::strain). Throws UsageError unless
/// every particle has a temperature.
ThermalSums thermal_sums(const Model& model, double strain);

/// Mass, momentum and centre of mass of each material's particles (one body per material in
/// multimaterial runs), one pass: for material k, out[k(1 + 2d) + 0] = Σ M_p,
/// out[… + 1 + a] = Σ M_p V_pa, out[… + 1 + d + a] = Σ M_p X_pa / Σ M_p (NaN without
/// particles). `out` is resized to n_materials (1 + 2d).
void material_sums(const Model& model, std::vector<double>& out);

/// √(Σ_p |V_p − V0_p|² / N), the RMS change of the particle velocities from V0 (N × d; the
/// velocity error of FMPM 2026 §3.1 when V0 is the exact field), in the fixed order of the
/// library's reductions; 0 without particles.
double velocity_change(const Particles& particles, const Field& V0);

} // namespace smpm
