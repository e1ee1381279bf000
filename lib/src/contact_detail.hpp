// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Helpers shared by the contact sources (internal to sparsempm): contact.cpp (nodes, laws, the
// lumped and incremental corrections) and contact_exact.cpp (the exact update's contact).

#include "sparsempm/contact.hpp"

namespace smpm::detail {

/// Row r of an n × d field as a 3-vector (zeros beyond d).
Eigen::Vector3d row3(const Field& f, Index r);

/// The separation at the end of the step if the two sides keep their velocities:
/// δ + Δt Δp(0)·n̂ / m_red (contact.cpp).
double gap_at_step_end(double separation, const Eigen::Vector3d& dp0, const Eigen::Vector3d& n,
                       double ma, double mb, double dt);

} // namespace smpm::detail
