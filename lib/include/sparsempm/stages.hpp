// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file stages.hpp
/// The kernels of an explicit MPM step: each product of the step (P2G, internal force, the FLIP
/// and PIC particle updates, the velocity gradient and the F update) as one pass over the CSR
/// arrays of S and the G_b, over particle fields passed as Eigen::Ref. A scheme (USL, USF, ...)
/// is the order in which scheme.cpp calls them. Node fields are n × d (one row per node),
/// particle fields N × d or N × d² (one row per particle, tensors row-major).
///
/// Every kernel runs on threads(): the particle kernels one particle per iteration, the node
/// sums (P2G, internal force) each thread over a range of nodes, adding the terms of the
/// particles' rows in particle order, so the results are the same bit for bit for any number
/// of threads (threads.hpp).
///
/// The kernels see the particles through ParticleOperators, the CSR rows of a contiguous block
/// of particles: all of them, or the block of one material (ParticleOperators::block), with
/// the matching rows of the fields (`P.V.middleRows(first, count)`).

#include "sparsempm/loads.hpp"
#include "sparsempm/operators.hpp"

#include <Eigen/Core>
#include <array>
#include <string_view>
#include <vector>

namespace smpm {

/// The particle rows of one step's operators: S and the G_b (which share S's pattern) and the
/// masses M of particles [first, first + rows), as raw CSR arrays. A view: the Operators it
/// was taken from must outlive it and keep its pattern.
struct ParticleOperators {
  int dim = 1;                      ///< d: the G_b used (b < d), the columns of node fields
  Index rows = 0;                   ///< particles in the block
  Index nodes = 0;                  ///< n, the columns
  const int* outer = nullptr;       ///< rows + 1 offsets into inner, S and G (absolute)
  const int* inner = nullptr;       ///< node of each entry
  const int* span = nullptr;        ///< 2 rows: each row's first and last node (ColumnIndex)
  const double* S = nullptr;        ///< S_pi of each entry
  std::array<const double*, 3> G{}; ///< ∂S_pi/∂x_b of each entry (b < d)
  const double* M = nullptr;        ///< rows particle masses
  /// S's pattern by columns (Operators::columns): the entries of each node (which balance the
  /// node ranges of the node sums) and, for several velocity fields, each node's entries and
  /// particles in particle order (null otherwise).
  const int* col_outer = nullptr; ///< n + 1 offsets into col_entry and col_row
  const int* col_entry = nullptr; ///< positions in inner, S and G, or null
  const int* col_row = nullptr;   ///< particle of each position (absolute row), or null
  Index first = 0;                ///< absolute row of the block's first particle

  /// The rows [first, first + count) of this block (one material's particles).
  ParticleOperators block(Index first, Index count) const;
};

/// The view of all particle rows of `ops`.
ParticleOperators particle_operators(const Operators& ops);

/// The velocity-gradient transfer's operator over S's pattern (Transfer::VelocityGradient;
/// Wallstedt & Guilkey 2007): for each entry S_pi the offset Δ_pi,b = x_ib − X_pb of its node
/// from the particle, one array per direction b < d, at the positions S was assembled at (the
/// step's start). P2G's affine term is Σ_b D_bᵀ M L_{·b} with D_b = S ∘ Δ_b.
struct AffineOffsets {
  std::array<std::vector<double>, 3> delta; ///< Δ_b over S's entries (ParticleOperators::S)
};
/// Δ_b of `op`'s entries from the particles' positions X and the positions x_i of the nodes of
/// `grid` (the step's grid; node i of a field block α n_g + i is grid node i).
void affine_offsets(const ParticleOperators& op, const Grid& grid, const ConstFieldRef& X,
                    AffineOffsets& offsets);
/// APIC's affine weights over S's pattern (Transfer::Apic; Jiang, Schroeder, Selle, Teran &
/// Stomakhin 2015, "The affine particle-in-cell method", ACM TOG 34(4):51): Ĝ_pi = D_p⁻¹ S_pi Δ_pi
/// with the inertia tensor D_p = Σ_i S_pi Δ_pi Δ_piᵀ, one array per direction b < d, so that
/// APIC's G2P C_p = B_p D_p⁻¹ = Σ_i v_i ⊗ Ĝ_pi is velocity_gradient with Ĝ in place of ∇S
/// (with_weights). For the linear hat, D_p is diagonal, (D_p)_bb = (X_pb − x_0b)(x_1b − X_pb),
/// singular on a node, and Ĝ = ∇S wherever it is not (the multilinear limit): with Shape::Linear
/// Ĝ is ∇S, and APIC is the velocity-gradient transfer.
struct ApicWeights {
  std::array<std::vector<double>, 3> g; ///< Ĝ_b over S's entries (ParticleOperators::S)
  /// The arrays Ĝ_b as assemble_affine_mass takes them (null beyond d).
  std::array<const double*, 3> pointers() const;
};
/// Ĝ of `op`'s entries from the step's offsets Δ (affine_offsets) and its shape (the operators
/// do not record it: Shape::Linear takes Ĝ = ∇S). Throws NumericalError naming the first
/// particle whose D_p is not positive definite (a pivot of its Cholesky factorisation at most
/// 10⁻¹² of D_p's largest diagonal entry, or not finite: with hats, a CPDI domain collapsed
/// onto a node line).
void apic_weights(const ParticleOperators& op, const AffineOffsets& offsets, Shape shape,
                  ApicWeights& weights);
/// The view of `op` with APIC's weights Ĝ in place of the G_b (the same pattern and masses).
ParticleOperators with_weights(const ParticleOperators& op, const ApicWeights& weights);
/// m̃_A of `ops` at the particles' positions X (N × d) of its assembly with `shape`:
/// affine_offsets, apic_weights and assemble_affine_mass, as the APIC transfer's part does each
/// step (for analysis: Python's Operators.apic_mass()).
void assemble_apic_mass(const Operators& ops, const ConstFieldRef& X, Shape shape,
                        ConsistentMass& mt);
/// P2G's term of an affine transfer: the offsets of the step and the particles' affine
/// velocities L (N × d², row-major: G v, or APIC's C_p), which P2G reads and the particle update
/// sets.
struct AffineMomentum {
  const AffineOffsets* offsets = nullptr; ///< Δ_b of the step's S
  const Field* L = nullptr;               ///< N × d² velocity gradients L_p
};

/// p = Sᵀ (M ∘ V), n × d  (FMPM 2026 task 1; Buzzi Eq. 26); with the velocity-gradient transfer's
/// term (`affine`, not null) p_i = Σ_p S_pi M_p (V_p + L_p Δ_pi) = Sᵀ M V + Σ_b D_bᵀ M L_{·b}
/// (Wallstedt & Guilkey 2007), each node's sum in particle order (the same bits for any number of
/// threads). An affine field V = V₀ + L x, L_p = L, then gives p_i = m_i (V₀ + L x_i).
void map_momentum(const ParticleOperators& op, const ConstFieldRef& V, Field& p,
                  const AffineMomentum* affine = nullptr);
/// g = Σ_b G_bᵀ V e_b, n × d: g_i = Σ_p G_pi V_p, the volume gradient of contact 2020 Eq. (11)
/// (in 2D with V_p the area times unit thickness), from the volumes V (one per particle).
void volume_gradient(const ParticleOperators& op, const ConstVectorRef& volume, Field& g);
/// f = −Σ_b G_bᵀ (Ω J σ_{·b}), n × d: the internal force from the Kirchhoff stress τ = Jσ and
/// the initial volumes Ω (FMPM 2026 task 2; Buzzi Eq. 15).
void internal_force(const ParticleOperators& op, const ConstVectorRef& volume0,
                    const ConstFieldRef& F, const ConstFieldRef& stress, Field& f);
/// f += m Bᵀ: the uniform body acceleration B (gravity), i.e. f += Sᵀ M B (Buzzi Eq. 14).
void add_gravity(const Eigen::VectorXd& m, const std::array<double, 3>& B, Field& f);
/// f += the loads of loads.hpp (FMPM 2026 task 2's external force): the body forces through S,
/// f_i += Σ_p S_pi F_p, and each traction corner's force through the hat functions of `grid`
/// (the step's grid) at the corner, over the nodes of its particle's row (renormalised to 1; S
/// itself when no node of the row has a hat weight).
void add_external_forces(const ParticleOperators& op, const Grid& grid, const ExternalForces& loads,
                         Field& f);
/// v = m⁻¹ x, with m_inv = 1/m_i on active nodes and 0 elsewhere.
void lumped_solve(const Eigen::VectorXd& m_inv, const Field& x, Field& v);

/// FLIP (FMPM 2026 Eq. 8): V ← V + S a Δt,  X ← X + S v⁺ Δt − (1 − α) S a Δt², one pass over
/// S. Throws NumericalError naming the first particle (of the block) with a non-finite X or V.
void update_particles_flip(const ParticleOperators& op, const Field& v_plus, const Field& a,
                           double dt, double alpha, FieldRef X, FieldRef V);
/// PIC with grid velocity v (FMPM 2026 Eq. 9): V' = S v,  X ← X + (α V' + (1 − α) V) Δt,
/// V ← V'; with v = v⁺(k) this is the FMPM(k) update. Throws NumericalError for a non-finite
/// X or V.
void update_particles_pic(const ParticleOperators& op, const Field& v, double dt, double alpha,
                          FieldRef X, FieldRef V);

/// Velocity gradients L_p = Σ_i v_i ⊗ G_pi, N × d²: L(p, a d + b) = Σ_i G_b(p, i) v(i, a).
void velocity_gradient(const ParticleOperators& op, const Field& v, FieldRef L);

/// How F follows the velocity gradient over a step.
enum class DeformationUpdate {
  Linear,     ///< F ← (I + L Δt) F (USL notes; Buzzi Eq. 30)
  Exponential ///< F ← exp(L Δt) F (FMPM 2026 task 5): exact for a constant L
};
/// Name used in input files: linear | exponential.
std::string_view to_string(DeformationUpdate u);
/// Inverse of to_string; throws InputError naming the valid choices.
DeformationUpdate deformation_update_from_string(std::string_view name);

/// L_p = Σ_i v_i ⊗ G_pi and F_p ← (I + L_p Δt) F_p or exp(L_p Δt) F_p, one pass over the G_b.
/// Throws NumericalError naming the first particle (of the block) with det F ≤ 0.
void update_deformation(const ParticleOperators& op, const Field& v, double dt,
                        DeformationUpdate kind, FieldRef F);

} // namespace smpm
