// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file contact.hpp
/// Multimaterial MPM with contact (contact 2020 §2–3; FMPM 2026 §3.2).
///
/// Each velocity field α extrapolates its own momenta and masses (contact 2020 Eq. 5). The
/// library stores the fields as blocks of columns of one S: node i of field α is column
/// α·n_g + i (operators.hpp), so that p^α, m^α and m̃^α are the blocks of p = Sᵀ M V, m = Sᵀ M
/// and the block-diagonal m̃ = Sᵀ M S (FMPM 2026 Eq. 15), one assembly of S per step.
///
/// At a node seen by two fields α < β, the momentum change that moves α to the centre-of-mass
/// velocity is Δp(0) = (m^α p^β − m^β p^α)/(m^α + m^β) (FMPM 2026 §3.2). With the contact normal
/// n̂ from α to β, the interface is in compression when N_c = −Δp(0)·n̂/(A_c Δt) > 0 (approaching,
/// contact 2020 Eq. 14), and in contact when, besides, the materials touch (separation < 0).
/// A node in contact changes the momenta by (FMPM 2026 Eq. 18; contact 2020 Eqs. 7–10)
///     Δp = (Δp(0)·n̂) n̂ + S_slide A_c Δt t̂,   p^α += Δp,   p^β −= Δp,
/// t̂ the unit tangential part of Δp(0), S_slide = min(T_c, μ N_c) for Coulomb friction
/// (T_c = Δp(0)·t̂/(A_c Δt), the traction that sticks), 0 frictionless, T_c stick.

#include "sparsempm/grid.hpp"
#include "sparsempm/types.hpp"

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string_view>
#include <vector>

namespace smpm {

struct BoundaryConditions;
struct Operators;
struct ParticleOperators;

/// The tangential law of an interface in contact.
enum class ContactLaw {
  Stick,        ///< Δp = Δp(0): both fields move with the centre of mass
  Frictionless, ///< S_slide = 0
  Coulomb       ///< S_slide = min(T_c, μ N_c)
};
/// How the contact normal n̂ (from field α to β) is found.
enum class ContactNormal {
  AverageGradient, ///< AG: n̂ ∝ g^α − g^β, g^α_i = Σ_{p∈α} G_pi V_p (contact 2020 Eqs. 11–13)
  Specified,         ///< SN: a direction given in the input, from the first material to the second
  LogisticRegression ///< LR: the plane separating the particle clouds (contact 2020 Eqs. 19–21)
};
/// When a node whose fields approach (N_c > 0) is in contact.
enum class ContactDetection {
  Always,      ///< every node seen by both fields, approaching or not: a bonded interface
  Approaching, ///< N_c > 0 alone (contact 2020 Eq. 14)
  Position,    ///< N_c > 0 and (x^β − x^α)·n̂ < δ_c h_n (CP = δ_c, contact 2020 Eq. 16)
  /// N_c > 0 and d((x^β − x_i)·n̂) − d((x^α − x_i)·n̂) < 0 (DF, contact 2020 Eq. 15), d the
  /// power-law fit of the edge positions (distance_function_edge)
  DistanceFunction,
  LogisticRegression ///< N_c > 0 and d_LR < 0 from the particle clouds (contact 2020 Eq. 24)
};

/// How contact corrects the increments of the FMPM(k) loop (FMPM 2026 §3.2, after Eq. 20).
enum class ContactFmpmMethod {
  Net,     ///< the law on the net uncorrected velocities; Δp^(eff)(ℓ) = Δp(ℓ) − Δp^(net)
  Evolving ///< the law on the evolving corrected velocities; Δp(ℓ) corrects the increment
};

/// Name of a law in the [[contact]] tables (key `law`): stick | frictionless | coulomb.
std::string_view to_string(ContactLaw law);
/// Name of a normal in the [[contact]] tables (key `normal`): AG | LR | specified.
std::string_view to_string(ContactNormal normal);
/// Name of a detection in the [[contact]] tables (key `detection`): approaching | CP | DF | LR |
/// always.
std::string_view to_string(ContactDetection detection);
/// Name of a method in the [[contact]] tables (key `fmpm_method`): net | evolving.
std::string_view to_string(ContactFmpmMethod method);
/// The law named `name`; throws InputError naming the valid choices.
ContactLaw contact_law_from_string(std::string_view name);
/// The normal named `name`; throws InputError naming the valid choices.
ContactNormal contact_normal_from_string(std::string_view name);
/// The detection named `name`; throws InputError naming the valid choices.
ContactDetection contact_detection_from_string(std::string_view name);
/// The method named `name`; throws InputError naming the valid choices.
ContactFmpmMethod contact_fmpm_method_from_string(std::string_view name);

/// The contact between two velocity fields.
struct ContactPair {
  /// α, the first field of the pair
  int first = 0, second = 1; ///< β, the second field (α < β)
  /// The tangential law.
  ContactLaw law = ContactLaw::Frictionless;
  double friction = 0; ///< μ of Coulomb friction
  /// The defaults are contact 2020's recommendation (§5: "use logistic regression to find contact
  /// normal and material separation"): LR normals with LR separation. A block sliding on an
  /// inclined, grid-unaligned slab keeps g(sin θ − μ cos θ) within 4% with them; with AG normals
  /// and the approaching criterion it loses half of it (docs/studies/contact.md).
  ContactNormal normal = ContactNormal::LogisticRegression;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitY(); ///< SN: unit n̂ from α to β
  /// When a node whose fields approach is in contact.
  ContactDetection detection = ContactDetection::LogisticRegression;
  double critical_separation = 0.8;        ///< δ_c of CP, in cells along n̂ (contact 2020 Eq. 16)
  double df_exponent = 0.5757166424934449; ///< r of the DF fit: ln 2 / ln(10/3)
  double df_reach = 1.25;                  ///< L of the DF fit, in cells along n̂
  ContactFmpmMethod fmpm_method = ContactFmpmMethod::Net; ///< inside FMPM(k) (FMPM 2026 §3.2)
};

/// The DF fit of contact 2020 Eq. (15), the power law of NairnMPM's material separation: the
/// position, in cells along n̂, of the edge of a material that lies on the −n̂ side of node i,
/// given the position s = (x^α − x_i)·n̂ / h_n of its extrapolated particle centre,
///     d(s) = 1 − 2 (−s/L)^r  (s ≤ 0),   d(s) = 1  (s > 0),
/// so d = −1 where the support of node i ends (s = −L) and d = 1 as the centre reaches the node.
/// A material on the +n̂ side has the mirrored edge −d(−s) (Fig. 1B's right-hand curves); the
/// separation of Eq. (15) is h_n (−d(−s^β) − d(s^α)). For s > 0 (a centre past the node, whose
/// exact edge is at least a cell beyond it) d stays 1, where NairnMPM's odd extension of the fit
/// would jump to −1. The defaults fit the exact d(s) of undeformed uGIMP particles at two per
/// cell (contact 2020 Fig. 1B; analysis/df_fit.py): L = 1.25 (the support of the node ends at
/// centres 1 + l_p cells away) and r = ln 2 / ln(10/3) = 0.5757, which makes the fit exact where
/// the edge sits on the node (s = −3/8, d = 0), the point that decides contact between like
/// materials (largest error elsewhere 0.021 cells). The least-squares r = 0.569 is off by
/// 0.008 cells there: two blocks touching on a grid line would be 0.016 cells apart and
/// released until they compress that much.
double distance_function_edge(double s, double exponent, double reach);

/// The velocity fields of a model and the contact between them.
struct Contact {
  /// Field of each material (index into Model::materials); empty: one field (single material
  /// mode). Materials with the same field share a velocity (a perfect interface).
  std::vector<int> material_field;
  /// Contact laws of pairs of fields; a pair without one uses `fallback` if set.
  std::vector<ContactPair> pairs;
  /// Whether pairs without a law of their own take `fallback` (a [[contact]] table without
  /// `materials`); without it, such a pair is an InputError.
  bool has_fallback = false;
  ContactPair fallback{}; ///< the law of every pair not in `pairs` (when has_fallback)

  /// Number of velocity fields (1 + the largest field id).
  int fields() const;
  /// The law between fields a and b (a ≠ b); throws InputError naming both if there is none.
  const ContactPair& pair(int a, int b) const;
  /// Field of every particle (from its material), written into `field` (resized).
  void particle_fields(const Eigen::VectorXi& material, Eigen::VectorXi& field) const;
};

/// The particle fields contact reads at the start of a step.
struct ContactParticles {
  ConstFieldRef X;           ///< N × d positions
  ConstFieldRef F;           ///< N × d² deformation gradients (R_p, contact 2020 Eq. 25)
  ConstFieldRef half_length; ///< N × d initial half-lengths R_0 (Eq. 25)
  ConstVectorRef volume;     ///< N current volumes (AG normals, Eq. 11)
};

/// How a logistic-regression fit ended.
struct LogisticFit {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(); ///< unit n̂ from class −1 to class +1
  int iterations = 0;                               ///< Gauss–Newton iterations taken
  bool converged = false; ///< 1 − n̂^(k+1)·n̂^(k) < 10⁻⁵ within 15 iterations
};

/// LR normal (contact 2020 Eqs. 19–21 and Appendix, Eqs. 53–57): the plane x·φ = 0 that
/// minimises Σ_p (f(x_p, φ) − c_p)² + Σ_j λ_j φ_j², f = 2/(1 + e^{−x·φ}) − 1, by Gauss–Newton
/// from φ⁽⁰⁾ = 0 (whose first step is the linear regression), with w_p = 1, the paper's penalty
/// λ = 10⁻⁷ Δx² (1, 1, 1, 0) and its stopping rule (1 − n̂^(k+1)·n̂^(k) < 10⁻⁵, at most 15
/// iterations, the last iterate kept). `points` are N × d positions (relative to the node),
/// `classes` −1 (material α) or +1 (β).
LogisticFit logistic_regression_normal(const ConstFieldRef& points,
                                       const Eigen::Ref<const Eigen::VectorXd>& classes,
                                       double cell);

/// R_p of contact 2020 Eq. (25): the distance along the unit n̂ from a particle's centre to
/// the ellipsoid inscribed in its initial domain (half-lengths r0) carried by F (row-major
/// d × d): 1/R_p = |diag(r0)⁻¹ F⁻¹ n̂|.
double particle_radius_along(int dim, const double* F, const double* r0, const Eigen::Vector3d& n);

/// The grid data that contact needs at the start of a step, computed once and reused by both
/// corrections of the step (after P2G and after the momentum update): the nodes seen by two or
/// more fields, their normals, separations and contact areas.
struct ContactNodes {
  /// A contact node: a grid node seen by two or more fields.
  struct Node {
    Index node = 0; ///< grid node i
    /// The first of its two fields (a < b); −1 for a node of 3+ fields.
    int a = 0, b = 0;      ///< the second of its two fields; −1 for a node of 3+ fields
    Index first_side = -1; ///< 3+ fields: sides[first_side + α] is field α against the rest
    Eigen::Vector3d normal = Eigen::Vector3d::Zero(); ///< n̂ from a to b (d entries used)
    double separation = 0; ///< CP: (x^b − x^a)·n̂ − δ_c h_n; DF: Eq. 15; LR: d_LR; −1 otherwise
    double area = 0;       ///< A_c = V_cell / h_n, h_n = √(Σ_a (n_a Δx_a)²)
    const ContactPair* pair = nullptr; ///< the law (two fields)
    int constrained = -1; ///< index into `free` when velocity conditions act here, else −1
  };
  /// One field against all the others lumped (contact 2020 §3.4, Eq. 50).
  struct Side {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero(); ///< n̂ from the field to the rest
    double separation = -1; ///< as Node::separation, along this normal; −1 without mass here
    const ContactPair* pair = nullptr; ///< the law with the heaviest other field
    /// The rigid field this field meets here instead of the rest (the rigid field holding most
    /// of the node's particle volume, at least 30% of it), or −1. The field then contacts that
    /// body alone, as at a node of two fields: its infinite mass, its outward normal.
    int rigid = -1;
  };
  std::vector<Node> nodes; ///< the contact nodes of the step, by ascending grid node
  /// Per field: 1 for the field of a rigid material (rigid.hpp; rigid_fields), whose mass is
  /// infinite in contact: Δp(0) = m^α (v^β − v^α) takes the other side to the rigid velocity,
  /// the increments of the FMPM loop leave the rigid side alone, and its velocity conditions
  /// undo the lumped corrections on it, their reactions holding the contact force on the body.
  /// A node of a rigid field and another is a contact node only where the rigid field holds
  /// 30% of its particle volume (contact_nodes.cpp), and AG and LR take the rigid body's outward
  /// normal there (contact_geometry.cpp). At a node of three or more fields where a rigid field
  /// holds 30% of the particle volume, each other field contacts it alone (Side::rigid); below
  /// that share it is no partner there and the other fields are lumped among themselves. Empty:
  /// no rigid field. Two rigid fields are never in contact.
  std::vector<char> rigid;
  std::vector<Side> sides; ///< nodes of 3+ fields: sides[first_side + α] for each field α
  /// Projectors onto the directions the velocity conditions of a node leave free
  /// (Node::constrained); find_contact_nodes projects the normals, and the contact laws Δp(0).
  std::vector<Eigen::Matrix3d> free;
  /// n_g: index into `free` of every grid node on which velocity conditions (of all fields)
  /// act, or −1. A rigid body's outward normal takes its gradients at such nodes in their free
  /// directions only (contact_geometry.cpp: a body's face on a roller is not a surface).
  std::vector<int> fixed;
  Field gradient;         ///< n × d: g^α_i = Σ_{p∈α} G_pi V_p (AG normals; rigid fields)
  Eigen::VectorXd volume; ///< n: Σ_{p∈α} S_pi V_p, with rigid fields (their share of a node)
  Field position;         ///< n × d: Σ_{p∈α} S_pi M_p X_p (mass-weighted positions; CP)
  // LR point clouds: the particles (and their fields) whose shape functions reach each contact
  // node, cloud[cloud_offset[c] … cloud_offset[c + 1]) for nodes[c]; reused from step to step.
  std::vector<int> slot; ///< n_g: index of the node in `nodes`, or −1
  /// nodes.size() + 1 offsets into `cloud`.
  std::vector<Index> cloud_offset;
  std::vector<std::pair<int, int>> cloud; ///< (particle, field)
  std::vector<Eigen::Vector3d> change;    ///< scratch of the lumped nodes
  /// The incremental contact of the FMPM loop (FMPM 2026 §3.2), per node of two fields:
  /// Δp^(prior)(0), which the last lumped correction (apply_contact) initialises and the
  /// corrections of the loop (contact_increment) or of the exact update (exact_contact) update
  std::vector<Eigen::Vector3d> prior, net; ///< Δp^(net), likewise (FMPM 2026 §3.2)
  /// Per node: the frictional work of the step at that node, when the last apply_contact was
  /// the momentum-update correction (0 otherwise): of its net correction, which the loop
  /// replaces (Net), or of all its corrections, which the loop adds to (Evolving; the fields of
  /// a node of three or more summed). Σ heat = friction_work of the step; heat transport turns
  /// it into heat at the node (transport.hpp).
  std::vector<double> heat;
  /// The frictional work of the step's momentum-update correction (apply_contact with a
  /// force; contact_friction_work) and of the corrections that follow it in the FMPM loop or
  /// the exact update (contact_increment, exact_contact), reset by find_contact_nodes.
  double friction_work = 0;
};

/// The work of Coulomb friction at one node (NairnMPM's first-order frictional heating): the
/// tangential impulse S_slide A_c Δt of Δp times the slip velocity it leaves,
/// (|Δp(0)_t| − S_slide A_c Δt)/m_red; 0 when the node sticks or the law has no friction.
double contact_friction_work(const Eigen::Vector3d& dp0, const Eigen::Vector3d& dp,
                             const Eigen::Vector3d& normal, double m_red);

/// Bonded contact (law stick, detection always: contact 2020 §2.3's test of the reversion to
/// single material mode) is single material mode on every node: a field with mass on a node
/// whose total Σ_α m^α_i single material mode keeps, but below the tolerance of an active field
/// (kMassTolerance of the largest total), is made active there when it is bonded to every other
/// field with mass on the node, so that its momentum and internal force stay on the node as in
/// single material mode. (A uGIMP domain that barely reaches a node gives such a field; dropping
/// its force there departed a bonded run from single material mode by 2e-8 of the velocity.)
/// Other laws keep the tolerance: a field of a tiny share is not a contact partner.
void activate_bonded_fields(const Contact& contact, Operators& ops);

/// Finds the nodes seen by two or more fields of `ops` (block columns) and their normals,
/// separations and areas (contact 2020 §2.3, §3.1), once per step.
///
/// With `bcs`, a contact node on which velocity conditions fix directions (a roller, a wall)
/// takes the part of its normal in the directions they leave free, renormalised, and its
/// separation and area along that normal; the contact laws then act on the free part of Δp(0)
/// (ContactNodes::free). The conditions overwrite those components of every field's velocity
/// after contact (with the correct BC ordering; Buzzi's improper ordering, kept for
/// comparison, does not re-apply them), so a normal tilted toward them (logistic regression on the
/// truncated particle clouds beside a wall) would lose that share of the normal impulse and let the
/// materials interpenetrate along the wall. NairnMPM zeroes the same components of normals and
/// momentum changes on its symmetry planes (CrackVelocityField::AdjustForSymmetry).
void find_contact_nodes(const Grid& grid, const Operators& ops, const ParticleOperators& op,
                        const Contact& contact, const ContactParticles& particles, ContactNodes& cn,
                        const BoundaryConditions* bcs = nullptr);

/// Δp(0) of contact node c with the directions fixed by velocity conditions removed
/// (find_contact_nodes); Δp(0) itself where no condition acts.
inline Eigen::Vector3d free_part(const ContactNodes& cn, size_t c, const Eigen::Vector3d& dp0) {
  const int k = cn.nodes[c].constrained;
  return k < 0 ? dp0 : Eigen::Vector3d(cn.free[size_t(k)] * dp0);
}

/// Δp of one node in contact (FMPM 2026 Eq. 18): the momentum change of field α given
/// Δp(0) = (m^α p^β − m^β p^α)/(m^α + m^β), the unit normal n̂ from α to β and the law.
/// Returns false (and Δp = 0) when the node is not in contact: not approaching (unless
/// detection is Always) or separated.
bool contact_momentum_change(const ContactPair& law, const Eigen::Vector3d& dp0,
                             const Eigen::Vector3d& normal, double separation, Eigen::Vector3d& dp);

/// Applies contact to the momenta p (block columns, n_f·n_g × d) at every contact node:
/// p^α += Δp, p^β −= Δp for two fields; for three or more, each field α against all others
/// lumped (contact 2020 Eq. 50), the law of the heaviest other field. When `force` is given,
/// adds Δp/Δt to it (the contact force f^{αC,1} of contact 2020 Eq. 33) and adds the frictional
/// work of the correction to cn.friction_work. Returns the number of nodes in contact. Allocates
/// nothing once `cn` has served a step.
Index apply_contact(const Operators& ops, ContactNodes& cn, double dt, Field& p,
                    Field* force = nullptr);

/// Contact on the increment Δv(ℓ) of the FMPM(k) loop (FMPM 2026 §3.2, Eqs. 19–20 and the
/// two-step algorithm after them), the contact hook of the loop (Table 1, line 2). At each node
/// of two fields, Δp(0) = Δp^(prior)(0) + m_red (Δv^β(ℓ) − Δv^α(ℓ)) (Eq. 20) goes through the
/// same law as the lumped correction (contact_momentum_change, Eq. 18) and gives Δp(ℓ) (0 when
/// not in contact); Evolving: Δv^α += Δp(ℓ)/m^α, Δv^β −= Δp(ℓ)/m^β, Δp^(prior)(0) = Δp(0) −
/// Δp(ℓ); Net: the same with Δp^(eff) = Δp(ℓ) − Δp^(net), then Δp^(prior)(0) = Δp(0),
/// Δp^(net) = Δp(ℓ). Starts from the state of the last apply_contact. Nodes of three or more
/// fields keep only their lumped correction. When `friction_work` (the loop after the
/// momentum-update correction), the frictional work follows the corrections: Net replaces the
/// node's work by that of Δp(ℓ) (NairnMPM's priorMredDelWf), Evolving adds that of each Δp(ℓ).
void contact_increment(const Operators& ops, ContactNodes& cn, double dt, Field& dv,
                       bool friction_work = false);

/// Contact for the exact update in multimaterial mode: the k → ∞ limit of the Net method
/// (FMPM 2026 §3.2). Summing the Net recursion over all passes gives its fixed point
///     v^α = (m̃^α)⁻¹ (p^α ± Δp),   Δp = law(Δp + m_red (v^β − v^α))   (Eqs. 18–20)
/// at every node of two fields (m̃ is block diagonal, one block per field, Eq. 15). On entry p
/// holds the momenta with the last lumped correction (apply_contact: Δp^(net)) and v = m̃⁻¹ p;
/// `respond(r, u)` gives u = m̃⁻¹ r with homogeneous velocity conditions (MassSolver::
/// solve_again). Each outer pass classifies the nodes by the law at the current state — apart
/// (Δp = 0), sticking (v^β = v^α), or normal only (the normal component of v^β − v^α zero, the
/// tangential impulse fixed at the law's: 0 frictionless, S_slide A_c Δt sliding) — and solves
/// the linear equations for the impulses by conjugate gradients on K = B ᵀ m̃⁻¹ B (one solve a
/// product, preconditioned by m_red), until the law holds at every node (changes below 1e-12
/// of the largest nodal momentum). Nodes of three or more fields keep their lumped correction.
/// Updates p, v, Δp^(net) and, with `friction_work`, the frictional work of the net impulses.
/// Returns the number of outer passes; throws NumericalError when they do not converge.
int exact_contact(const Operators& ops, ContactNodes& cn, double dt,
                  const std::function<void(const Field& r, Field& u)>& respond, Field& p, Field& v,
                  bool friction_work = false);

} // namespace smpm
