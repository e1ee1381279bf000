// SPDX-License-Identifier: BSD-3-Clause
// Multimaterial contact (contact.hpp): the fields of the particles, the contact law of one node
// (FMPM 2026 Eq. 18; contact 2020 Eqs. 14–16, 24) and the momentum corrections that apply it —
// after P2G and after the momentum update (lumped, contact 2020 Eqs. 26, 33–34 and 50) and
// inside the FMPM(k) loop (FMPM 2026 §3.2). The contact nodes are found in contact_nodes.cpp.

#include "sparsempm/contact.hpp"

#include "enum_names.hpp"

#include "contact_detail.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace smpm {

namespace detail {
Eigen::Vector3d row3(const Field& f, Index r) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int a = 0; a < f.cols(); ++a)
    x[a] = f(r, a);
  return x;
}

// The separation at the end of the step if the two sides keep their velocities:
// δ + Δt (v^β − v^α)·n̂ = δ + Δt Δp(0)·n̂ / m_red. Contact is judged on it, so that sides
// whose separation is zero to round-off (touching under compression, where δ sits at ±10⁻⁷ of
// a cell) and that approach are in contact; NairnMPM predicts the gap the same way for its grid
// separations (CoulombFriction::GetFrictionalDeltaMomentum).
double gap_at_step_end(double separation, const Eigen::Vector3d& dp0, const Eigen::Vector3d& n,
                       const SideMasses& m, double dt) {
  if (m.rigid_a || m.rigid_b)
    return separation + dt * dp0.dot(n) / m.reduced();
  return separation + dt * dp0.dot(n) * (m.ma + m.mb) / (m.ma * m.mb);
}

SideMasses side_masses(const Operators& ops, const ContactNodes& cn, Index node, int a, int b) {
  const Index ng = ops.grid_node_count;
  SideMasses m{ops.m[a * ng + node], ops.m[b * ng + node]};
  if (!cn.rigid.empty()) {
    m.rigid_a = cn.rigid[size_t(a)] != 0;
    m.rigid_b = cn.rigid[size_t(b)] != 0;
  }
  return m;
}
} // namespace detail

using detail::gap_at_step_end;
using detail::row3;
using detail::side_masses;
using detail::SideMasses;

namespace {
constexpr detail::EnumNames<ContactLaw, 3> kLaws{{{ContactLaw::Stick, "stick"},
                                                  {ContactLaw::Frictionless, "frictionless"},
                                                  {ContactLaw::Coulomb, "coulomb"}}};
constexpr detail::EnumNames<ContactNormal, 3> kNormals{
    {{ContactNormal::AverageGradient, "AG", "average gradient"},
     {ContactNormal::LogisticRegression, "LR", "logistic regression"},
     {ContactNormal::Specified, "specified"}}};
constexpr detail::EnumNames<ContactDetection, 5> kDetections{
    {{ContactDetection::Approaching, "approaching"},
     {ContactDetection::Position, "CP", "critical position"},
     {ContactDetection::DistanceFunction, "DF", "distance function"},
     {ContactDetection::LogisticRegression, "LR", "logistic regression"},
     {ContactDetection::Always, "always", "bonded"}}};
constexpr detail::EnumNames<ContactFmpmMethod, 2> kFmpmMethods{
    {{ContactFmpmMethod::Net, "net"}, {ContactFmpmMethod::Evolving, "evolving"}}};
} // namespace

std::string_view to_string(ContactLaw law) {
  return detail::enum_name(law, kLaws);
}
std::string_view to_string(ContactNormal normal) {
  return detail::enum_name(normal, kNormals);
}
std::string_view to_string(ContactDetection detection) {
  return detail::enum_name(detection, kDetections);
}
std::string_view to_string(ContactFmpmMethod method) {
  return detail::enum_name(method, kFmpmMethods);
}
ContactLaw contact_law_from_string(std::string_view name) {
  return detail::parse_enum(name, kLaws, "contact law");
}
ContactNormal contact_normal_from_string(std::string_view name) {
  return detail::parse_enum(name, kNormals, "contact normal");
}
ContactDetection contact_detection_from_string(std::string_view name) {
  return detail::parse_enum(name, kDetections, "contact detection");
}
ContactFmpmMethod contact_fmpm_method_from_string(std::string_view name) {
  return detail::parse_enum(name, kFmpmMethods, "contact method inside FMPM(k)");
}

double distance_function_edge(double s, double exponent, double reach) {
  return s > 0 ? 1.0 : 1 - 2 * std::pow(-s / reach, exponent);
}

int Contact::fields() const {
  int n = 1;
  for (int f : material_field)
    n = std::max(n, f + 1);
  return n;
}

const ContactPair& Contact::pair(int a, int b) const {
  if (a > b)
    std::swap(a, b);
  for (const ContactPair& p : pairs)
    if (p.first == a && p.second == b)
      return p;
  if (has_fallback)
    return fallback;
  throw InputError("velocity fields " + std::to_string(a) + " and " + std::to_string(b) +
                   " meet but no [[contact]] table gives their law");
}

void activate_bonded_fields(const Contact& contact, Operators& ops) {
  const int nf = ops.fields;
  if (nf < 2)
    return;
  auto bonded_law = [](const ContactPair& p) {
    return p.law == ContactLaw::Stick && p.detection == ContactDetection::Always;
  };
  std::vector<char> bonded(size_t(nf * nf), 0); // bonded[a nf + b]: a and b are bonded
  bool any = false;
  for (int a = 0; a < nf; ++a)
    for (int b = a + 1; b < nf; ++b) {
      bool law = contact.has_fallback && bonded_law(contact.fallback);
      for (const ContactPair& p : contact.pairs)
        if (p.first == a && p.second == b)
          law = bonded_law(p);
      bonded[size_t(a * nf + b)] = bonded[size_t(b * nf + a)] = law;
      any = any || law;
    }
  if (!any)
    return;
  const Index ng = ops.grid_node_count;
  auto total = [&](Index i) {
    double t = 0; // in field order, as lumped_mass_and_active sums it
    for (int f = 0; f < nf; ++f)
      t += ops.m[f * ng + i];
    return t;
  };
  double largest = 0;
  for (Index i = 0; i < ng; ++i)
    largest = std::max(largest, total(i));
  for (Index i = 0; i < ng; ++i) {
    if (!(total(i) > kMassTolerance * largest))
      continue;
    for (int f = 0; f < nf; ++f) {
      const Index r = f * ng + i;
      if (ops.active[r] || !(ops.m[r] > std::numeric_limits<double>::min()))
        continue;
      bool all = true;
      for (int g = 0; g < nf && all; ++g)
        all = g == f || !(ops.m[g * ng + i] > 0) || bonded[size_t(f * nf + g)];
      if (all) {
        ops.active[r] = true;
        ops.m_inv[r] = 1 / ops.m[r];
      }
    }
  }
}

void Contact::particle_fields(const Eigen::VectorXi& material, Eigen::VectorXi& field) const {
  field.resize(material.size());
  for (Index p = 0; p < material.size(); ++p) {
    const int m = material[p];
    SMPM_VERIFY(m >= 0 && size_t(m) < material_field.size(),
                "Contact::particle_fields: particle " + std::to_string(p) + " has material " +
                    std::to_string(m) + " without a field");
    field[p] = material_field[size_t(m)];
  }
}

bool contact_momentum_change(const ContactPair& law, const Eigen::Vector3d& dp0,
                             const Eigen::Vector3d& normal, double separation,
                             Eigen::Vector3d& dp) {
  dp.setZero();
  const double dn = dp0.dot(normal); // −N_c A_c Δt
  if (law.detection != ContactDetection::Always) {
    if (!(dn < 0)) // not approaching: N_c ≤ 0 (contact 2020 Eq. 14)
      return false;
    if (!(separation < 0))
      return false; // apart (CP, Eq. 16; LR, Eq. 24)
  }
  if (law.law == ContactLaw::Stick) {
    dp = dp0;
    return true;
  }
  if (normal.squaredNorm() == 0) // no normal (gradients cancel): no frictional interface
    return false;
  dp = dn * normal;
  if (law.law == ContactLaw::Frictionless)
    return true;
  const Eigen::Vector3d tangential = dp0 - dp; // T_c A_c Δt t̂
  const double stick = tangential.norm();
  if (stick > 0) {
    // S_slide A_c Δt = min(T_c, μ N_c) A_c Δt (FMPM 2026 Eq. 18, Fig. 6); no friction in tension.
    const double slide = std::min(stick, law.friction * std::max(0.0, -dn));
    dp += (slide / stick) * tangential;
  }
  return true;
}

double contact_friction_work(const Eigen::Vector3d& dp0, const Eigen::Vector3d& dp,
                             const Eigen::Vector3d& normal, double m_red) {
  const double stick = (dp0 - dp0.dot(normal) * normal).norm(); // |Δp(0)_t| = T_c A_c Δt
  const double slide = (dp - dp.dot(normal) * normal).norm();   // S_slide A_c Δt
  if (!(stick > slide) || !(m_red > 0))
    return 0; // sticks (or frictionless: no tangential impulse)
  return slide * (stick - slide) / m_red;
}

namespace {

// A node of three or more fields (contact 2020 §3.4, Eq. 50): each field α against the others
// lumped into one virtual field (p^β = Σ_{k≠α} p^k, m^β = Σ_{k≠α} m^k); the change goes to α
// only, so momentum is not conserved exactly (as the paper says).
bool lumped_node(const Operators& ops, ContactNodes& cn, size_t c, double dt, Field& p,
                 Field* force) {
  const ContactNodes::Node& node = cn.nodes[c];
  const Index ng = ops.grid_node_count, i = node.node;
  const int nf = ops.fields, d = int(p.cols());
  cn.change.assign(size_t(nf), Eigen::Vector3d::Zero());
  // A rigid field is not lumped: a field meets it alone (Side::rigid) or not at all.
  Eigen::Vector3d p_all = Eigen::Vector3d::Zero();
  double m_all = 0;
  for (int f = 0; f < nf; ++f)
    if (ops.active[f * ng + i] && (cn.rigid.empty() || !cn.rigid[size_t(f)])) {
      m_all += ops.m[f * ng + i];
      p_all += row3(p, f * ng + i);
    }
  bool in_contact = false;
  for (int f = 0; f < nf; ++f) {
    const Index r = f * ng + i;
    if (!ops.active[r])
      continue;
    const ContactNodes::Side& side = cn.sides[size_t(node.first_side + f)];
    if (!side.pair)
      continue; // a rigid field, or a field with no partner here
    const Eigen::Vector3d pa = row3(p, r);
    SideMasses m{ops.m[r], m_all - ops.m[r]};
    Eigen::Vector3d pb = p_all - pa;
    if (side.rigid >= 0) { // against the rigid body alone, its mass infinite
      m.mb = ops.m[side.rigid * ng + i];
      m.rigid_b = true;
      pb = row3(p, side.rigid * ng + i);
    }
    const Eigen::Vector3d dp0 = free_part(cn, c, m.centre_of_mass_change(pa, pb));
    const double gap = gap_at_step_end(side.separation, dp0, side.normal, m, dt);
    const bool touching =
        contact_momentum_change(*side.pair, dp0, side.normal, gap, cn.change[size_t(f)]);
    in_contact = touching || in_contact;
    if (touching && force) {
      const double work =
          contact_friction_work(dp0, cn.change[size_t(f)], side.normal, m.reduced());
      cn.friction_work += work;
      cn.heat[c] += work;
    }
  }
  // A field that met the rigid body alone gives the body the opposite change (undone by the
  // body's conditions, whose reaction then holds the contact force).
  for (int f = 0; f < nf; ++f)
    if (const int b = cn.sides[size_t(node.first_side + f)].rigid; b >= 0)
      cn.change[size_t(b)] -= cn.change[size_t(f)];
  for (int f = 0; f < nf; ++f)
    if (const Index r = f * ng + i; ops.active[r]) {
      p.row(r) += cn.change[size_t(f)].head(d).transpose();
      if (force)
        force->row(r) += cn.change[size_t(f)].head(d).transpose() / dt;
    }
  return in_contact;
}

} // namespace

Index apply_contact(const Operators& ops, ContactNodes& cn, double dt, Field& p, Field* force) {
  const Index ng = ops.grid_node_count;
  const int d = int(p.cols());
  Index in_contact = 0;
  Eigen::Vector3d dp;
  cn.prior.resize(cn.nodes.size());
  cn.net.resize(cn.nodes.size());
  cn.heat.assign(cn.nodes.size(), 0.0);
  for (size_t c = 0; c < cn.nodes.size(); ++c) {
    const ContactNodes::Node& node = cn.nodes[c];
    if (node.a < 0) {
      in_contact += lumped_node(ops, cn, c, dt, p, force);
      continue;
    }
    const Index ra = node.a * ng + node.node, rb = node.b * ng + node.node;
    const SideMasses m = side_masses(ops, cn, node.node, node.a, node.b);
    const Eigen::Vector3d dp0 = free_part(cn, c, m.centre_of_mass_change(row3(p, ra), row3(p, rb)));
    const double gap = gap_at_step_end(node.separation, dp0, node.normal, m, dt);
    const bool touching =
        !m.both_rigid() && contact_momentum_change(*node.pair, dp0, node.normal, gap, dp);
    if (!touching)
      dp.setZero();
    // Step 1 of FMPM 2026 §3.2's algorithm: initialise the incremental state.
    const bool evolving = node.pair->fmpm_method == ContactFmpmMethod::Evolving;
    cn.prior[c] = evolving ? Eigen::Vector3d(dp0 - dp) : dp0;
    cn.net[c] = dp;
    if (!touching)
      continue;
    ++in_contact;
    // A rigid side's change is undone by its velocity conditions, whose reaction then holds
    // the contact force on the rigid body (rigid.hpp).
    p.row(ra) += dp.head(d).transpose();
    p.row(rb) -= dp.head(d).transpose();
    if (force) {
      force->row(ra) += dp.head(d).transpose() / dt;
      force->row(rb) -= dp.head(d).transpose() / dt;
      // Heat only in the momentum-update correction, as NairnMPM: the correction after P2G
      // changes the grid velocities the FLIP increment is measured from, not the particles'.
      cn.heat[c] = contact_friction_work(dp0, dp, node.normal, m.reduced());
      cn.friction_work += cn.heat[c];
    }
  }
  return in_contact;
}

void contact_increment(const Operators& ops, ContactNodes& cn, double dt, Field& dv,
                       bool friction_work) {
  SMPM_VERIFY(cn.prior.size() == cn.nodes.size(),
              "contact_increment: the lumped contact (apply_contact) must run first");
  const Index ng = ops.grid_node_count;
  const int d = int(dv.cols());
  Eigen::Vector3d dp;
  for (size_t c = 0; c < cn.nodes.size(); ++c) {
    const ContactNodes::Node& node = cn.nodes[c];
    if (node.a < 0)
      continue; // three or more fields: the lumped correction only
    const Index ra = node.a * ng + node.node, rb = node.b * ng + node.node;
    const SideMasses m = side_masses(ops, cn, node.node, node.a, node.b);
    const double ma = m.ma, mb = m.mb, mred = m.reduced();
    // Eq. (20)
    const Eigen::Vector3d dp0 =
        cn.prior[c] + free_part(cn, c, mred * (row3(dv, rb) - row3(dv, ra)));
    const double gap = gap_at_step_end(node.separation, dp0, node.normal, m, dt);
    const bool touching =
        !m.both_rigid() && contact_momentum_change(*node.pair, dp0, node.normal, gap, dp);
    if (!touching)
      dp.setZero(); // not in contact: Δp(ℓ) = 0
    const double work = touching && friction_work
                            ? contact_friction_work(dp0, dp, node.normal, mred)
                            : 0.0; // first-order frictional heat of Δp(ℓ)
    Eigen::Vector3d correction = dp;
    if (node.pair->fmpm_method == ContactFmpmMethod::Evolving) {
      cn.prior[c] = dp0 - dp;
      cn.friction_work += work;
      cn.heat[c] += work;
    } else {
      correction = dp - cn.net[c]; // Δp^(eff)(ℓ)
      cn.prior[c] = dp0;
      cn.net[c] = dp;
      if (friction_work) {
        cn.friction_work += work - cn.heat[c];
        cn.heat[c] = work;
      }
    }
    if (!m.rigid_a) // a rigid field's increments stay those of its velocity conditions
      dv.row(ra) += (correction.head(d) / ma).transpose();
    if (!m.rigid_b)
      dv.row(rb) -= (correction.head(d) / mb).transpose();
  }
}

} // namespace smpm
