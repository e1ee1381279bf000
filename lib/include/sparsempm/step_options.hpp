// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file step_options.hpp
/// The options of an explicit MPM time step, read by the Stepper (step.hpp), the stages
/// (scheme.hpp), the linearised step (stability.hpp) and the exact solver (exact.hpp): the
/// update scheme, the velocity update with its FMPM family, the exact-solver settings, the one
/// validate() that holds every limit, and the schedule of periodic FMPM (FMPM 2026 §3.3).

#include "sparsempm/fmpm.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/shape.hpp"
#include "sparsempm/stages.hpp"
#include "sparsempm/transport.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string_view>

namespace smpm {

/// When the particle stress is updated (Buzzi Figs. 2–3 and 5–7; FMPM 2026 §2.1, Fig. 1).
enum class UpdateScheme {
  USL,      ///< update stress last, from v⁺ (task 5; the recommended method)
  USF,      ///< update stress first, from v = m̃_k⁻¹ p before the forces (task 1.c)
  USLPlus,  ///< USL from velocities re-extrapolated after the particle update (task 4.c)
  USAVG,    ///< half Δt first (task 1.c) and half Δt last from v⁺ (task 3.b)
  USAVGPlus ///< half Δt first (task 1.c) and half Δt last, re-extrapolated (task 4.c)
};
/// How particle velocities are updated from the grid.
enum class VelocityUpdate {
  FLIP, ///< increment by the extrapolated lumped acceleration (FMPM 2026 Eq. 8)
  PIC,  ///< V = S v⁺(1), i.e. FMPM(1) (FMPM 2026 Eq. 9)
  FMPM, ///< V = S v⁺(k) with the FMPM loop of Table 1 (FMPM 2026 Eq. 9)
  XPIC, ///< V = S m(v − v*) + S a Δt (contact 2020 Eqs. 35, 41–43)
  Exact ///< V = S m̃⁻¹ p⁺, the consistent-mass inverse ("FMPM(∞)")
};
/// How particle momenta reach the grid (P2G).
enum class Transfer {
  Standard, ///< p_i = Σ_p S_ip M_p V_p (FMPM 2026 task 1)
  /// p_i = Σ_p S_ip M_p (V_p + L_p (x_i − X_p)), L_p the particle's velocity gradient, the
  /// gradient G v of the grid velocity its last particle update took (Wallstedt & Guilkey 2007,
  /// "Improved velocity projection for the material point method", CMES 19:223–232; FMPM 2026
  /// §3.3's Ref. [30]): affine velocity fields cross P2G and G2P exactly
  VelocityGradient,
  /// APIC (Jiang et al. 2015, "The affine particle-in-cell method", ACM TOG 34(4):51): P2G as
  /// VelocityGradient with the particle's affine velocity C_p = B_p D_p⁻¹ in place of L_p, B_p =
  /// Σ_i v_i ⊗ S_pi (x_i − X_p) and D_p = Σ_i S_pi (x_i − X_p)(x_i − X_p)ᵀ at the G2P's
  /// positions (stages.hpp, apic_weights; the particles carry C_p, not B_p:
  /// docs/studies/gradient-transfers.md); its mass operator m̃_A is symmetric and m̃ ≤ m̃_A ≤ m. With
  /// linear hats it is VelocityGradient (the multilinear limit)
  Apic
};
/// Name used in input files: standard | velocity_gradient | apic.
std::string_view to_string(Transfer t);
/// The transfer named `name`; throws InputError naming the valid choices.
Transfer transfer_from_string(std::string_view name);

/// How XPIC(m)'s grid velocity m(v − v*) = Σ_{j<m} A^j v (contact 2020 Eqs. 41–43; the
/// binomial sum of the FMPM loop run from v instead of v⁺) is computed, per field in
/// multimaterial mode (α's A^α = I − S^{+α}S^α): by the loop, whose increments the velocity BCs
/// correct (as `bc_method` says) in single material mode too, and contact in multimaterial mode;
/// or by the paper's closed form, which corrects neither.
enum class XpicContact {
  /// Default: that sum is FMPM 2026 Table 1's loop run from the contact-corrected v^α, with the
  /// velocity BCs and contact correcting every increment (§3.2, each pair's Net or Evolving
  /// method, from the state of the momentum update's lumped contact), as NairnMPM's XPIC does
  /// (XPICExtrapolationTask::GetDeltaV). Bonded contact reverts to single material XPIC(m) to
  /// round-off, and objects pressed together keep apart.
  Increments,
  /// The closed form of contact 2020 Eq. (41) with the contact term of Eq. (37),
  /// (I − S^α S^{+α})^{m−1} S^α Δv^α, and no correction of the increments: reverts to single
  /// material only approximately (its Eqs. 45–47), and lets objects under sustained compaction
  /// flow through each other.
  Term,
  /// Eq. (41) without the contact term: the paper's "uncorrected XPIC" (its Fig. 7).
  None
};
/// Name used in input files: increments | term | none.
std::string_view to_string(XpicContact c);
/// The method named `name`; throws InputError naming the valid choices.
XpicContact xpic_contact_from_string(std::string_view name);

/// How many contact corrections a multimaterial step makes (contact 2020 §3.2 and its "LR
/// Once" curve of Fig. 5).
enum class ContactCorrections {
  /// Default: after the extrapolation of the particle velocities to the grid (Eq. 26, the
  /// velocities the strains and FMPM start from) and after the momentum update (Eqs. 32–34):
  /// the paper's "general MPM codes should always use two contact calculations per time step".
  Twice,
  /// After the momentum update only, which then finds about the sum of both changes: kept to
  /// reproduce the paper's comparison (larger errors; not single material mode on a perfect
  /// interface).
  Once
};
/// Name used in input files: twice | once.
std::string_view to_string(ContactCorrections c);
/// The choice named `name`; throws InputError naming the valid choices.
ContactCorrections contact_corrections_from_string(std::string_view name);

/// Where zero-velocity conditions are imposed (Buzzi §5.5).
enum class BCOrdering {
  Correct, ///< zero the fixed momentum after P2G (BC1) and its rate before the update (BC2)
  Improper ///< BC2 and zero velocity only in the strain update (BC3), without BC1 (Fig. 22)
};
/// Name used in input files: correct | improper.
std::string_view to_string(BCOrdering o);
/// The ordering named `name`; throws InputError naming the valid choices.
BCOrdering bc_ordering_from_string(std::string_view name);

/// Names of the input files: USL | USF | USL+ | USAVG | USAVG+ and FLIP | PIC | FMPM | XPIC |
/// exact; the parsers throw InputError naming the valid choices.
std::string_view to_string(UpdateScheme s);
/// Name used in input files: FLIP | PIC | FMPM | XPIC | exact.
std::string_view to_string(VelocityUpdate v);
/// The scheme named `name`; throws InputError naming the valid choices.
UpdateScheme update_scheme_from_string(std::string_view name);
/// The velocity update named `name`; throws InputError naming the valid choices.
VelocityUpdate velocity_update_from_string(std::string_view name);

/// A velocity update as input files, the command line, Python and the tables name it: FLIP |
/// PIC | FMPM | XPIC | exact, or the other members of FMPM's polynomial family, chebyshev |
/// least_squares | chebyshev_squared (VelocityUpdate::FMPM with FmpmOptions::polynomial).
struct VelocityChoice {
  VelocityUpdate velocity = VelocityUpdate::FLIP; ///< the update
  Polynomial polynomial = Polynomial::Series;     ///< FMPM's member of the family
};
/// The choice named `name`; throws InputError naming the eight valid names.
VelocityChoice velocity_choice_from_string(std::string_view name);
/// Sets options.velocity and options.fmpm.polynomial from the choice named `name`.
void set_velocity(struct StepOptions& options, std::string_view name);
/// The name of the options' velocity update: the polynomial's for FMPM with a member other than
/// the series, else to_string(velocity).
std::string_view velocity_name(const struct StepOptions& options);

/// The nodal system m̃ v = p an exact solver is given (ExactOptions::system): the generic system of
/// the consistent-mass inverse, named once where its solver is made, so that the solver's
/// messages name the matrix it factors (velocity_solver_options, transport_solver_options).
enum class NodalSystem {
  ConsistentMass, ///< m̃ = Sᵀ diag(M) S of the velocity update (symmetric; FMPM 2026 §2.1)
  /// m̃_L of the velocity-gradient transfer (Transfer::VelocityGradient; not symmetric)
  GradientMass,
  /// m̃_A of the APIC transfer (Transfer::Apic; symmetric, m̃ ≤ m̃_A ≤ m)
  ApicMass,
  ConsistentCapacity ///< c̃ = Sᵀ diag(𝗖) S of heat transport (symmetric; FMPM 2026 §3.5)
};
/// The matrix's name in messages: "consistent mass matrix m~", "mass matrix m~_L of the
/// velocity-gradient transfer", "mass matrix m~_A of the APIC transfer" or "consistent capacity
/// matrix c~".
std::string_view to_string(NodalSystem s);
/// Whether the system's matrix is symmetric: m̃, m̃_A and c̃ are, m̃_L is not.
bool is_symmetric(NodalSystem s);

/// How the exact update solves m̃_FF v_F = b (exact.hpp): a sparse factorisation (CHOLMOD's
/// Cholesky for a symmetric m̃, UMFPACK's LU for m̃_L) or the preconditioned conjugate gradient
/// (Eigen's ConjugateGradient, symmetric m̃ only) to a relative residual.
enum class ExactMethod {
  Factor, ///< CHOLMOD or UMFPACK: m̃_FF⁻¹ to round-off
  PCG     ///< conjugate gradient to ‖b − m̃_FF v_F‖ ≤ tolerance ‖b‖
};
/// The preconditioner of ExactMethod::PCG.
enum class ExactPreconditioner {
  Diagonal,          ///< the diagonal of m̃_FF (Jacobi)
  IncompleteCholesky ///< Eigen's IncompleteCholesky of m̃_FF (zero fill, with its shift)
};
/// Names used in input files: factor | pcg.
std::string_view to_string(ExactMethod m);
/// Inverse of to_string; throws InputError naming the valid choices.
ExactMethod exact_method_from_string(std::string_view name);
/// Names used in input files: diagonal | ic.
std::string_view to_string(ExactPreconditioner p);
/// Inverse of to_string; throws InputError naming the valid choices.
ExactPreconditioner exact_preconditioner_from_string(std::string_view name);

/// The settings of the exact consistent-mass inverse (VelocityUpdate::Exact; exact.hpp and the
/// docs/studies/stability.md, "The exact inverse"): data, read by the solver a MassSolverFactory
/// makes and by anyone who inspects the options.
struct ExactOptions {
  /// ε ∈ [0, 1]: factor the blended mass (1 − ε) m̃ + ε m of FMPM 2026 §3.3 instead of m̃
  double regularization = 0;
  /// τ ∈ [0, 1): active nodes lighter than τ max m take their lumped velocity p_i/m_i
  double mass_cutoff = 0;
  /// A factorisation (CHOLMOD, UMFPACK) or the preconditioned conjugate gradient (symmetric m̃)
  ExactMethod method = ExactMethod::Factor;
  /// PCG: the relative residual ‖b − m̃_FF v_F‖ / ‖b‖ it stops at, in (0, 1)
  double tolerance = 1e-12;
  ExactPreconditioner preconditioner = ExactPreconditioner::Diagonal; ///< PCG's preconditioner
  /// The system the solver is given: m̃, m̃_L (not symmetric), m̃_A or c̃, named in its messages. Set
  /// where a solver is made (velocity_solver_options from the step's transfer,
  /// transport_solver_options), not an input entry.
  NodalSystem system = NodalSystem::ConsistentMass;
};

/// Solves the consistent-mass system m̃ v = p on the active nodes, with the velocity BCs of
/// `bc` imposed (the limit k → ∞ of the incremental method). Implemented with CHOLMOD in
/// sparsempm::exact (exact.hpp). A solver keeps state (its factorisation): each Stepper and
/// each linearised step makes its own from StepOptions::exact_solver.
class MassSolver {
public:
  virtual ~MassSolver() = default;
  /// v = m̃⁻¹ p (n × d) with m̃ = `mt` (n × n) on the active nodes of `ops` and the velocity BCs
  /// of `bc` imposed; v = 0 on the other nodes.
  virtual void solve(const Operators& ops, const SparseRowMatrix& mt, const LoopConstraints& bc,
                     const Field& p, Field& v) = 0;
  /// The response v = m̃⁻¹ r to a momentum change r with the matrix of the last solve and
  /// homogeneous conditions (zero on the components that solve prescribed): what the contact
  /// of the exact update in multimaterial mode needs. The default throws InputError.
  virtual void solve_again(const Field& r, Field& v);
  /// Whether solve() takes a window's momentum totals and solves m̃ v = p across processes (a
  /// step with NodeSums needs one); false for the solvers of one process.
  virtual bool across_processes() const { return false; }
};
/// Makes a new MassSolver with the given settings (e.g. cholmod_solver_factory() of exact.hpp,
/// which the input reader and the Python module choose).
using MassSolverFactory = std::function<std::unique_ptr<MassSolver>(const ExactOptions&)>;

/// The options of an explicit MPM time step (FMPM 2026 Fig. 1): shape functions, scheme,
/// velocity update with its FMPM or XPIC options, α, BC ordering, F update, exact solver and
/// the nodes of the step. validate(const StepOptions&) holds their limits.
struct StepOptions {
  Shape shape = Shape::CPDI; ///< the default of the input files (CPDI1, Sadeghirad et al. 2011)
  /// The order of the stages: when the stress is updated.
  UpdateScheme scheme = UpdateScheme::USL;
  /// How particle velocities follow the grid: FLIP, PIC, FMPM(k), XPIC(m) or the exact inverse.
  VelocityUpdate velocity = VelocityUpdate::FLIP;
  /// α of FMPM 2026 Eqs. (8)–(9); unset: default_position_alpha(velocity).
  std::optional<double> position_alpha{};
  BCOrdering bc_ordering = BCOrdering::Correct; ///< where velocity BCs act (Buzzi §5.5)
  FmpmOptions fmpm{};     ///< order k (FMPM) or m (XPIC), blending, BC method, dynamic
  double periodic_cx = 0; ///< C_X of periodic FMPM (§3.3); 0: FMPM on every step
  DeformationUpdate deformation = DeformationUpdate::Linear; ///< F ← (I + LΔt)F or exp(LΔt)F
  /// Multimaterial XPIC(m): contact on every increment of the loop (default), contact 2020
  /// Eq. (37)'s contact term, or neither (XpicContact).
  XpicContact xpic_contact = XpicContact::Increments;
  /// Contact after the extrapolation and after the momentum update (default), or after the
  /// momentum update only (ContactCorrections).
  ContactCorrections contact_corrections = ContactCorrections::Twice;
  ExactOptions exact{};             ///< settings of the exact inverse
  MassSolverFactory exact_solver{}; ///< required by VelocityUpdate::Exact
  /// The nodes of a step: the particles' window of the grid (storage and time proportional to
  /// the particles and the nodes they reach) or every node of the grid. The results are the same
  /// bits either way; only the numbering of the grid fields differs (Stepper::operators()).
  NodeRange nodes = NodeRange::Particles;
  /// Heat transport (transport.hpp): off (isothermal, the default), lumped, FMPM(k) on c̃ or
  /// the exact consistent-capacity solve.
  TransportOptions transport{};
  /// P2G of the momenta: standard, or with the particles' velocity gradients (Transfer).
  Transfer transfer = Transfer::Standard;
};

/// α of Eqs. (8)–(9) when the options leave it unset: 1 for FLIP (the usual choice, FMPM 2026
/// footnote to Eq. 8), ½ for grid-velocity updates (Eq. 9's consistent choice, §2.3).
double default_position_alpha(VelocityUpdate velocity);
/// The α a step with these options uses.
double position_alpha(const StepOptions& options);

/// Throws OptionError (an InputError naming the option) unless ε ∈ [0, 1] and τ ∈ [0, 1).
void validate(const ExactOptions& options);
/// Throws OptionError for option values outside their ranges (validate of FmpmOptions and of
/// ExactOptions, α ∈ [0, 1], C_X ≥ 0 and finite, the transport order, which transport = FMPM
/// needs unless the velocity update is FMPM or XPIC) and UsageError for an exact update
/// (velocity or transport) without a solver factory. The one check of StepOptions, and so the one
/// set of limits: the Stepper, the linearised step, the input reader, the command line and the
/// Python module call it.
void validate(const StepOptions& options);
/// The settings of the velocity update's exact solver: options.exact on m̃, on m̃_L (not
/// symmetric) with the velocity-gradient transfer, or on m̃_A with APIC.
ExactOptions velocity_solver_options(const StepOptions& options);
/// The settings of the exact transport solve: options.exact on the capacity matrix c̃.
ExactOptions transport_solver_options(const StepOptions& options);

/// The FMPM options of the transport loop on c̃: the order of TransportOptions (the mechanics'
/// order when it is 0; 1 for the lumped update), the mechanics' blending and BC method, no
/// dynamic stopping, and the series whatever the mechanics' member of the polynomial family.
FmpmOptions transport_fmpm_options(const StepOptions& options);
/// Whether a step assembles c̃: heat transport by FMPM(k) of order > 1 or the exact solve.
bool uses_consistent_capacity(const StepOptions& options);

/// Whether a step assembles m̃ (FMPM 2026 §2.2): on steps that update particles from grid
/// velocities (`grid_update`) with the exact inverse, or with FMPM(k) or XPIC(m) of order > 1.
bool uses_consistent_mass(const StepOptions& options, bool grid_update);

/// Periodic FMPM (FMPM 2026 §3.3): the grid-velocity update once per Courant budget C_X, FLIP on
/// the steps between. Adds the Courant number C of a step to the budget accumulated since the
/// last grid-velocity step; true (and the budget emptied) on the step that reaches C_X.
bool periodic_fmpm_step(double periodic_cx, double courant, double& budget);
/// The steps of one period at a constant Courant number C, the last of them the grid-velocity
/// step: the schedule of periodic_fmpm_step from an empty budget (⌈C_X / C⌉ up to round-off).
int periodic_fmpm_period(double periodic_cx, double courant);

} // namespace smpm
