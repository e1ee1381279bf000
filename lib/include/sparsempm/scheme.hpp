// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file scheme.hpp
/// The stages of one explicit MPM step in the order of its scheme (FMPM 2026 Fig. 1: USL, USF,
/// USL+, USAVG, USAVG+), with the grid-velocity solve (lumped, FMPM(k), XPIC(m) or exact) where
/// the figure places it. scheme_step is the only implementation of the step: the Stepper calls
/// it on the live state with freshly assembled operators, the linearised update operator T
/// (stability.hpp) on frozen operators with homogeneous velocity BCs.

#include "sparsempm/boundary.hpp"
#include "sparsempm/contact.hpp"
#include "sparsempm/loads.hpp"
#include "sparsempm/material.hpp"
#include "sparsempm/plasticity.hpp"
#include "sparsempm/step_options.hpp"

#include <array>
#include <span>

namespace smpm {

/// Grid fields of one step (all n × d).
struct GridState {
  Field p;      ///< momentum p = Sᵀ M V (after BC1)
  Field f;      ///< total force (after BC2)
  Field p_plus; ///< updated momentum p⁺ = p + f Δt
  Field v;      ///< v = m⁻¹ p
  Field v_plus; ///< v⁺ = m̃_k⁻¹ p⁺ (m⁻¹ p⁺ for FLIP and PIC)
  Field a;      ///< a = m⁻¹ f
  /// The velocity conditions' reaction forces f^(BC) = Δp/Δt of task 2.a (part of f; zero with
  /// the improper BC ordering, which sets no reaction).
  Field reaction;
};

/// The particle fields a step reads and writes, one row per particle of the operators.
struct ParticleFields {
  FieldRef X;             ///< N × d positions
  FieldRef V;             ///< N × d velocities
  FieldRef F;             ///< N × d² deformation gradients (read for J = det F)
  FieldRef stress;        ///< N × d² Cauchy stresses
  ConstVectorRef volume0; ///< N initial volumes
};

/// Task 5 (and task 1.c of USF/USAVG): the particles' deformation and stress over a time dt
/// from grid velocities v (n × d). One call per stage, never per particle.
class StrainUpdate {
public:
  virtual ~StrainUpdate() = default;
  /// Updates F and σ of the particles of `op` (the rows of `fields`) over dt from the grid
  /// velocities v (n × d).
  virtual void update(const ParticleOperators& op, const Field& v, double dt,
                      ParticleFields& fields) = 0;
};

/// The state shock physics carries through a strain update (material.hpp, Mie–Grüneisen): the
/// particles' internal energies, the cell size of the artificial viscosity, and scratch.
struct ShockState {
  Eigen::VectorXd* energy = nullptr;      ///< N internal energies per unit mass U (updated)
  double dx = 0;                          ///< Δx of contact 2020 Eq. (52): the smallest cell size
  Eigen::VectorXd J_old, p_old, pressure; ///< N: p + q after the strain update (scratch)
  /// \var J_old
  /// N: det F of each particle before the strain update (scratch, reused from step to step)
  /// \var p_old
  /// N: p + q of each Mie–Grüneisen particle before the strain update (scratch)
  Eigen::VectorXd work;    ///< N: each particle's viscous work of the update, with heat (scratch)
  double viscous_work = 0; ///< the viscosity's work Σ_p −q ΔJ V⁽⁰⁾ of the last update
};

/// The state heat transport carries through a strain update: the particles' temperatures, which
/// the couplings of the materials change reversibly, ΔT = −T Δc / (ρ₀ C_V) with c their
/// thermal_coupling (thermal expansion; the Grüneisen solid: ΔT = −γ₀ T ΔJ) (isentropic_heating),
/// and the dissipation of the other parts heats, ΔT = w / (M C_V) (heat_of_work; NairnMPM's dT_q0
/// and dissipated energy); scratch.
struct ThermalStrainState {
  Eigen::VectorXd* temperature = nullptr; ///< N absolute temperatures (updated)
  Eigen::VectorXd coupling;               ///< scratch: c of each particle before the step
};

/// The states of the parts in one strain update, which the parts' strain hooks read across
/// parts (the J2 return reads the shock's pressure, the shock's pressure the plastic state, and
/// dissipation heats the temperatures); null: the part is not in the step.
struct StrainCouplings {
  ShockState* shock = nullptr;           ///< Mie–Grüneisen energies and viscosity (shocks)
  ThermalStrainState* thermal = nullptr; ///< the temperatures the couplings change (heat)
  PlasticState* plastic = nullptr;       ///< b̄ᵉ and ε̄ᵖ of the J2 return (plasticity)
};

/// What the parts' strain hooks read and change in one strain update (MaterialStrainUpdate).
struct StrainStep {
  const std::vector<Material>& materials;            ///< the model's materials
  const Eigen::Ref<const Eigen::VectorXi>& material; ///< N material ids
  ParticleFields& fields;                            ///< the particles' F, σ (updated)
  double dt;                                         ///< the update's time
  const StrainCouplings& couplings;                  ///< the parts' states
  /// W(F_p) of every particle, as update_stress stores it (null: not stored); a part that
  /// changes a particle's stress stores its W.
  Eigen::VectorXd* density;
};

struct StepContext;

/// A part's work at the stage boundaries of scheme_step (FMPM 2026 Fig. 1; step_part.hpp) and
/// in its strain updates, on whole fields, once per step or update: never per particle. The
/// default hooks do nothing.
class StageHooks {
public:
  virtual ~StageHooks() = default;
  /// After task 1: the grid momenta and velocities of the particles' P2G.
  virtual void after_momentum(const StepContext& /*c*/, ParticleFields& /*fields*/) {}
  /// After tasks 2–3: the forces and the updated grid velocity, contact's frictional work done.
  virtual void after_velocity(const StepContext& /*c*/, ParticleFields& /*fields*/) {}
  /// After task 4, the particle update; u is the grid velocity the particles took (v⁺ for FLIP,
  /// v⁺(k) for FMPM(k), XPIC's for XPIC).
  virtual void after_particles(const StepContext& /*c*/, const Field& /*u*/,
                               ParticleFields& /*fields*/) {}
  /// A strain update (task 5, task 1.c of USF/USAVG) before F changes: what the part needs of
  /// the particles' state at the start of the update.
  virtual void before_deformation(StrainStep& /*s*/) {}
  /// A strain update after F changed, before the stresses σ(F).
  virtual void after_deformation(StrainStep& /*s*/) {}
  /// A strain update after the stresses σ(F): the part's own stresses and their dissipation.
  virtual void after_stress(StrainStep& /*s*/) {}
};

/// The simulation's strain update: F from the velocity gradient (update_deformation), then
/// σ = σ(F) by each particle's material (update_stress), with the parts' strain hooks around
/// them (StageHooks): shock physics' pressure, artificial viscosity and internal energy
/// (update_shock_stress), the J2 return (update_plastic_stress), the thermal couplings.
class MaterialStrainUpdate final : public StrainUpdate {
public:
  /// With `density`, each stress update also stores W(F_p) of every particle there
  /// (update_stress), for the energies of the step. With `couplings.thermal` (heat transport)
  /// the stresses take the temperatures' thermal expansion. The hooks run in their order.
  MaterialStrainUpdate(const std::vector<Material>& materials,
                       const Eigen::Ref<const Eigen::VectorXi>& material, DeformationUpdate kind,
                       Eigen::VectorXd* density = nullptr, const StrainCouplings& couplings = {},
                       std::span<StageHooks* const> hooks = {})
      : materials_(materials), material_(material), kind_(kind), density_(density),
        couplings_(couplings), hooks_(hooks) {}
  /// before_deformation, F ← (I + L Δt) F or exp(L Δt) F (update_deformation),
  /// after_deformation, σ = σ(F) (update_stress), after_stress.
  void update(const ParticleOperators& op, const Field& v, double dt,
              ParticleFields& fields) override;

private:
  const std::vector<Material>& materials_;
  Eigen::Ref<const Eigen::VectorXi> material_;
  DeformationUpdate kind_;
  Eigen::VectorXd* density_;
  StrainCouplings couplings_;
  std::span<StageHooks* const> hooks_;
};

/// Heat transport in one step (transport.hpp; FMPM 2026 §3.5): what the transport stages read
/// besides the step's operators, and the particle temperatures they update.
struct TransportContext {
  TransportUpdate update = TransportUpdate::Off;     ///< lumped (FLIP), FMPM(k) or exact
  FmpmOptions fmpm{};                                ///< FMPM(k) on c̃ (transport_fmpm_options)
  TransportLimiter limiter = TransportLimiter::None; ///< a bound on FMPM(k) (TransportOptions)
  const TransportOperators* ops = nullptr;           ///< capacities, conductances, c on the nodes
  const SparseRowMatrix* ct = nullptr; ///< c̃ (required when uses_consistent_capacity)
  MassSolver* solver = nullptr;        ///< required by TransportUpdate::Exact
  /// Temperature conditions of the step on the transport nodes (values at t, as the velocity
  /// BCs).
  const BoundaryConditions* bcs = nullptr;
  Eigen::VectorXd* temperature = nullptr; ///< N particle temperatures, updated by the step
  /// Mie–Grüneisen particles: their internal energies U (N), which take the heat received, with
  /// the materials and the particles' material ids; null without such particles.
  Eigen::VectorXd* energy = nullptr;
  const std::vector<Material>* materials = nullptr; ///< the model's materials
  const Eigen::VectorXi* material = nullptr;        ///< N material ids
  /// Whether the particle update checks that every temperature stays positive (absolute
  /// temperatures); false for the linearised transport step of the stability analysis, which
  /// maps perturbations of any sign.
  bool absolute = true;
};

/// What the stages read besides the particle fields; fixed during the step.
struct StepContext {
  /// The step's options: scheme, velocity update, FMPM options, α.
  const StepOptions* options = nullptr;
  const Operators* ops = nullptr;      ///< S, G, M, m at the start of the step
  const SparseRowMatrix* mt = nullptr; ///< m̃ (required when uses_consistent_mass)
  MassSolver* solver = nullptr;        ///< required by VelocityUpdate::Exact
  /// The grid of the operators' nodes (Operators::grid).
  const Grid* grid = nullptr;
  /// Velocity BCs, with one value and one node set per step: every use (the momentum reset
  /// after P2G, the reaction force of task 2.a, the FMPM loop, the exact solve, BC3) takes
  /// the values at the start of the step, t, as NairnMPM does (FMPM 2026 §3.1).
  const BoundaryConditions* bcs = nullptr;
  std::array<double, 3> gravity{0, 0, 0}; ///< the body acceleration B (Model::gravity)
  /// The external forces of Model::loads at t (external_forces); null without loads.
  const ExternalForces* external = nullptr;
  /// Multimaterial contact (contact.hpp): this step's contact nodes with their laws, normals
  /// and separations, found at the start of the step; null in single material mode.
  ContactNodes* contact_nodes = nullptr;
  double time = 0; ///< t at the start of the step
  /// Δt, the length of the step.
  double dt = 0;
  bool grid_update = false; ///< update particles from grid velocities (false: FLIP)
  /// P2G's term of an affine transfer (its part); null: p = Sᵀ M V.
  const AffineMomentum* affine = nullptr;
  /// The parts' work at the stage boundaries (StageHooks), in the parts' order.
  std::span<StageHooks* const> hooks{};
  /// Across processes (fmpm.hpp): `ops` and `mt` hold this process's particles on its window
  /// with m, m_inv and active already the totals; the step sums its P2G momenta and forces and
  /// the FMPM loop's products over the processes. FLIP, PIC, FMPM(k) and the exact update (with a
  /// `solver` that solves across the processes) in single material mode without heat; null: one
  /// process.
  const NodeSums* sums = nullptr;
};

/// The grid fields of the transport stages (n_g × 1, N × d for the gradients).
struct TransportState {
  Field tau;      ///< τ = Sᵀ 𝗖 T, the nodal heat content (task 1)
  Field T;        ///< T = c⁻¹ τ with the temperature conditions set: the conduction's field
  Field gradient; ///< N × d: ∇T_p = Σ_i G_pi T_i
  Field q;        ///< heat flow −K T + Sᵀ M r + contact heat, then + the conditions' reaction
  Field tau_plus; ///< τ⁺ = τ + q Δt (task 2), with the conditions set (task 2.a)
  Field theta;    ///< θ⁺ = c̃_k⁻¹ τ⁺: the updated nodal temperatures (task 3.b)
  Field rate;     ///< Ṫ = c⁻¹ q, the FLIP rate of the particle update
  FmpmWorkspace fmpm;  ///< scratch of the FMPM loop on c̃
  Eigen::VectorXd low; ///< FCT (TransportLimiter::FCT): θ_1 = c⁻¹ τ⁺, FMPM(1)'s nodal field
  Eigen::VectorXd lower;   ///< FCT: the least θ_1 of each node's neighbours and its particles' T
  Eigen::VectorXd upper;   ///< FCT: the largest of the same
  Eigen::VectorXd r_plus;  ///< FCT: Zalesak's R⁺, the share of a node's inflow it can take
  Eigen::VectorXd r_minus; ///< FCT: Zalesak's R⁻, the share of its outflow
  Eigen::VectorXd limited; ///< FCT: the limited θ before it replaces θ⁺
  Eigen::VectorXd before;  ///< N: temperatures before the particle update (Mie–Grüneisen U)
};

/// Scratch of the step, reused from step to step.
struct StepBuffers {
  GridState g;                         ///< the grid fields of the step
  FmpmWorkspace fmpm;                  ///< scratch of the FMPM loop and of XPIC
  FmpmReport report;                   ///< how the last FMPM loop ended
  Field v_strain, p_re, v_re, xpic, L; ///< N × d² scratch (scheme_step itself leaves it unused)
  /// \var v_strain
  /// n × d: v with the BC velocities set, for the strain update only (BC3, improper ordering)
  /// \var p_re
  /// n × d: the momenta re-extrapolated after the particle update (task 4.a of USL+, USAVG+)
  /// \var v_re
  /// n × d: m̃_k⁻¹ p of the strain updates from the first momenta (task 1.c) or from p_re (4.c)
  /// \var xpic
  /// n × d: XPIC's grid velocity m (v − v*) + a Δt of the particle update (contact 2020 Eq. 35)
  Field contact_dv; ///< Δv^α = m⁻¹Δp^α of the contact after P2G (multimaterial XPIC, Eq. 37)
  Field p_contact;  ///< p with the contact impulses of the exact update (multimaterial)
  TransportState heat; ///< the transport stages' fields (the heat part's)
};

/// The transport stages of one step (FMPM 2026 §3.5), as scheme_step calls them beside the
/// mechanics' tasks 1–4, and the linearised transport step of the stability analysis on their own.
/// Task 1: τ = Sᵀ 𝗖 T, and the nodal temperatures of the conduction, T = c⁻¹ τ with the
/// temperature conditions set (NairnMPM's gradient pass: τ itself stays as extrapolated, so that
/// the conditions' reaction heat of task 2.a includes the step to their values).
void transport_content(const Operators& ops, const TransportContext& heat, double t,
                       TransportState& h);
/// Tasks 2–3: q = −K T + Sᵀ M r + q_c with q_c the frictional heat of each contact node over Δt
/// (`contact`, after the velocity solve whose corrections do that work), τ⁺ = τ + q Δt, the
/// temperature conditions on τ⁺ with their reaction heat added to q (task 2.a), and θ⁺ = c̃_k⁻¹ τ⁺
/// (task 3.b): updated_velocity on the transport nodes (c in the place of m, the loop of Table 1
/// on c̃ with the conditions' increments zeroed) or the exact solve; Ṫ = c⁻¹ q for FLIP.
void transport_update(const Operators& ops, const TransportContext& heat,
                      const ContactNodes* contact, double t, double dt, TransportState& h);
/// Task 4: T_p += Δt S Ṫ (lumped; Eq. 8 with T for V) or T_p = S θ⁺ (FMPM, exact; Eq. 9); a
/// Mie–Grüneisen particle's internal energy U takes the heat it receives, C_V ΔT (its pressure's
/// thermal part ρ₀γ₀U; NairnMPM's e = W + Q).
void transport_particles(const Operators& ops, const TransportContext& heat, double dt,
                         TransportState& h);

/// One step of the scheme context.options->scheme (FMPM 2026 Fig. 1):
///   task 1  p = Sᵀ M V, contact (task 1.a), BC1, v = m⁻¹ p; USF/USAVG: strain update from
///           m̃_k⁻¹ p (task 1.c);
///   task 2  f = internal + body force, p⁺ = p + f Δt, contact on p⁺ with its force added to
///           f (task 3.a; contact 2020 Eqs. 30–34), BC2 with reaction forces (task 2.a);
///   task 3  v⁺ = m̃_k⁻¹ p⁺ (task 3.b): lumped, FMPM(k) (fmpm_velocity) or exact;
///   task 4  particle update: FLIP (Eq. 8), PIC/FMPM/exact (Eq. 9) or XPIC (contact 2020 Eq. 35);
///   task 5  USL: strain update from v⁺; USL+/USAVG+: from re-extrapolated velocities (4.c).
/// The parts' hooks (context.hooks) run at the stage boundaries. Heat transport's (lib/src/parts/
/// heat.cpp) run beside tasks 1–4 in every scheme, as NairnMPM's
/// TransportTask: τ = Sᵀ 𝗖 T and T = c⁻¹ τ with the temperature conditions for the conduction
/// (task 1); q = −K T + Sᵀ M r + the contact nodes' frictional heat / Δt, τ⁺ = τ + q Δt, the
/// conditions on τ⁺ with their reaction heat in q (task 2.a, after the velocity solve, whose
/// contact corrections do the frictional work); θ⁺ = c̃_k⁻¹ τ⁺ by updated_velocity on the
/// transport nodes (task 3.b: the same loop, hooks and BC method as the velocities) or the exact
/// solve; T_p += Δt S c⁻¹ q (lumped) or T_p = S θ⁺ (task 4).
/// Throws NumericalError naming the particle when a kernel finds NaN or det F ≤ 0, or a
/// temperature that is not positive.
void scheme_step(const StepContext& context, ParticleFields& fields, StrainUpdate& strain,
                 StepBuffers& buffers);

} // namespace smpm
