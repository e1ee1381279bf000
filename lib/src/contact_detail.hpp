// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Helpers shared by the contact sources (internal to sparsempm): contact.cpp (nodes, laws, the
// lumped and incremental corrections) and contact_exact.cpp (the exact update's contact).

#include "sparsempm/contact.hpp"

namespace smpm::detail {

/// Row r of an n × d field as a 3-vector (zeros beyond d).
Eigen::Vector3d row3(const Field& f, Index r);

/// The masses of a contact node's two sides α, β. The field of a rigid material (rigid.hpp)
/// has infinite mass in contact: its velocity is prescribed, so the other side alone takes the
/// momentum change, m_red = m of the other side and Δp(0) = m_red (v^β − v^α).
struct SideMasses {
  double ma = 0, mb = 0;                 ///< m^α, m^β
  bool rigid_a = false, rigid_b = false; ///< whether α, β is a rigid field
  /// m^α m^β / (m^α + m^β), or the mass of the side that is not rigid.
  double reduced() const { return rigid_b ? ma : rigid_a ? mb : ma * mb / (ma + mb); }
  /// Δp(0) = (m^α p^β − m^β p^α)/(m^α + m^β): the change of α's momentum that takes both
  /// sides to their centre-of-mass velocity (the rigid side's velocity if one is rigid).
  Eigen::Vector3d centre_of_mass_change(const Eigen::Vector3d& pa,
                                        const Eigen::Vector3d& pb) const {
    if (rigid_a || rigid_b)
      return reduced() * (pb / mb - pa / ma);
    return (ma * pb - mb * pa) / (ma + mb);
  }
  /// Whether both sides are rigid: two prescribed motions, no contact between them.
  bool both_rigid() const { return rigid_a && rigid_b; }
};

/// The masses of contact node c's fields a, b from ops.m and cn.rigid.
SideMasses side_masses(const Operators& ops, const ContactNodes& cn, Index node, int a, int b);

/// The separation at the end of the step if the two sides keep their velocities:
/// δ + Δt Δp(0)·n̂ / m_red (contact.cpp).
double gap_at_step_end(double separation, const Eigen::Vector3d& dp0, const Eigen::Vector3d& n,
                       const SideMasses& m, double dt);

} // namespace smpm::detail
