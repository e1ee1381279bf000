#pragma once
/// \file stages.hpp
/// The stages of an explicit MPM step as matrix expressions over the assembled operators.
/// A scheme (USL, USF) is the order in which step.cpp calls them. n × d nodal fields hold one
/// row per node; N × d particle fields one row per particle.

#include "sparsempm/material.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/particles.hpp"

#include <Eigen/Core>
#include <array>

namespace smpm {

/// Grid fields of one step (all n × d).
struct GridState {
  Field p;      ///< momentum p = Sᵀ M V (after BC1)
  Field f;      ///< total force (after BC2)
  Field p_plus; ///< updated momentum p⁺ = p + f Δt
  Field v;      ///< v = m⁻¹ p
  Field v_plus; ///< v⁺ = m⁻¹ p⁺
  Field a;      ///< a = m⁻¹ f
};

/// Scratch storage reused from step to step, so that the stages do not allocate once sizes
/// are settled.
struct StageWorkspace {
  Field particle;         ///< N × d
  Field particle2;        ///< N × 2d
  Field tensor;           ///< N × d²
  Field node2;            ///< n × 2d
  Eigen::VectorXd volume; ///< N
};

/// p = Sᵀ (M ∘ V)  (FMPM 2026 task 1; Buzzi Eq. 26).
void map_momentum(const Operators& ops, const Particles& P, Field& p, StageWorkspace& w);
/// f = −Σ_b G_bᵀ (Ω J σ_{·b}): internal force from Kirchhoff stress τ = Jσ and initial
/// volumes Ω (FMPM 2026 task 2; Buzzi Eq. 15).
void internal_force(const Operators& ops, const Particles& P, Field& f, StageWorkspace& w);
/// f += Sᵀ M B for a uniform body acceleration B, i.e. f += m Bᵀ (Buzzi Eq. 14).
void add_body_force(const Operators& ops, const std::array<double, 3>& B, Field& f);
/// v = m⁻¹ x on active nodes, 0 on inactive ones.
void lumped_solve(const Operators& ops, const Field& x, Field& v);

/// FLIP (FMPM 2026 Eq. 8): V ← V + S a Δt,  X ← X + S v⁺ Δt − (1 − α) S a Δt², in one pass
/// over S. Throws NumericalError naming the first particle with a non-finite X or V.
void update_particles_flip(const Operators& ops, const GridState& g, double dt, double alpha,
                           Particles& P, StageWorkspace& w);
/// PIC, i.e. FMPM(1) (FMPM 2026 Eq. 9): V' = S v⁺,  X ← X + (α V' + (1 − α) V) Δt; with v⁺(k)
/// this is the FMPM(k) update. Throws NumericalError for a non-finite X or V.
void update_particles_pic(const Operators& ops, const Field& v_plus, double dt, double alpha,
                          Particles& P, StageWorkspace& w);

/// Velocity gradients L_p = Σ_i v_i ⊗ G_pi: column a d + b of L (N × d²) is (G_b v)_{·a}.
void velocity_gradient(const Operators& ops, const Field& v, Field& L);
/// F_p ← (I + L_p Δt) F_p for every particle.
void update_deformation_gradient(const Field& L, double dt, Particles& P);
/// The two above in one pass over the G_b: L_p = Σ_i v_i ⊗ G_pi, F_p ← (I + L_p Δt) F_p.
/// Throws NumericalError naming the first particle with det F ≤ 0.
void update_deformation_from_velocity(const Operators& ops, const Field& v, double dt,
                                      Particles& P);

/// Throws NumericalError naming the first particle with a non-finite position, velocity or
/// stress, or with det F ≤ 0.
void check_particles(const Particles& P);

} // namespace smpm
