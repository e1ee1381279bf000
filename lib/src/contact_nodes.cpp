// SPDX-License-Identifier: BSD-3-Clause
// Contact nodes (contact.hpp, find_contact_nodes): the nodes two or more velocity fields share,
// with their normals (AG, LR, the axes), separations (CP, DF, LR), contact areas and the
// directions their velocity conditions leave free (contact 2020 §3.1–3.4, FMPM 2026 §3.2). The
// normal and separation at one node are in contact_geometry.cpp; the laws and the momentum
// corrections that use them in contact.cpp.

#include "sparsempm/contact.hpp"

#include "contact_geometry.hpp"
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

using detail::cell_width_along;
using detail::NodeGeometry;
using detail::unit_or_zero;

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

double cell_volume(const Grid& grid) {
  double v = 1;
  for (int a = 0; a < grid.dim(); ++a)
    v *= grid.cell_size(a);
  return v;
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

// The node fields the normals and separations read: the volume gradients (AG, and a rigid
// body's normal, NodeGeometry::normal), with a rigid field each field's particle volume
// Σ_p S_pi V_p per field row, in particle order (the rigid share of a node), and for CP and DF
// Σ_{p∈α} S_pi M_p X_p.
void node_fields(const ParticleOperators& op, const Contact& contact, const ContactParticles& P,
                 ContactNodes& cn) {
  const bool rigid = std::find(cn.rigid.begin(), cn.rigid.end(), 1) != cn.rigid.end();
  if (uses(contact, ContactNormal::AverageGradient) || rigid)
    volume_gradient(op, P.volume, cn.gradient);
  SMPM_VERIFY(op.col_entry && op.col_row,
              "contact nodes: the column lists of S are built for several velocity fields");
  if (rigid) {
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
    map_momentum(op, P.X, cn.position);
}

// The sides of the nodes of three or more fields, one per field, laid out first.
void lay_out_sides(const Operators& ops, ContactNodes& cn) {
  Index sides = 0;
  for (ContactNodes::Node& node : cn.nodes)
    if (node.a < 0) {
      node.first_side = sides;
      sides += ops.fields;
    }
  cn.sides.assign(size_t(sides), ContactNodes::Side{});
}

// A node of two fields: the normal and separation of their pair, and its contact area
// A_c = V_cell / h_n.
void pair_node(const Contact& contact, const NodeGeometry& geo, const ContactNodes& cn,
               ContactNodes::Node& node, double vcell) {
  node.pair = &contact.pair(node.a, node.b);
  node.normal = constrained_normal(cn, node, geo.normal(*node.pair, node.a, node.b));
  node.separation = geo.separation(*node.pair, node.a, node.b, node.normal);
  if (geo.rigid(node.a) != geo.rigid(node.b) && node.pair->detection != ContactDetection::Always) {
    // A rigid partner only where it holds kRigidShare of the node's particle volume
    // (ContactNodes::rigid): a node it barely reaches is not on its surface.
    const Index ng = geo.ops.grid_node_count;
    const double vr = cn.volume[(geo.rigid(node.a) ? node.a : node.b) * ng + node.node];
    const double vo = cn.volume[(geo.rigid(node.a) ? node.b : node.a) * ng + node.node];
    if (!(vr >= kRigidShare * (vr + vo)))
      node.separation = std::numeric_limits<double>::infinity();
  }
  const double h = cell_width_along(geo.grid, node.normal);
  node.area = h > 0 ? vcell / h : 0;
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
  node_fields(op, contact, P, cn);
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
  lay_out_sides(ops, cn);
  // Each node's normal, separation and area in parallel (they read the clouds and the node
  // fields only).
  detail::parallel_for(
      Index(cn.nodes.size()),
      [&](Index c) {
        ContactNodes::Node& node = cn.nodes[size_t(c)];
        const NodeGeometry geo{grid, ops, cn, P, node.node, c};
        if (node.a < 0)
          lumped_sides(ops, contact, geo, cn, node);
        else
          pair_node(contact, geo, cn, node, vcell);
      },
      op.rows);
}

} // namespace smpm
