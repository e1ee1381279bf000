// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The geometry of one contact node (internal to sparsempm): the normal from one side to the other
// and their separation, which find_contact_nodes (contact_nodes.cpp) takes for each node; the
// normals and separations are in contact_geometry.cpp.

#include "sparsempm/contact.hpp"
#include "sparsempm/operators.hpp"

#include <Eigen/Core>

namespace smpm::detail {

// h_n = √(Σ_a (n_a Δx_a)²), the cell size along n̂ that NairnMPM uses for the separation
// and the contact area (MeshInfo::GetPerpendicularDistance: exact there for 2D grids and for
// cubic cells; its 3D non-cubic form follows the tangent plane): h_n = Δx on square cells for
// every n̂. A_c = V_cell / h_n only scales tractions: with the laws here it cancels from Δp
// (S_slide A_c Δt = min(Δp(0)·t̂, −μ Δp(0)·n̂)).
double cell_width_along(const Grid& grid, const Eigen::Vector3d& n);

// v/|v|, or 0 when v = 0 (gradients that cancel give no normal).
inline Eigen::Vector3d unit_or_zero(const Eigen::Vector3d& v) {
  const double norm = v.norm();
  return norm > 0 ? Eigen::Vector3d(v / norm) : Eigen::Vector3d::Zero();
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
  Eigen::Vector3d side_b(const Field& x, int a, int b) const;
  double mass_b(int a, int b) const;
  // Class of cloud entry k: −1 on side A, +1 on side B, 0 otherwise.
  double cls(Index k, int a, int b) const;
  // The position of cloud entry k's particle relative to the node.
  Eigen::Vector3d relative(Index k) const;

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
  Eigen::Vector3d rigid_outward(int r) const;

  // n̂ from A to B: specified, AG (contact 2020 Eq. 13) or LR (Eqs. 19–21). Against a rigid
  // field (rigid.hpp), AG and LR take the rigid body's outward normal (rigid_outward; NairnMPM
  // too can take the rigid material's volume gradient, MeshInfo rigidGradientBias): its
  // surface is undeformed, and with its infinite mass in contact a normal fitted to the two
  // clouds at a node it barely reaches (a block's corner on a rigid slab, where the fit tilts
  // to the block's end face) would give that wrong normal the whole impulse. Measured on a
  // block sliding on a rigid slab at 25° and 35°: the fitted normals lost up to 40% of
  // g(sin θ − μ cos θ) with CPDI, the rigid body's normal 2% (tests/lib/test_rigid.cpp).
  Eigen::Vector3d normal(const ContactPair& pair, int a, int b) const;

  // CP: (x^B − x^A)·n̂ − δ_c h_n (Eq. 16); DF: (−d(−s^B) − d(s^A)) h_n, s = (x − x_i)·n̂/h_n
  // (Eq. 15); LR: d_LR = min_B(X·n̂ − R_p) − max_A(X·n̂ + R_p) (Eqs. 22–25); −1 (touching)
  // for the other criteria.
  double separation(const ContactPair& pair, int a, int b, const Eigen::Vector3d& n) const;
};

} // namespace smpm::detail
