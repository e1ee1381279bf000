// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/rigid.hpp"

#include "sparsempm/fmpm.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace smpm {

Eigen::Vector3d RigidMotion::at(double t) const {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    if (!velocity[size_t(a)])
      continue;
    v[a] = velocity[size_t(a)](t);
    if (!std::isfinite(v[a]))
      throw NumericalError(label + ".velocity[" + std::to_string(a) + "] is " + number_text(v[a]) +
                           " at t = " + number_text(t));
  }
  return v;
}

Eigen::Vector3d rigid_velocity(const RigidMotion& m, const Particles& P, double t,
                               const NodeSums* sums) {
  if (!m.free)
    return m.at(t);
  double s[4] = {0, 0, 0, 0}; // Σ M_p V_p, Σ M_p
  for (Index p = 0; p < P.size(); ++p)
    if (P.material[p] == m.material) {
      s[3] += P.mass[p];
      for (int a = 0; a < P.dim; ++a)
        s[a] += P.mass[p] * P.V(p, a);
    }
  if (sums)
    sums->sum(s, 4);
  return s[3] > 0 ? Eigen::Vector3d(Eigen::Vector3d(s[0], s[1], s[2]) / s[3])
                  : Eigen::Vector3d::Zero();
}

void rigid_fields(const std::vector<RigidMotion>& motions, const std::vector<int>& material_field,
                  int fields, std::vector<char>& rigid) {
  rigid.assign(size_t(fields), 0);
  for (const RigidMotion& m : motions)
    if (m.material >= 0 && size_t(m.material) < material_field.size())
      rigid[size_t(material_field[size_t(m.material)])] = 1;
}

void add_rigid_conditions(const std::vector<RigidMotion>& motions, const Particles& P,
                          const std::vector<int>& material_field, const Operators& ops, double t,
                          BoundaryConditions& step, const NodeSums* sums) {
  if (motions.empty())
    return;
  const int d = ops.grid.dim();
  const Index ng = ops.grid_node_count;
  const SparseRowMatrix& S = ops.S;
  for (const RigidMotion& m : motions) {
    // Multimaterial: the material's own field, a contact partner (contact.hpp); else all fields.
    const int field = ops.fields > 1 && size_t(m.material) < material_field.size()
                          ? material_field[size_t(m.material)]
                          : -1;
    std::vector<Index> nodes;
    if (sums) { // the columns any process's particles of the material reach, summed
      Field reached = Field::Zero(ops.num_nodes(), 1);
      for (Index p = 0; p < S.rows(); ++p)
        if (P.material[p] == m.material)
          for (SparseRowMatrix::InnerIterator it(S, p); it; ++it)
            if (it.value() > 0)
              reached(it.col(), 0) = 1;
      sums->add(reached);
      for (Index c = 0; c < reached.rows(); ++c)
        if (reached(c, 0) > 0)
          nodes.push_back(ops.grid.whole_node(c % ng));
    } else {
      for (Index p = 0; p < S.rows(); ++p) {
        if (P.material[p] != m.material)
          continue;
        for (SparseRowMatrix::InnerIterator it(S, p); it; ++it)
          if (it.value() > 0)
            nodes.push_back(ops.grid.whole_node(it.col() % ng)); // conditions name whole nodes
      }
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    const Eigen::Vector3d v = rigid_velocity(m, P, t, sums);
    for (int a = 0; a < d; ++a) {
      // A node another condition on the same fields already sets along this axis keeps that
      // condition alone (parallel conditions would add their values): the earlier ones win.
      std::vector<Index> taken;
      for (const VelocityCondition& other : step.conditions)
        if ((other.field < 0 || other.field == field) &&
            std::abs(std::abs(other.direction[a]) - 1) < 1e-12)
          taken.insert(taken.end(), other.nodes.begin(), other.nodes.end());
      std::sort(taken.begin(), taken.end());
      VelocityCondition c;
      std::set_difference(nodes.begin(), nodes.end(), taken.begin(), taken.end(),
                          std::back_inserter(c.nodes));
      c.direction = Eigen::Vector3d::Unit(a);
      c.label = m.label + "." + std::string(1, "xyz"[a]);
      c.field = field;
      c.value = [value = v[a]](double, const Eigen::Vector3d&) { return value; };
      step.conditions.push_back(std::move(c));
    }
  }
  step.check_superposition();
}

void check_rigid_motions(const std::vector<RigidMotion>& motions,
                         const std::vector<int>& material_field, const StepOptions& options) {
  for (const RigidMotion& m : motions) {
    if (!material_field.empty()) {
      const int field = material_field.at(size_t(m.material));
      for (size_t other = 0; other < material_field.size(); ++other)
        if (int(other) != m.material && material_field[other] == field)
          throw InputError(m.label + ".model: a rigid material needs a velocity field of its " +
                           "own (it shares one with material " + std::to_string(other) +
                           ": single-field)");
    }
    if (!m.free)
      continue;
    if (material_field.empty())
      throw InputError(m.label + ".free: a free rigid body needs multimaterial mode (a " +
                       "[[contact]] table giving it a velocity field of its own)");
    if (options.velocity != VelocityUpdate::FLIP && options.velocity != VelocityUpdate::PIC)
      throw InputError(m.label +
                       ".free: a free rigid body needs step.velocity = FLIP or PIC (the " +
                       "contact corrections of FMPM, XPIC and exact do not reach its reaction)");
    if (options.bc_ordering != BCOrdering::Correct)
      throw InputError(m.label + ".free: a free rigid body needs the correct BC ordering (its " +
                       "reactions)");
  }
}

void start_rigid_motion(const std::vector<RigidMotion>& motions, double t, Particles& P,
                        std::vector<Eigen::Vector3d>& velocity, const NodeSums* sums) {
  velocity.resize(motions.size());
  for (size_t k = 0; k < motions.size(); ++k) {
    const RigidMotion& m = motions[k];
    velocity[k] = rigid_velocity(m, P, t, sums);
    if (m.free)
      continue;
    for (Index p = 0; p < P.size(); ++p)
      if (P.material[p] == m.material)
        for (int a = 0; a < P.dim; ++a)
          P.V(p, a) = velocity[k][a];
  }
}

void move_rigid_particles(const std::vector<RigidMotion>& motions, const Field& X_start, double t,
                          double dt, const std::vector<Eigen::Vector3d>& velocity,
                          const double* reactions, const double* masses, Particles& P) {
  const int d = P.dim;
  for (size_t k = 0; k < motions.size(); ++k) {
    const RigidMotion& m = motions[k];
    Eigen::Vector3d mid, end;
    if (m.free) {
      const Eigen::Vector3d& v = velocity[k];
      end = v;
      for (int a = 0; a < d; ++a) {
        const size_t c = k * size_t(d) + size_t(a);
        if (masses[c] > 0)
          end[a] -= dt * reactions[c] / masses[c]; // M dv = −R Δt
      }
      if (!end.allFinite())
        throw NumericalError(m.label + ": the free rigid body's velocity is not finite");
      mid = 0.5 * (v + end);
    } else {
      mid = m.at(t + 0.5 * dt);
      end = m.at(t + dt);
    }
    for (Index p = 0; p < P.size(); ++p) {
      if (P.material[p] != m.material)
        continue;
      for (int a = 0; a < d; ++a) {
        P.X(p, a) = X_start(p, a) + dt * mid[a];
        P.V(p, a) = end[a];
      }
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b) {
          P.F(p, a * d + b) = a == b ? 1.0 : 0.0;
          P.stress(p, a * d + b) = 0;
        }
    }
  }
}

} // namespace smpm
