// SPDX-License-Identifier: BSD-3-Clause
// The contact of the exact update in multimaterial mode (FMPM 2026 §3.2 at k → ∞): the fixed
// point of the Net method, solved by active-set passes and conjugate gradients on the contact
// compliance (contact.hpp, exact_contact).

#include "sparsempm/contact.hpp"

#include "contact_detail.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace smpm {

using detail::gap_at_step_end;
using detail::row3;
using detail::side_masses;
using detail::SideMasses;

namespace {

// How a node of two fields takes part in one linear solve of exact_contact.
enum class ExactMode { Apart, Stick, Normal };

constexpr int kMaxOuter = 50, kMaxCg = 1000;

// The state of exact_contact's passes: each node's mode, its first unknown and the law's Δp.
class ExactContact {
public:
  ExactContact(const Operators& ops, ContactNodes& cn, double dt,
               const std::function<void(const Field& r, Field& u)>& respond, Field& p, Field& v)
      : ops_(ops), cn_(cn), dt_(dt), respond_(respond), p_(p), v_(v), nc_(cn.nodes.size()),
        ng_(ops.grid_node_count), d_(int(p.cols())), mode_(nc_, ExactMode::Apart),
        released_(nc_, 0), first_(nc_, -1), law_dp_(nc_, Eigen::Vector3d::Zero()), q_(p.rows(), d_),
        u_(p.rows(), d_), jump_(p.rows(), d_) {}

  // 1. The law at the current state (Eq. 20 summed: Δp(0) = Δp^(net) + m_red (v^β − v^α)): each
  // node's mode and its unknowns. Returns the largest change of a node's impulse. A node released
  // from contact stays apart for the rest of the call: without it, nodes in tension and nodes
  // that approach once released can trade places forever.
  double classify(Index& unknowns) {
    double change = 0;
    unknowns = 0;
    for (size_t c = 0; c < nc_; ++c) {
      const ContactNodes::Node& node = cn_.nodes[c];
      if (node.a < 0)
        continue;
      const auto [ra, rb] = rows(c);
      const Eigen::Vector3d dp0 =
          cn_.net[c] + free_part(cn_, c, mred(c) * (row3(v_, rb) - row3(v_, ra)));
      const SideMasses m = side_masses(ops_, cn_, node.node, node.a, node.b);
      const double gap = gap_at_step_end(node.separation, dp0, node.normal, m, dt_);
      Eigen::Vector3d& dp = law_dp_[c];
      const bool touching = !released_[c] && !m.both_rigid() &&
                            contact_momentum_change(*node.pair, dp0, node.normal, gap, dp);
      if (!touching)
        dp.setZero();
      change = std::max(change, (dp - cn_.net[c]).norm());
      cn_.prior[c] = dp0;
      if (!touching) {
        released_[c] = released_[c] || mode_[c] != ExactMode::Apart;
        mode_[c] = ExactMode::Apart;
        continue;
      }
      const double dn = dp0.dot(node.normal);
      const bool sticks =
          node.pair->law == ContactLaw::Stick ||
          (node.pair->law == ContactLaw::Coulomb &&
           (dp - dn * node.normal - (dp0 - dn * node.normal)).norm() <= 1e-14 * dp0.norm());
      mode_[c] = sticks ? ExactMode::Stick : ExactMode::Normal;
      first_[c] = unknowns;
      unknowns += sticks ? d_ : 1;
    }
    return change;
  }

  // The frictional work of the net impulses, replacing each node's.
  void friction_work() {
    for (size_t c = 0; c < nc_; ++c) {
      const double work =
          mode_[c] == ExactMode::Apart
              ? 0.0
              : contact_friction_work(cn_.prior[c], law_dp_[c], cn_.nodes[c].normal, mred(c));
      cn_.friction_work += work - cn_.heat[c];
      cn_.heat[c] = work;
    }
  }

  // 2. The fixed parts: apart nodes drop their impulse, normal-only nodes take the law's
  // tangential impulse; their momenta and the velocities they imply.
  void fixed_parts(int outer) {
    q_.setZero();
    for (size_t c = 0; c < nc_; ++c) {
      if (cn_.nodes[c].a < 0 || mode_[c] == ExactMode::Stick)
        continue;
      const Eigen::Vector3d& nrm = cn_.nodes[c].normal;
      Eigen::Vector3d target = Eigen::Vector3d::Zero();
      if (mode_[c] == ExactMode::Normal) {
        // The law's tangential impulse; after the first passes, half way from the current one:
        // a sliding node whose slip reverses from pass to pass (the lumped m_red overshoots
        // the exact response) then settles instead of cycling.
        const Eigen::Vector3d t_law = law_dp_[c] - law_dp_[c].dot(nrm) * nrm;
        const Eigen::Vector3d t_now = cn_.net[c] - cn_.net[c].dot(nrm) * nrm;
        target = (outer <= 2 ? t_law : 0.5 * (t_law + t_now)) + cn_.net[c].dot(nrm) * nrm;
      }
      add_impulse(q_, c, target - cn_.net[c]);
      cn_.net[c] = target;
    }
    apply(q_);
  }

  // 3. The impulses y that close the constrained relative velocities: K y = r with
  // K y = −P(u^β − u^α), u = m̃⁻¹ B y, r = P(v^β − v^α); CG preconditioned by m_red.
  void constrained_impulses(Index unknowns) {
    Eigen::VectorXd precond(unknowns), r(unknowns), y = Eigen::VectorXd::Zero(unknowns);
    for (size_t c = 0; c < nc_; ++c)
      if (mode_[c] != ExactMode::Apart)
        precond.segment(first_[c], mode_[c] == ExactMode::Stick ? d_ : 1).setConstant(mred(c));
    gather(v_, r, 1.0);
    const double r0 = r.norm();
    Eigen::VectorXd z = precond.cwiseProduct(r), dir = z, kd(unknowns);
    double rz = r.dot(z);
    for (int it = 0; it < kMaxCg && r.norm() > 1e-14 * r0 && r0 > 0; ++it) {
      scatter(dir, jump_); // K dir
      respond_(jump_, u_);
      gather(u_, kd, -1.0);
      const double curvature = dir.dot(kd);
      if (!(curvature > 0))
        break; // the rest lies on prescribed components (velocity BCs): no response
      const double step = rz / curvature;
      y += step * dir;
      r -= step * kd;
      z = precond.cwiseProduct(r);
      const double rz_new = r.dot(z);
      dir = z + (rz_new / rz) * dir;
      rz = rz_new;
    }
    scatter(y, q_);
    apply(q_);
    for (size_t c = 0; c < nc_; ++c) {
      if (mode_[c] == ExactMode::Stick)
        cn_.net[c].head(d_) += y.segment(first_[c], d_);
      else if (mode_[c] == ExactMode::Normal)
        cn_.net[c] += y[first_[c]] * cn_.nodes[c].normal;
    }
  }

private:
  std::pair<Index, Index> rows(size_t c) const {
    const ContactNodes::Node& node = cn_.nodes[c];
    return {node.a * ng_ + node.node, node.b * ng_ + node.node};
  }
  double mred(size_t c) const {
    const ContactNodes::Node& node = cn_.nodes[c];
    return side_masses(ops_, cn_, node.node, node.a, node.b).reduced();
  }
  // Adds impulse Δ at node c: f^α += Δ, f^β −= Δ.
  void add_impulse(Field& f, size_t c, const Eigen::Vector3d& delta) const {
    const auto [ra, rb] = rows(c);
    f.row(ra) += delta.head(d_).transpose();
    f.row(rb) -= delta.head(d_).transpose();
  }
  // The momentum change q and the velocities it implies: p += q, v += m̃⁻¹ q.
  void apply(const Field& q) {
    p_ += q;
    respond_(q, u_);
    v_ += u_;
  }
  // The impulses y of the constrained nodes as momenta f.
  void scatter(const Eigen::VectorXd& y, Field& f) const {
    f.setZero();
    for (size_t c = 0; c < nc_; ++c) {
      if (mode_[c] == ExactMode::Apart)
        continue;
      Eigen::Vector3d delta = Eigen::Vector3d::Zero();
      if (mode_[c] == ExactMode::Stick)
        delta.head(d_) = y.segment(first_[c], d_);
      else
        delta = y[first_[c]] * cn_.nodes[c].normal;
      add_impulse(f, c, delta);
    }
  }
  // The constrained relative velocities sign (vel^β − vel^α) of the constrained nodes.
  void gather(const Field& vel, Eigen::VectorXd& out, double sign) const {
    for (size_t c = 0; c < nc_; ++c) {
      if (mode_[c] == ExactMode::Apart)
        continue;
      const auto [ra, rb] = rows(c);
      const Eigen::Vector3d rel = sign * (row3(vel, rb) - row3(vel, ra));
      if (mode_[c] == ExactMode::Stick)
        out.segment(first_[c], d_) = rel.head(d_);
      else
        out[first_[c]] = rel.dot(cn_.nodes[c].normal);
    }
  }

  const Operators& ops_;
  ContactNodes& cn_;
  double dt_;
  const std::function<void(const Field& r, Field& u)>& respond_;
  Field& p_;
  Field& v_;
  size_t nc_;
  Index ng_;
  int d_;
  std::vector<ExactMode> mode_;
  std::vector<char> released_;
  std::vector<Index> first_; // first unknown of each node
  std::vector<Eigen::Vector3d> law_dp_;
  Field q_, u_, jump_;
};

} // namespace

int exact_contact(const Operators& ops, ContactNodes& cn, double dt,
                  const std::function<void(const Field& r, Field& u)>& respond, Field& p, Field& v,
                  bool friction_work) {
  SMPM_VERIFY(cn.net.size() == cn.nodes.size(),
              "exact_contact: the lumped contact (apply_contact) must run first");
  const double scale = p.rowwise().norm().maxCoeff();
  ExactContact solve(ops, cn, dt, respond, p, v);
  for (int outer = 1; outer <= kMaxOuter; ++outer) {
    Index unknowns = 0;
    if (!(solve.classify(unknowns) > 1e-12 * scale)) {
      if (friction_work)
        solve.friction_work();
      return outer;
    }
    solve.fixed_parts(outer);
    if (unknowns > 0)
      solve.constrained_impulses(unknowns);
  }
  throw NumericalError("the contact of the exact update did not converge in " +
                       std::to_string(kMaxOuter) +
                       " passes (the law's contact and slip sets keep changing); use FMPM(k)");
}

} // namespace smpm
