#include "sparsempm/contact.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/stages.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace smpm {

std::string_view to_string(ContactLaw law) {
  switch (law) {
  case ContactLaw::Stick:
    return "stick";
  case ContactLaw::Frictionless:
    return "frictionless";
  case ContactLaw::Coulomb:
    return "coulomb";
  }
  return "?";
}
std::string_view to_string(ContactNormal normal) {
  return normal == ContactNormal::AverageGradient ? "AG" : "specified";
}
std::string_view to_string(ContactDetection detection) {
  switch (detection) {
  case ContactDetection::Always:
    return "always";
  case ContactDetection::Approaching:
    return "approaching";
  case ContactDetection::Position:
    return "CP";
  }
  return "?";
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

namespace {

// h_n = Σ_a |n_a| Δx_a, the width of a cell along n̂; A_c = V_cell / h_n (an axis-aligned
// interface gets the cell face). A_c only scales tractions: with the laws here it cancels from
// Δp (S_slide A_c Δt = min(Δp(0)·t̂, −μ Δp(0)·n̂)).
double cell_width_along(const Grid& grid, const Eigen::Vector3d& n) {
  double h = 0;
  for (int a = 0; a < grid.dim(); ++a)
    h += std::abs(n[a]) * grid.cell_size(a);
  return h;
}

double cell_volume(const Grid& grid) {
  double v = 1;
  for (int a = 0; a < grid.dim(); ++a)
    v *= grid.cell_size(a);
  return v;
}

// v/|v|, or 0 when v = 0 (gradients that cancel give no normal).
Eigen::Vector3d unit_or_zero(const Eigen::Vector3d& v) {
  const double norm = v.norm();
  return norm > 0 ? Eigen::Vector3d(v / norm) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d row3(const Field& f, Index r) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int a = 0; a < f.cols(); ++a)
    x[a] = f(r, a);
  return x;
}

// n̂ from field a to field b at node i (contact 2020 Eq. 13 for AG), and the separation
// (x^b − x^a)·n̂ − δ_c h_n of CP (Eq. 16), −1 for the other criteria. ga, gb, xa, xb are the
// gradients and mass-weighted positions of each side, ma, mb their masses.
void normal_and_separation(const Grid& grid, const ContactPair& pair, bool a_is_first,
                           const Eigen::Vector3d& ga, const Eigen::Vector3d& gb,
                           const Eigen::Vector3d& xa, const Eigen::Vector3d& xb, double ma,
                           double mb, Eigen::Vector3d& n, double& separation) {
  if (pair.normal == ContactNormal::Specified)
    n = a_is_first ? pair.direction : Eigen::Vector3d(-pair.direction);
  else
    n = unit_or_zero(ga - gb);
  separation = -1;
  if (pair.detection == ContactDetection::Position)
    separation = (xb / mb - xa / ma).dot(n) - pair.critical_separation * cell_width_along(grid, n);
}

} // namespace

void find_contact_nodes(const Grid& grid, const Operators& ops, const ParticleOperators& op,
                        const Contact& contact, const ConstFieldRef& X,
                        const Eigen::VectorXd& volume, ContactNodes& cn) {
  cn.nodes.clear();
  const int nf = ops.fields;
  if (nf < 2)
    return;
  const Index ng = ops.grid_node_count;
  bool gradient = false, position = false;
  auto need = [&](const ContactPair& p) {
    gradient = gradient || p.normal == ContactNormal::AverageGradient;
    position = position || p.detection == ContactDetection::Position;
  };
  for (const ContactPair& p : contact.pairs)
    need(p);
  if (contact.has_fallback)
    need(contact.fallback);
  if (gradient)
    volume_gradient(op, volume, cn.gradient);
  if (position)
    map_momentum(op, X, cn.position); // Σ_{p∈α} S_pi M_p X_p
  const double vcell = cell_volume(grid);
  for (Index i = 0; i < ng; ++i) {
    int count = 0, a = -1, b = -1;
    for (int f = 0; f < nf; ++f)
      if (ops.active[f * ng + i]) {
        ++count;
        (a < 0 ? a : b) = f;
      }
    if (count < 2)
      continue;
    ContactNodes::Node node{};
    node.node = i;
    if (count > 2) { // contact 2020 §3.4: lumped at apply time
      node.a = node.b = -1;
      cn.nodes.push_back(node);
      continue;
    }
    node.a = a;
    node.b = b;
    node.pair = &contact.pair(a, b);
    const Index ra = a * ng + i, rb = b * ng + i;
    const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
    normal_and_separation(
        grid, *node.pair, node.pair->first == a, gradient ? row3(cn.gradient, ra) : zero,
        gradient ? row3(cn.gradient, rb) : zero, position ? row3(cn.position, ra) : zero,
        position ? row3(cn.position, rb) : zero, ops.m[ra], ops.m[rb], node.normal,
        node.separation);
    const double h = cell_width_along(grid, node.normal);
    node.area = h > 0 ? vcell / h : 0;
    cn.nodes.push_back(node);
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
    if (law.detection == ContactDetection::Position && !(separation < 0))
      return false; // apart (Eq. 16)
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

namespace {

// Contact 2020 §3.4, Eq. (50): each field α at a node of three or more against all the others
// lumped into one virtual field, the law of the heaviest other field; the change goes to α only.
Index lumped_node(const Operators& ops, const ContactNodes& cn, const Contact* contact,
                  const Grid* grid, Index i, double dt, Field& p, Field* force,
                  std::vector<Eigen::Vector3d>& change) {
  const Index ng = ops.grid_node_count;
  const int nf = ops.fields;
  const bool gradient = cn.gradient.rows() == ops.num_nodes();
  const bool position = cn.position.rows() == ops.num_nodes();
  change.assign(size_t(nf), Eigen::Vector3d::Zero());
  Eigen::Vector3d g_all = Eigen::Vector3d::Zero(), x_all = Eigen::Vector3d::Zero(),
                  p_all = Eigen::Vector3d::Zero();
  double m_all = 0;
  for (int f = 0; f < nf; ++f)
    if (const Index r = f * ng + i; ops.active[r]) {
      m_all += ops.m[r];
      p_all += row3(p, r);
      if (gradient)
        g_all += row3(cn.gradient, r);
      if (position)
        x_all += row3(cn.position, r);
    }
  Index in_contact = 0;
  for (int f = 0; f < nf; ++f) {
    const Index r = f * ng + i;
    if (!ops.active[r])
      continue;
    int heaviest = -1;
    for (int o = 0; o < nf; ++o)
      if (o != f && ops.active[o * ng + i] &&
          (heaviest < 0 || ops.m[o * ng + i] > ops.m[heaviest * ng + i]))
        heaviest = o;
    const ContactPair& law = contact->pair(f, heaviest);
    const double ma = ops.m[r], mb = m_all - ma;
    const Eigen::Vector3d pa = row3(p, r), pb = p_all - pa;
    const Eigen::Vector3d ga = gradient ? row3(cn.gradient, r) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d xa = position ? row3(cn.position, r) : Eigen::Vector3d::Zero();
    Eigen::Vector3d n;
    double separation;
    normal_and_separation(*grid, law, law.first == f, ga, g_all - ga, xa, x_all - xa, ma, mb, n,
                          separation);
    const Eigen::Vector3d dp0 = (ma * pb - mb * pa) / (ma + mb);
    in_contact += contact_momentum_change(law, dp0, n, separation, change[size_t(f)]);
  }
  const int d = int(p.cols());
  for (int f = 0; f < nf; ++f)
    if (const Index r = f * ng + i; ops.active[r]) {
      p.row(r) += change[size_t(f)].head(d).transpose();
      if (force)
        force->row(r) += change[size_t(f)].head(d).transpose() / dt;
    }
  return in_contact > 0;
}

} // namespace

Index apply_contact(const Operators& ops, ContactNodes& cn, const Contact& contact,
                    const Grid& grid, double dt, Field& p, Field* force) {
  const Index ng = ops.grid_node_count;
  const int d = int(p.cols());
  Index in_contact = 0;
  Eigen::Vector3d dp;
  for (const ContactNodes::Node& node : cn.nodes) {
    if (node.a < 0) {
      in_contact += lumped_node(ops, cn, &contact, &grid, node.node, dt, p, force, cn.change);
      continue;
    }
    const Index ra = node.a * ng + node.node, rb = node.b * ng + node.node;
    const double ma = ops.m[ra], mb = ops.m[rb];
    const Eigen::Vector3d dp0 = (ma * row3(p, rb) - mb * row3(p, ra)) / (ma + mb);
    if (!contact_momentum_change(*node.pair, dp0, node.normal, node.separation, dp))
      continue;
    ++in_contact;
    p.row(ra) += dp.head(d).transpose();
    p.row(rb) -= dp.head(d).transpose();
    if (force) {
      force->row(ra) += dp.head(d).transpose() / dt;
      force->row(rb) -= dp.head(d).transpose() / dt;
    }
  }
  return in_contact;
}

} // namespace smpm
