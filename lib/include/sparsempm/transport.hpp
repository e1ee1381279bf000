// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file transport.hpp
/// Heat transport by MPM with the capacity matrices in the place of the mass matrices
/// (FMPM 2026 §3.5; Nairn 2024, CMAME 420:116757, its Ref. [3]). One temperature per grid node,
/// shared by every material (perfect thermal contact; NairnMPM's single temperature field):
///
///     τ = Sᵀ (𝗖 T_p)                  nodal heat content, 𝗖 = diag(M_p C_V,p)   (p = Sᵀ M V)
///     c = Sᵀ 𝗖 1                      lumped capacity                          (m = Sᵀ M)
///     c̃ = Sᵀ 𝗖 S                      consistent (full) capacity               (m̃ = Sᵀ M S)
///     K = Σ_b G_bᵀ diag(V_p κ_p) G_b   conductivity (isotropic κ)
///     q = −K T + Sᵀ (M_p r_p) + q_c    heat flow: conduction, particle sources, contact heat
///     τ⁺ = τ + q Δt,   θ⁺(k) = c̃_k⁻¹ τ⁺  (FMPM(k) on c̃: fmpm_loop with c⁻¹ and c̃)
///
/// An anisotropic conductivity κ_ab would enter as K = Σ_a Σ_b G_aᵀ diag(V_p κ_ab,p) G_b, a flux
/// −κ ∇T with off-diagonal terms; the library takes isotropic κ. In multimaterial mode the columns
/// of S are blocks of velocity fields (operators.hpp): node i of field α is column α n_g + i, and
/// transport folds them onto grid node i (every particle reaches its own field's block only, so
/// the folded c̃ = Σ_α c̃^α).

#include "sparsempm/material.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/particles.hpp"

#include <string>
#include <string_view>

namespace smpm {

/// How the particles' temperatures follow the grid (`[step] transport`).
enum class TransportUpdate {
  Off,    ///< no temperature: isothermal mechanics
  Lumped, ///< T_p += Δt S c⁻¹ q (FMPM 2026 Eq. 8 with T for V): FLIP with the lumped capacity
  FMPM, ///< T_p = S θ⁺(k), θ⁺(k) = c̃_k⁻¹ τ⁺ by the FMPM loop on c̃ (Eq. 9 with T for V);
        ///< FMPM(1) is PIC with the lumped capacity
  Exact ///< T_p = S c̃⁻¹ τ⁺: the consistent-capacity solve (CHOLMOD)
};
/// Name used in input files: off | lumped | FMPM | exact.
std::string_view to_string(TransportUpdate u);
/// The transport update named `name`; throws InputError naming the valid choices.
TransportUpdate transport_update_from_string(std::string_view name);

/// A bound on FMPM(k) transport (TransportOptions::limiter). c̃_k⁻¹ has negative entries next to
/// its diagonal for k ≥ 2 (c̃₂⁻¹_ij = −c̃_ij / (c_i c_j)), so heat added at one node takes heat
/// from its neighbours and a positive source can cool particles below every temperature of the
/// step before it; the lumped update cannot.
enum class TransportLimiter {
  None, ///< FMPM(k) as the loop gives it
  /// Flux-corrected transport (Zalesak 1979, J. Comput. Phys. 31:335; Kuzmin & Turek 2002): the
  /// correction of FMPM(k) over FMPM(1), c (θ_k − θ_1) = Σ_j f_ij with the antisymmetric fluxes
  /// f_ij = c̃_ij (y_i − y_j), y = θ_{k−1}, limited edge by edge (θ_i = θ_1,i + c_i⁻¹ Σ_j α_ij
  /// f_ij, α_ij = α_ji ∈ [0, 1]) so that each θ_i stays between the least and the largest of θ_1
  /// on its neighbours and the temperatures of its particles. Heat is conserved (α symmetric);
  /// where no bound binds, θ is FMPM(k)'s to round-off.
  FCT
};
/// Name used in input files: none | fct.
std::string_view to_string(TransportLimiter l);
/// The limiter named `name`; throws InputError naming the valid choices.
TransportLimiter transport_limiter_from_string(std::string_view name);

/// Why temperature conditions cannot be held with shape functions `shape`: empty for linear hats,
/// uGIMP and CPDI, whose nodal values interpolate, so that a held node holds the temperature at
/// its plane; the reason for the quadratic B-splines (bspline2, b2cpdi), whose nodal values are
/// control points, so that the field at a held plane is not the held value and the error next
/// to it does not converge (measured on a bar with held ends, docs/studies/heat.md: the lumped
/// update's grows as the cells shrink, FMPM(k)'s and the exact solve's fall at first order only;
/// with insulated ends every shape converges at second order with FMPM(k) and the exact solve).
std::string held_temperature_refusal(Shape shape);

/// The options of heat transport in a step (part of StepOptions).
struct TransportOptions {
  TransportUpdate update = TransportUpdate::Off; ///< off: isothermal
  /// k of FMPM(k) on c̃ (TransportUpdate::FMPM); 0: the mechanics' order StepOptions::fmpm.order.
  /// The loop takes the mechanics' blending (blend_alpha, blend_every) and BC method.
  int order = 0;
  /// A bound on FMPM(k) transport (TransportUpdate::FMPM without blending): none (the default)
  /// or FCT.
  TransportLimiter limiter = TransportLimiter::None;
};

/// The particle and node data of heat transport in one step, prepared from the step's
/// operators (prepare_transport).
struct TransportOperators {
  Eigen::VectorXd capacity;    ///< N: M_p C_V,p, the heat capacity of each particle (𝗖)
  Eigen::VectorXd conductance; ///< N: V_p κ_p, current volume J_p V_p⁽⁰⁾ times conductivity
  Eigen::VectorXd source;      ///< N: M_p r_p, the particles' heat sources (power); empty: none
  /// The transport nodes: the n_g nodes of the step's grid with the lumped capacity in the place
  /// of the lumped mass, nodes.m = c, nodes.m_inv = 1/c on active nodes (c_i > tolerance · max c;
  /// prepare_transport), nodes.active and nodes.grid, so that the functions of the mass inverse
  /// (updated_velocity, fmpm_velocity, a MassSolver) serve transport unchanged. nodes.S has no
  /// particle rows: the particles reach these nodes through the step's S and G (folded).
  Operators nodes;
};

/// Prepares `t` for the step of operators `ops` (assembled for the particles P): 𝗖 and V κ from
/// each particle's material (Material::heat_capacity, conductivity; V_p = det F_p V_p⁽⁰⁾), the
/// sources M_p r_p (Particles::heat_source), and c = Sᵀ 𝗖 1 on the n_g nodes of ops.grid, each
/// node's sum in particle order. The active nodes are those with c_i > tolerance · max c: with the
/// default 0 every node a particle reaches, so that T_p = S θ loses no share of any particle's heat
/// (a nodal temperature θ_i is an average of particle temperatures, bounded however small c_i, and
/// the rows of A_c = I − c⁻¹ c̃ stay bounded); the exact solve takes kMassTolerance, which keeps
/// c̃ positive definite in floating point, as for m̃. Throws InputError naming a material
/// without a positive heat capacity.
void prepare_transport(const Operators& ops, const Particles& P,
                       const std::vector<Material>& materials, TransportOperators& t,
                       double tolerance = 0);

/// Gives every particle its material's reference temperature (Material::reference_temperature).
/// Throws InputError naming a material whose reference temperature is not positive and finite.
void set_reference_temperatures(Particles& P, const std::vector<Material>& materials);

/// τ = Sᵀ (𝗖 T), n_g × 1: the nodal heat content of particle temperatures T (N), each node's sum
/// in particle order (FMPM 2026 task 1 with T for V).
void map_heat(const Operators& ops, const TransportOperators& t, const ConstVectorRef& T,
              Field& tau);
/// ∇T_p = Σ_i G_pi T_i, N × d, from nodal temperatures T (n_g × 1).
void temperature_gradient(const Operators& ops, const Field& T, Field& gradient);
/// q = −Σ_b G_bᵀ (V κ ∂_b T) + Sᵀ (M r), n_g × 1: the conduction flow −K T from the particle
/// gradients (N × d; temperature_gradient) and the particles' sources.
void heat_flow(const Operators& ops, const TransportOperators& t, const Field& gradient, Field& q);
/// FLIP (FMPM 2026 Eq. 8 with T for V): T_p += Δt Σ_i S_pi Ṫ_i, Ṫ = c⁻¹ q (n_g × 1). Throws
/// NumericalError naming the first particle whose temperature is not positive and finite
/// (`absolute`), or not finite.
void update_temperature_flip(const Operators& ops, const Field& rate, double dt,
                             Eigen::Ref<Eigen::VectorXd> T, bool absolute = true);
/// PIC/FMPM (FMPM 2026 Eq. 9 with T for V): T_p = Σ_i S_pi θ_i (θ: n_g × 1). Throws
/// NumericalError naming the first particle whose temperature is not positive and finite
/// (`absolute`), or not finite.
void update_temperature_grid(const Operators& ops, const Field& theta,
                             Eigen::Ref<Eigen::VectorXd> T, bool absolute = true);

/// c̃ = Sᵀ diag(𝗖) S on the n_g transport nodes (block columns folded), written into the stencil
/// storage `ct` as assemble_consistent_mass writes m̃ (the same pattern in single material mode);
/// `capacity` holds 𝗖 (N). Rows sum to c.
void assemble_consistent_capacity(const Operators& ops, const Eigen::VectorXd& capacity,
                                  ConsistentMass& ct);
/// c̃ of the step as an n_g × n_g matrix (exact zeros pruned).
SparseMatrix consistent_capacity(const Operators& ops, const TransportOperators& t);
/// K = Σ_b G_bᵀ diag(V κ) G_b, n_g × n_g, symmetric positive semidefinite, K 1 = 0.
SparseMatrix conductivity_matrix(const Operators& ops, const TransportOperators& t);
/// An N × n matrix of the step (S or a G_b) with its block columns folded onto the n_g grid
/// nodes (column α n_g + i → i): the operator transport applies. The matrix itself with one
/// field.
SparseMatrix folded_columns(const Operators& ops, const SparseRowMatrix& A);

/// The diffusion time of a cell, Δx_min² / D_max, with D = κ/(ρ C_V) the largest diffusivity of
/// the particles' materials: a time step is F Δx_min² / D_max for the Fourier number F
/// (critical_fourier of transport_stability.hpp finds its explicit limit); +∞ when no material
/// conducts.
double diffusion_time(const Grid& grid, const std::vector<Material>& materials,
                      const Particles& particles);
/// The Fourier number of runs that do not choose one ([time] fourier, AdvanceOptions::fourier):
/// 0.1 in every dimension, below the smallest critical Fourier number critical_fourier finds for
/// the lumped, FMPM(k) and exact transport over lattice shifts of 2 particles per cell per axis:
/// 0.229 (2D, linear shape functions, the exact capacity solve with particles near the nodes);
/// uGIMP 0.42, CPDI 0.50 (docs/studies/heat.md). The grid forms conduct with the lumped nodal
/// temperature c⁻¹ τ, whose limit λ_max(c⁻¹ K) = 4D/Δx² gives 1/2 on regular lattices, not the
/// consistent capacity's 1/6.
double default_fourier(int dim);

} // namespace smpm
