// SPDX-License-Identifier: BSD-3-Clause
// The contact nodes of a multimaterial frame in the run file (output.hpp).

#include "output_format.hpp"

#include "sparsempm/contact.hpp"

#include <cmath>
#include <vector>

namespace smpm::detail {

// The contact nodes of a frame (contact.hpp): the grid nodes seen by two or more velocity
// fields, the two fields (−1, −1 for a node of three or more, lumped), the normal n̂ from the
// first to the second, the separation δ of the pair's detection (−1 where it has none) and
// whether the fields approach there, Δp(0)·n̂ < 0 with Δp(0) from the frame's momenta before
// contact. The frame's state: a step from it corrects the approaching nodes whose end-of-step
// gap δ + Δt Δp(0)·n̂/m_red is negative.
void write_contact_nodes(hid_t g, const StepPreparation& prep, const Field& p) {
  const Operators& ops = prep.ops;
  const ContactNodes& cn = prep.contact;
  const Index nc = Index(cn.nodes.size()), ng = ops.grid_node_count;
  const int d = ops.dim;
  std::vector<int> node(static_cast<size_t>(nc)), pair(static_cast<size_t>(2 * nc)),
      approaching(static_cast<size_t>(nc), 0);
  Field normal = Field::Zero(nc, d), position(nc, d);
  Eigen::VectorXd separation = Eigen::VectorXd::Constant(nc, -1);
  for (Index c = 0; c < nc; ++c) {
    const ContactNodes::Node& n = cn.nodes[size_t(c)];
    node[size_t(c)] = int(ops.grid.whole_node(n.node)); // the node's index in the grid
    position.row(c) = ops.grid.node_position(n.node).head(d).transpose();
    pair[size_t(2 * c)] = n.a;
    pair[size_t(2 * c + 1)] = n.b;
    if (n.a < 0)
      continue;
    // +∞: no detection here (a rigid partner under kRigidShare of the node's volume), which
    // the layout writes as none (−1), as for a node of three or more fields.
    separation[c] = std::isfinite(n.separation) ? n.separation : -1.0;
    const Index ra = n.a * ng + n.node, rb = n.b * ng + n.node;
    const double ma = ops.m[ra], mb = ops.m[rb];
    double dn = 0;
    for (int a = 0; a < d; ++a) {
      normal(c, a) = n.normal[a];
      dn += (ma * p(rb, a) - mb * p(ra, a)) / (ma + mb) * n.normal[a];
    }
    approaching[size_t(c)] = dn < 0;
  }
  const hsize_t rows = hsize_t(nc);
  h5::write_ints(g, "contact_nodes", node.data(), rows);
  h5::write_ints(g, "contact_fields", pair.data(), 2 * rows);
  h5::write_doubles(g, "contact_normal", normal.data(), rows, hsize_t(d));
  h5::write_doubles(g, "contact_separation", separation.data(), rows, 0);
  h5::write_ints(g, "contact_approaching", approaching.data(), rows);
  h5::write_doubles(g, "contact_X", position.data(), rows, hsize_t(d));
  if (d == 1)
    write_xyz(g, "contact_xyz", position);
}

} // namespace smpm::detail
