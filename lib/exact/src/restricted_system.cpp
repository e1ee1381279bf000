// SPDX-License-Identifier: BSD-3-Clause
// The equations of the exact solve (restricted_system.hpp) and its known values
// (prescribed_components of exact.hpp).
#include "restricted_system.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/exact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace smpm {

namespace {
int axis_of(const VelocityCondition& c, int d) {
  for (int a = 0; a < d; ++a)
    if (std::abs(std::abs(c.direction[a]) - 1) < 1e-12)
      return a;
  throw InputError("the exact velocity update supports velocity conditions along axes only ('" +
                   c.label + "' is not)");
}
} // namespace

Field prescribed_components(const LoopConstraints& bc,
                            const Eigen::Array<bool, Eigen::Dynamic, 1>& active,
                            const Eigen::VectorXd& m, const Field& p, double light) {
  const Index n = active.size();
  const int d = int(p.cols());
  Field prescribed = Field::Constant(n, d, std::numeric_limits<double>::quiet_NaN());
  if (bc.bcs && !bc.bcs->conditions.empty()) {
    // Conditions along axes only; a direction within round-off of an axis is taken as the axis.
    const BoundaryConditions* bcs = bc.bcs;
    BoundaryConditions snapped;
    for (const VelocityCondition& cond : bc.bcs->conditions) {
      const int a = axis_of(cond, d);
      const Eigen::Vector3d axis = (cond.direction[a] > 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a);
      if (cond.direction.head(d) != axis.head(d) && bcs == bc.bcs) {
        snapped = *bc.bcs;
        bcs = &snapped;
      }
    }
    if (bcs == &snapped)
      for (VelocityCondition& cond : snapped.conditions) {
        const int a = axis_of(cond, d);
        cond.direction = (cond.direction[a] > 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a);
      }
    Field values = Field::Zero(n, d), fixed = Field::Ones(n, d);
    bcs->constrain_velocity(*bc.grid, bc.time, values, &active);
    bcs->zero_directions(*bc.grid, fixed);
    for (Index i = 0; i < n; ++i)
      for (int a = 0; a < d; ++a)
        if (active[i] && fixed(i, a) == 0)
          prescribed(i, a) = values(i, a);
  }
  if (light > 0)
    for (Index i = 0; i < n; ++i)
      if (active[i] && m[i] < light)
        for (int a = 0; a < d; ++a)
          if (std::isnan(prescribed(i, a)))
            prescribed(i, a) = p(i, a) * (1.0 / m[i]);
  return prescribed;
}

namespace detail {

std::string lightest_nodes(const Operators& ops, const std::vector<int>& free, NodalSystem system) {
  const bool heat = system == NodalSystem::ConsistentCapacity;
  std::vector<int> order(free);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return ops.m[a] < ops.m[b]; });
  std::ostringstream os;
  os << (heat ? "smallest lumped capacities: " : "smallest lumped masses: ");
  for (size_t k = 0; k < std::min<size_t>(3, order.size()); ++k)
    os << (k ? ", " : "") << ops.node_text(order[k]) << (heat ? " (c = " : " (m = ")
       << ops.m[order[k]] << ")";
  return os.str();
}

namespace {
// The remedies of a singular velocity system whose matrix is `name` (m~, m~_L or m~_A).
std::string velocity_remedies(const char* name) {
  return std::string(" (set step.exact_mass_cutoff > 0 to give light nodes their lumped velocity, "
                     "or step.exact_regularization > 0 to factor (1 - eps) ") +
         name + " + eps m)";
}
} // namespace

std::string remedies(NodalSystem system) {
  switch (system) {
  case NodalSystem::ConsistentCapacity: // c~ = S^T C S is singular where S v = 0 for some v
    return " (c~ = S^T C S is singular where fewer particles reach a group of nodes than it has "
           "nodes: set step.exact_regularization > 0 to factor (1 - eps) c~ + eps c, positive "
           "definite for every eps > 0, or step.exact_mass_cutoff > 0 to give light nodes their "
           "lumped temperature, which cures it only where those nodes are the light ones)";
  case NodalSystem::GradientMass:
    return velocity_remedies("m~_L");
  case NodalSystem::ApicMass:
    return velocity_remedies("m~_A");
  case NodalSystem::ConsistentMass:
    break;
  }
  return velocity_remedies("m~");
}

std::vector<std::pair<std::vector<int>, std::vector<int>>> free_groups(const Operators& ops,
                                                                       const Field& prescribed) {
  std::vector<std::pair<std::vector<int>, std::vector<int>>> groups; // (F, components)
  for (int a = 0; a < int(prescribed.cols()); ++a) {
    std::vector<int> F;
    for (Index i = 0; i < ops.num_nodes(); ++i)
      if (ops.active[i] && std::isnan(prescribed(i, a)))
        F.push_back(int(i));
    auto same =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == F; });
    if (same != groups.end())
      same->second.push_back(a);
    else
      groups.push_back({std::move(F), {a}});
  }
  return groups;
}

bool restrict_matrix(const Operators& ops, const SparseRowMatrix& mt, double regularization,
                     const std::vector<int>& local, Restricted& f, const std::vector<int>& F,
                     bool factored) {
  std::vector<int> colptr(F.size() + 1, 0), rowind;
  std::vector<double> values;
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  for (size_t k = 0; k < F.size(); ++k) {
    const int j = F[k];
    for (int q = ro[j]; q < ro[j + 1]; ++q)
      if (local[size_t(ri[q])] >= 0) {
        rowind.push_back(local[size_t(ri[q])]);
        values.push_back((1 - regularization) * rv[q] +
                         (ri[q] == j ? regularization * ops.m[j] : 0.0));
      }
    colptr[k + 1] = int(rowind.size());
  }
  const bool same_pattern = factored && f.free == F && f.colptr == colptr && f.rowind == rowind;
  f.free = F;
  f.colptr.swap(colptr);
  f.rowind.swap(rowind);
  f.values.swap(values);
  return same_pattern;
}

Eigen::MatrixXd symmetric_right_hand_sides(const Operators& ops, const SparseRowMatrix& mt,
                                           double blend, const Field& p, const Field& prescribed,
                                           const std::vector<int>& F, const std::vector<int>& local,
                                           const std::vector<int>& comps, Field& v) {
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  Eigen::MatrixXd B(F.size(), comps.size());
  for (size_t k = 0; k < comps.size(); ++k) {
    const int comp = comps[k];
    for (size_t q = 0; q < F.size(); ++q)
      B(Index(q), Index(k)) = p(F[q], comp);
    for (Index i = 0; i < ops.num_nodes(); ++i) {
      const double vc = prescribed(i, comp);
      if (!ops.active[i] || std::isnan(vc))
        continue;
      v(i, comp) = vc;
      for (int q = ro[i]; q < ro[i + 1]; ++q)
        if (const int l = local[size_t(ri[q])]; l >= 0)
          B(l, Index(k)) -= blend * rv[q] * vc;
    }
  }
  return B;
}

Eigen::MatrixXd general_right_hand_sides(const SparseRowMatrix& mt, double blend, const Field& p,
                                         const Field& prescribed, const std::vector<int>& F,
                                         const std::vector<int>& comps, Field& v) {
  const int* ro = mt.outerIndexPtr();
  const int* ri = mt.innerIndexPtr();
  const double* rv = mt.valuePtr();
  for (const int comp : comps)
    for (Index i = 0; i < prescribed.rows(); ++i)
      if (!std::isnan(prescribed(i, comp)))
        v(i, comp) = prescribed(i, comp);
  Eigen::MatrixXd B(F.size(), comps.size());
  for (size_t k = 0; k < comps.size(); ++k) {
    const int comp = comps[k];
    for (size_t l = 0; l < F.size(); ++l) {
      double b = p(F[l], comp);
      for (int q = ro[F[l]]; q < ro[F[l] + 1]; ++q)
        if (const double vc = prescribed(ri[q], comp); !std::isnan(vc))
          b -= blend * rv[q] * vc;
      B(Index(l), Index(k)) = b;
    }
  }
  return B;
}

} // namespace detail

} // namespace smpm
