// SPDX-License-Identifier: BSD-3-Clause
// Contact nodes (contact.hpp, find_contact_nodes): the nodes two or more velocity fields share,
// with their normals (AG, LR, the axes), separations (CP, DF, LR), contact areas and the
// directions their velocity conditions leave free (contact 2020 §3.1–3.4, FMPM 2026 §3.2).
// The laws and the momentum corrections that use them are in contact.cpp.

#include "sparsempm/contact.hpp"

#include "contact_detail.hpp"

#include "contact_lr.hpp"
#include "parallel.hpp"

#include "sparsempm/boundary.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/stages.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace smpm {

using detail::row3;

namespace {

// The share of a node's particle volume (Σ_p S_pi V_p over its fields) that a rigid field must
// hold for the node to be a contact node with it. With infinite mass, a node the rigid body
// barely reaches (inside the other body, a cell from the surface) would take the other side's
// whole velocity along a normal that only a sliver of the body defines; a block on a rigid slab
// inclined at 25° and 35° to the grid then crept with μ = 1 > tan θ and lost 12% of its
// acceleration with μ = 0.2 (CPDI; 40% with GIMP). Measured on that block: shares of 0.3 to
// 0.45 give g(sin θ − μ cos θ) within 1% and hold it with μ = 1; 0.2 loses 2.4%
// (tests/lib/test_rigid.cpp).
constexpr double kRigidShare = 0.3;

// h_n = √(Σ_a (n_a Δx_a)²), the cell size along n̂ that NairnMPM uses for the separation
// and the contact area (MeshInfo::GetPerpendicularDistance: exact there for 2D grids and for
// cubic cells; its 3D non-cubic form follows the tangent plane): h_n = Δx on square cells for
// every n̂. A_c = V_cell / h_n only scales tractions: with the laws here it cancels from Δp
// (S_slide A_c Δt = min(Δp(0)·t̂, −μ Δp(0)·n̂)).
double cell_width_along(const Grid& grid, const Eigen::Vector3d& n) {
  double h2 = 0;
  for (int a = 0; a < grid.dim(); ++a)
    h2 += n[a] * n[a] * grid.cell_size(a) * grid.cell_size(a);
  return std::sqrt(h2);
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

bool uses(const Contact& c, ContactNormal normal) {
  bool any = c.has_fallback && c.fallback.normal == normal;
  for (const ContactPair& p : c.pairs)
    any = any || p.normal == normal;
  return any;
}
bool uses(const Contact& c, ContactDetection detection) {
  bool any = c.has_fallback && c.fallback.detection == detection;
  for (const ContactPair& p : c.pairs)
    any = any || p.detection == detection;
  return any;
}

// The geometry of one contact node: side A is field a, side B field b, or every other field
// with mass when b < 0 (the lumped virtual material of contact 2020 Eq. 50).
struct NodeGeometry {
  const Grid& grid;
  const Operators& ops;
  const ContactNodes& cn;
  const ContactParticles& P;
  Index node;      // grid node i
  Index cloud = 0; // its contact index (LR clouds)

  // Side B: field b, or (b < 0) every other active field but a rigid one (a rigid body is no
  // part of the lumped rest: ContactNodes::Side::rigid).
  bool in_b(int f, int a, int b) const {
    return f != a && (b >= 0 ? f == b : ops.active[f * ops.grid_node_count + node] && !rigid(f));
  }
  // Σ over side B of a node field.
  Eigen::Vector3d side_b(const Field& x, int a, int b) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int f = 0; f < ops.fields; ++f)
      if (in_b(f, a, b))
        sum += row3(x, f * ops.grid_node_count + node);
    return sum;
  }
  double mass_b(int a, int b) const {
    double m = 0;
    for (int f = 0; f < ops.fields; ++f)
      if (in_b(f, a, b))
        m += ops.m[f * ops.grid_node_count + node];
    return m;
  }
  // Class of cloud entry k: −1 on side A, +1 on side B, 0 otherwise.
  double cls(Index k, int a, int b) const {
    const int f = cn.cloud[size_t(k)].second;
    return f == a ? -1.0 : (in_b(f, a, b) ? 1.0 : 0.0);
  }
  Eigen::Vector3d relative(Index k) const {
    const int p = cn.cloud[size_t(k)].first;
    Eigen::Vector3d x = -grid.node_position(node);
    for (int c = 0; c < ops.dim; ++c)
      x[c] += P.X(p, c);
    return x;
  }

  bool rigid(int f) const { return f >= 0 && !cn.rigid.empty() && cn.rigid[size_t(f)] != 0; }

  // The outward normal of rigid field r at this node: Σ_j m^r_j g^r_j over the node and its 3^d
  // neighbours j, normalised (g^r_j = Σ_{p∈r} G_pj V_p). Each g^r_j points out of the rigid
  // body's particles toward node j; weighting by m^r_j lets the nodes where the body has mass
  // decide, so that a node the body barely reaches (one particle's sliver of support) takes
  // the normal of the surface near it rather than the direction from that particle. At a node
  // with velocity conditions g^r_j counts in the directions they leave free: a face of the body
  // on a roller (a symmetry plane) is not a surface to contact. Without that, a piston between
  // rollers took normals tilted 30–45° toward them one row inside, and a shocked bar slid
  // into it there (tests/cli/test_shock.py).
  Eigen::Vector3d rigid_outward(int r) const {
    const Index ng = ops.grid_node_count;
    const std::array<int, 3> ijk = grid.node_ijk(node);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const int span[3] = {1, grid.dim() > 1 ? 1 : 0, grid.dim() > 2 ? 1 : 0};
    for (int dk = -span[2]; dk <= span[2]; ++dk)
      for (int dj = -span[1]; dj <= span[1]; ++dj)
        for (int di = -span[0]; di <= span[0]; ++di) {
          const int q[3] = {ijk[0] + di, ijk[1] + dj, ijk[2] + dk};
          bool inside = true;
          for (int a = 0; a < grid.dim(); ++a)
            inside =
                inside && q[a] >= grid.first_node(a) && q[a] < grid.first_node(a) + grid.nodes(a);
          if (!inside)
            continue;
          const Index j = grid.node_index(q[0], q[1], q[2]), row = r * ng + j;
          const int k = cn.fixed.empty() ? -1 : cn.fixed[size_t(j)];
          sum +=
              ops.m[row] * (k < 0 ? row3(cn.gradient, row)
                                  : Eigen::Vector3d(cn.free[size_t(k)] * row3(cn.gradient, row)));
        }
    return unit_or_zero(sum);
  }

  // n̂ from A to B: specified, AG (contact 2020 Eq. 13) or LR (Eqs. 19–21). Against a rigid
  // field (rigid.hpp), AG and LR take the rigid body's outward normal (rigid_outward; NairnMPM
  // too can take the rigid material's volume gradient, MeshInfo rigidGradientBias): its
  // surface is undeformed, and with its infinite mass in contact a normal fitted to the two
  // clouds at a node it barely reaches (a block's corner on a rigid slab, where the fit tilts
  // to the block's end face) would give that wrong normal the whole impulse. Measured on a
  // block sliding on a rigid slab at 25° and 35°: the fitted normals lost up to 40% of
  // g(sin θ − μ cos θ) with CPDI, the rigid body's normal 2% (tests/lib/test_rigid.cpp).
  Eigen::Vector3d normal(const ContactPair& pair, int a, int b) const {
    const Index ng = ops.grid_node_count;
    if (pair.normal != ContactNormal::Specified && b >= 0 && rigid(a) != rigid(b))
      return rigid(a) ? rigid_outward(a) : Eigen::Vector3d(-rigid_outward(b));
    switch (pair.normal) {
    case ContactNormal::Specified:
      return pair.first == a ? pair.direction : Eigen::Vector3d(-pair.direction);
    case ContactNormal::AverageGradient:
      return unit_or_zero(row3(cn.gradient, a * ng + node) - side_b(cn.gradient, a, b));
    case ContactNormal::LogisticRegression: {
      const Index first = cn.cloud_offset[size_t(cloud)];
      const Index count = cn.cloud_offset[size_t(cloud) + 1] - first;
      return detail::logistic_fit(
                 ops.dim, count, [&](Index k) { return relative(first + k); },
                 [&](Index k) { return cls(first + k, a, b); }, grid.min_cell_size())
          .normal;
    }
    }
    return Eigen::Vector3d::Zero();
  }

  // CP: (x^B − x^A)·n̂ − δ_c h_n (Eq. 16); DF: (−d(−s^B) − d(s^A)) h_n, s = (x − x_i)·n̂/h_n
  // (Eq. 15); LR: d_LR = min_B(X·n̂ − R_p) − max_A(X·n̂ + R_p) (Eqs. 22–25); −1 (touching)
  // for the other criteria.
  double separation(const ContactPair& pair, int a, int b, const Eigen::Vector3d& n) const {
    const Index ng = ops.grid_node_count;
    if (pair.detection == ContactDetection::Position ||
        pair.detection == ContactDetection::DistanceFunction) {
      const Eigen::Vector3d xa = row3(cn.position, a * ng + node) / ops.m[a * ng + node];
      const Eigen::Vector3d xb = side_b(cn.position, a, b) / mass_b(a, b);
      const double h = cell_width_along(grid, n);
      if (pair.detection == ContactDetection::Position)
        return (xb - xa).dot(n) - pair.critical_separation * h;
      if (!(h > 0))
        return 1; // no normal: no separation along it
      const Eigen::Vector3d xi = grid.node_position(node);
      const double sa = (xa - xi).dot(n) / h, sb = (xb - xi).dot(n) / h;
      return -h * (distance_function_edge(-sb, pair.df_exponent, pair.df_reach) +
                   distance_function_edge(sa, pair.df_exponent, pair.df_reach));
    }
    if (pair.detection != ContactDetection::LogisticRegression)
      return -1;
    double max_a = -std::numeric_limits<double>::infinity();
    double min_b = std::numeric_limits<double>::infinity();
    const int d = ops.dim;
    for (Index k = cn.cloud_offset[size_t(cloud)]; k < cn.cloud_offset[size_t(cloud) + 1]; ++k) {
      const double c = cls(k, a, b);
      if (c == 0)
        continue;
      const int p = cn.cloud[size_t(k)].first;
      const double s = relative(k).dot(n);
      const double r =
          particle_radius_along(d, P.F.data() + p * P.F.outerStride(),
                                P.half_length.data() + p * P.half_length.outerStride(), n);
      if (c < 0)
        max_a = std::max(max_a, s + r);
      else
        min_b = std::min(min_b, s - r);
    }
    return min_b - max_a; // +inf if a side has no particle here: not touching
  }
};

// The projectors onto the directions left free by the velocity conditions on each node they
// act on (find_contact_nodes): I − Σ b̂ b̂ᵀ over an orthonormal basis b̂ of the fixed directions
// (the conditions on a node are parallel or perpendicular, boundary.hpp); the contact nodes
// among them take theirs (Node::constrained). A condition on one field (a rigid material's,
// rigid.hpp) leaves the others free: it is the contact partner's motion.
void free_directions(const Grid& grid, const BoundaryConditions& bcs, ContactNodes& cn) {
  cn.free.clear();
  cn.fixed.assign(cn.slot.size(), -1);
  for (const VelocityCondition& bc : bcs.conditions) {
    if (bc.field >= 0)
      continue;
    for (Index whole : bc.nodes) {
      const Index i = grid.node_of_whole(whole); // the conditions name nodes of the whole grid
      if (i < 0 || i >= Index(cn.fixed.size()))
        continue;
      int& k = cn.fixed[size_t(i)];
      if (k < 0) {
        k = int(cn.free.size());
        cn.free.push_back(Eigen::Matrix3d::Identity());
        if (const int c = cn.slot[size_t(i)]; c >= 0)
          cn.nodes[size_t(c)].constrained = k;
      }
      Eigen::Matrix3d& free = cn.free[size_t(k)];
      // The part not fixed already; below 1e-4 the direction is one already fixed (parallel
      // within the 4.5e-5 rad that check_superposition accepts as parallel).
      const Eigen::Vector3d b = free * bc.direction;
      if (b.norm() > 1e-4)
        free -= b.normalized() * b.normalized().transpose();
    }
  }
}

// The particles whose shape functions reach each contact node (any field), with their fields:
// the LR point clouds (contact 2020 §3.1), gathered from S's column index (each column lists its
// particles in ascending order) node by node in parallel: count, offsets, fill. A particle has
// entries in its own field's columns only, so a node's cloud sorted by particle is the order of
// a pass over the rows of S, whatever the number of threads.
void build_clouds(const Operators& ops, const ParticleOperators& op, ContactNodes& cn) {
  SMPM_VERIFY(op.col_entry && op.col_row,
              "contact nodes: the column lists of S are built for several velocity fields");
  const Index ng = ops.grid_node_count, nc = Index(cn.nodes.size());
  auto each = [&](Index c, auto&& visit) { // the entries S_pi ≠ 0 of node c, field by field
    const Index i = cn.nodes[size_t(c)].node;
    for (int f = 0; f < ops.fields; ++f)
      for (int t = op.col_outer[f * ng + i]; t < op.col_outer[f * ng + i + 1]; ++t)
        if (op.S[op.col_entry[t]] != 0)
          visit(int(op.col_row[t] - op.first), f);
  };
  cn.cloud_offset.assign(size_t(nc) + 1, 0);
  detail::parallel_for(
      nc,
      [&](Index c) {
        Index count = 0;
        each(c, [&](int, int) { ++count; });
        cn.cloud_offset[size_t(c) + 1] = count;
      },
      op.rows);
  for (Index c = 0; c < nc; ++c)
    cn.cloud_offset[size_t(c) + 1] += cn.cloud_offset[size_t(c)];
  cn.cloud.resize(size_t(cn.cloud_offset[size_t(nc)]));
  detail::parallel_for(
      nc,
      [&](Index c) {
        std::pair<int, int>* out = cn.cloud.data() + cn.cloud_offset[size_t(c)];
        Index k = 0;
        each(c, [&](int p, int f) { out[k++] = {p, f}; });
        std::sort(out, out + k);
      },
      op.rows);
}

} // namespace

namespace {

// The nodes seen by two or more fields (a = b = −1 for three or more), and their slots.
void collect_contact_nodes(const Operators& ops, ContactNodes& cn) {
  const int nf = ops.fields;
  const Index ng = ops.grid_node_count;
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
    node.a = count > 2 ? -1 : a;
    node.b = count > 2 ? -1 : b;
    cn.nodes.push_back(node);
  }
  cn.slot.assign(size_t(ng), -1);
  for (size_t c = 0; c < cn.nodes.size(); ++c)
    cn.slot[size_t(cn.nodes[c].node)] = int(c);
}

// n̂ ← P n̂ / |P n̂| with P the node's projector onto its free directions.
Eigen::Vector3d constrained_normal(const ContactNodes& cn, const ContactNodes::Node& node,
                                   const Eigen::Vector3d& n) {
  return node.constrained < 0 ? n : unit_or_zero(cn.free[size_t(node.constrained)] * n);
}

// Contact 2020 §3.4, Eq. (50): at a node of three or more fields, each field against the others
// lumped, with the law of the heaviest other field.
void lumped_sides(const Operators& ops, const Contact& contact, const NodeGeometry& geo,
                  ContactNodes& cn, ContactNodes::Node& node) {
  const int nf = ops.fields;
  const Index ng = ops.grid_node_count;
  // The rigid field holding most of the node's particle volume, if it holds kRigidShare of it:
  // every other field contacts that body alone (ContactNodes::Side::rigid). A rigid field has no
  // side of its own, and one below the share is no contact partner here (as at a node of two
  // fields): the other fields are lumped among themselves.
  const bool any_rigid = std::find(cn.rigid.begin(), cn.rigid.end(), 1) != cn.rigid.end();
  int largest = -1, deformable = 0;
  double total = 0, most = 0;
  for (int f = 0; f < nf; ++f)
    if (ops.active[f * ng + node.node]) {
      deformable += !geo.rigid(f);
      if (!any_rigid) // cn.volume is computed with rigid fields only
        continue;
      const double v = cn.volume[f * ng + node.node];
      total += v;
      if (geo.rigid(f) && v > most) {
        most = v;
        largest = f;
      }
    }
  const bool share = largest >= 0 && most >= kRigidShare * total;
  for (int f = 0; f < nf; ++f) {
    ContactNodes::Side side;
    // The body this field meets alone: above the share, or bonded to it (detection "always",
    // as at a node of two fields).
    const int body =
        largest >= 0 && !geo.rigid(f) &&
                (share || contact.pair(f, largest).detection == ContactDetection::Always)
            ? largest
            : -1;
    if (!ops.active[f * ng + node.node] || geo.rigid(f)) {
      // no side: inactive, or a rigid body (the others' contact with it is theirs)
    } else if (body >= 0) {
      side.rigid = body;
      side.pair = &contact.pair(f, body);
      side.normal = constrained_normal(cn, node, geo.normal(*side.pair, f, body));
      side.separation = geo.separation(*side.pair, f, body, side.normal);
    } else if (deformable > 1) {
      int heaviest = -1;
      for (int o = 0; o < nf; ++o)
        if (o != f && !geo.rigid(o) && ops.active[o * ng + node.node] &&
            (heaviest < 0 || ops.m[o * ng + node.node] > ops.m[heaviest * ng + node.node]))
          heaviest = o;
      side.pair = &contact.pair(f, heaviest);
      side.normal = constrained_normal(cn, node, geo.normal(*side.pair, f, -1));
      side.separation = geo.separation(*side.pair, f, -1, side.normal);
    }
    cn.sides[size_t(node.first_side + f)] = side;
  }
}

} // namespace

void find_contact_nodes(const Grid& grid, const Operators& ops, const ParticleOperators& op,
                        const Contact& contact, const ContactParticles& P, ContactNodes& cn,
                        const BoundaryConditions* bcs) {
  cn.nodes.clear();
  cn.sides.clear();
  cn.friction_work = 0;
  if (ops.fields < 2)
    return;
  const bool rigid = std::find(cn.rigid.begin(), cn.rigid.end(), 1) != cn.rigid.end();
  if (uses(contact, ContactNormal::AverageGradient) || rigid) // rigid: NodeGeometry::normal
    volume_gradient(op, P.volume, cn.gradient);
  SMPM_VERIFY(op.col_entry && op.col_row,
              "contact nodes: the column lists of S are built for several velocity fields");
  if (rigid) { // Σ_p S_pi V_p per field row, in particle order: the rigid share of a node
    cn.volume.resize(op.nodes);
    detail::parallel_for(op.nodes, [&](Index i) {
      double sum = 0;
      for (int t = op.col_outer[i]; t < op.col_outer[i + 1]; ++t)
        sum += op.S[op.col_entry[t]] * P.volume[op.col_row[t] - op.first];
      cn.volume[i] = sum;
    });
  }
  if (uses(contact, ContactDetection::Position) ||
      uses(contact, ContactDetection::DistanceFunction))
    map_momentum(op, P.X, cn.position); // Σ_{p∈α} S_pi M_p X_p
  collect_contact_nodes(ops, cn);
  if (bcs) {
    free_directions(grid, *bcs, cn);
  } else {
    cn.free.clear();
    cn.fixed.clear();
  }
  if (uses(contact, ContactNormal::LogisticRegression) ||
      uses(contact, ContactDetection::LogisticRegression))
    build_clouds(ops, op, cn);
  const double vcell = cell_volume(grid);
  // Each node's normal, separation and area in parallel (they read the clouds and the node
  // fields only); a node of three or more fields has a side per field, laid out first.
  Index sides = 0;
  for (ContactNodes::Node& node : cn.nodes)
    if (node.a < 0) {
      node.first_side = sides;
      sides += ops.fields;
    }
  cn.sides.assign(size_t(sides), ContactNodes::Side{});
  detail::parallel_for(
      Index(cn.nodes.size()),
      [&](Index c) {
        ContactNodes::Node& node = cn.nodes[size_t(c)];
        const NodeGeometry geo{grid, ops, cn, P, node.node, c};
        if (node.a < 0) {
          lumped_sides(ops, contact, geo, cn, node);
          return;
        }
        node.pair = &contact.pair(node.a, node.b);
        node.normal = constrained_normal(cn, node, geo.normal(*node.pair, node.a, node.b));
        node.separation = geo.separation(*node.pair, node.a, node.b, node.normal);
        if (geo.rigid(node.a) != geo.rigid(node.b) &&
            node.pair->detection != ContactDetection::Always) {
          // A rigid partner only where it holds kRigidShare of the node's particle volume
          // (ContactNodes::rigid): a node it barely reaches is not on its surface.
          const Index ng = ops.grid_node_count;
          const double vr = cn.volume[(geo.rigid(node.a) ? node.a : node.b) * ng + node.node];
          const double vo = cn.volume[(geo.rigid(node.a) ? node.b : node.a) * ng + node.node];
          if (!(vr >= kRigidShare * (vr + vo)))
            node.separation = std::numeric_limits<double>::infinity();
        }
        const double h = cell_width_along(grid, node.normal);
        node.area = h > 0 ? vcell / h : 0;
      },
      op.rows);
}

} // namespace smpm
