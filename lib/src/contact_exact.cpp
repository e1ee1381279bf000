// The contact of the exact update in multimaterial mode (FMPM 2026 §3.2 at k → ∞): the fixed
// point of the Net method, solved by active-set passes and conjugate gradients on the contact
// compliance (contact.hpp, exact_contact).

#include "sparsempm/contact.hpp"

#include "contact_detail.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace smpm {

using detail::gap_at_step_end;
using detail::row3;

namespace {
// How a node of two fields takes part in one linear solve of exact_contact.
enum class ExactMode { Apart, Stick, Normal };
} // namespace

int exact_contact(const Operators& ops, ContactNodes& cn, double dt,
                  const std::function<void(const Field& r, Field& u)>& respond, Field& p, Field& v,
                  bool friction_work) {
  SMPM_VERIFY(cn.net.size() == cn.nodes.size(),
              "exact_contact: the lumped contact (apply_contact) must run first");
  constexpr int kMaxOuter = 50, kMaxCg = 1000;
  const Index ng = ops.grid_node_count, n = p.rows();
  const int d = int(p.cols());
  const double scale = p.rowwise().norm().maxCoeff();
  const size_t nc = cn.nodes.size();
  std::vector<ExactMode> mode(nc, ExactMode::Apart);
  // A node released from contact stays apart for the rest of the call: without it, nodes in
  // tension and nodes that approach once released can trade places forever.
  std::vector<char> released(nc, 0);
  std::vector<Index> first(nc, -1); // first unknown of each node
  std::vector<Eigen::Vector3d> law_dp(nc, Eigen::Vector3d::Zero());
  Field q(n, d), u(n, d), jump(n, d);
  auto rows = [&](size_t c) {
    const ContactNodes::Node& node = cn.nodes[c];
    return std::pair{node.a * ng + node.node, node.b * ng + node.node};
  };
  auto mred = [&](size_t c) {
    const auto [ra, rb] = rows(c);
    return ops.m[ra] * ops.m[rb] / (ops.m[ra] + ops.m[rb]);
  };
  // Adds impulse Δ at node c: p^α += Δ, p^β −= Δ (and into a momentum field q likewise).
  auto add_impulse = [&](Field& f, size_t c, const Eigen::Vector3d& delta) {
    const auto [ra, rb] = rows(c);
    f.row(ra) += delta.head(d).transpose();
    f.row(rb) -= delta.head(d).transpose();
  };
  for (int outer = 1; outer <= kMaxOuter; ++outer) {
    // 1. The law at the current state (Eq. 20 summed: Δp(0) = Δp^(net) + m_red (v^β − v^α)).
    double change = 0;
    Index unknowns = 0;
    for (size_t c = 0; c < nc; ++c) {
      const ContactNodes::Node& node = cn.nodes[c];
      if (node.a < 0)
        continue;
      const auto [ra, rb] = rows(c);
      const Eigen::Vector3d dp0 =
          cn.net[c] + free_part(cn, c, mred(c) * (row3(v, rb) - row3(v, ra)));
      const double gap =
          gap_at_step_end(node.separation, dp0, node.normal, ops.m[ra], ops.m[rb], dt);
      Eigen::Vector3d& dp = law_dp[c];
      const bool touching =
          !released[c] && contact_momentum_change(*node.pair, dp0, node.normal, gap, dp);
      if (!touching)
        dp.setZero();
      change = std::max(change, (dp - cn.net[c]).norm());
      cn.prior[c] = dp0;
      if (!touching) {
        released[c] = released[c] || mode[c] != ExactMode::Apart;
        mode[c] = ExactMode::Apart;
        continue; // apart
      }
      const double dn = dp0.dot(node.normal);
      const bool sticks =
          node.pair->law == ContactLaw::Stick ||
          (node.pair->law == ContactLaw::Coulomb &&
           (dp - dn * node.normal - (dp0 - dn * node.normal)).norm() <= 1e-14 * dp0.norm());
      mode[c] = sticks ? ExactMode::Stick : ExactMode::Normal;
      first[c] = unknowns;
      unknowns += sticks ? d : 1;
    }
    if (!(change > 1e-12 * scale)) {
      if (friction_work)
        for (size_t c = 0; c < nc; ++c) {
          const double work =
              mode[c] == ExactMode::Apart
                  ? 0.0
                  : contact_friction_work(cn.prior[c], law_dp[c], cn.nodes[c].normal, mred(c));
          cn.friction_work += work - cn.heat[c];
          cn.heat[c] = work;
        }
      return outer;
    }
    // 2. The fixed parts: apart nodes drop their impulse, normal-only nodes take the law's
    // tangential impulse; their momenta and the velocities they imply.
    q.setZero();
    for (size_t c = 0; c < nc; ++c) {
      if (cn.nodes[c].a < 0 || mode[c] == ExactMode::Stick)
        continue;
      const Eigen::Vector3d& nrm = cn.nodes[c].normal;
      Eigen::Vector3d target = Eigen::Vector3d::Zero();
      if (mode[c] == ExactMode::Normal) {
        // The law's tangential impulse; after the first passes, half way from the current one:
        // a sliding node whose slip reverses from pass to pass (the lumped m_red overshoots
        // the exact response) then settles instead of cycling.
        const Eigen::Vector3d t_law = law_dp[c] - law_dp[c].dot(nrm) * nrm;
        const Eigen::Vector3d t_now = cn.net[c] - cn.net[c].dot(nrm) * nrm;
        target = (outer <= 2 ? t_law : 0.5 * (t_law + t_now)) + cn.net[c].dot(nrm) * nrm;
      }
      const Eigen::Vector3d delta = target - cn.net[c];
      add_impulse(q, c, delta);
      cn.net[c] = target;
    }
    p += q;
    respond(q, u);
    v += u;
    if (unknowns == 0)
      continue;
    // 3. The impulses y that close the constrained relative velocities: K y = r with
    // K y = −P(u^β − u^α), u = m̃⁻¹ B y, r = P(v^β − v^α); CG preconditioned by m_red.
    auto scatter = [&](const Eigen::VectorXd& y, Field& f) {
      f.setZero();
      for (size_t c = 0; c < nc; ++c) {
        if (mode[c] == ExactMode::Apart)
          continue;
        const Eigen::Vector3d& nrm = cn.nodes[c].normal;
        Eigen::Vector3d delta = Eigen::Vector3d::Zero();
        if (mode[c] == ExactMode::Stick)
          delta.head(d) = y.segment(first[c], d);
        else
          delta = y[first[c]] * nrm;
        add_impulse(f, c, delta);
      }
    };
    auto gather = [&](const Field& vel, Eigen::VectorXd& out, double sign) {
      for (size_t c = 0; c < nc; ++c) {
        if (mode[c] == ExactMode::Apart)
          continue;
        const auto [ra, rb] = rows(c);
        const Eigen::Vector3d rel = sign * (row3(vel, rb) - row3(vel, ra));
        if (mode[c] == ExactMode::Stick)
          out.segment(first[c], d) = rel.head(d);
        else
          out[first[c]] = rel.dot(cn.nodes[c].normal);
      }
    };
    auto apply_k = [&](const Eigen::VectorXd& y, Eigen::VectorXd& ky) {
      scatter(y, jump);
      respond(jump, u);
      gather(u, ky, -1.0);
    };
    Eigen::VectorXd precond(unknowns), r(unknowns), y = Eigen::VectorXd::Zero(unknowns);
    for (size_t c = 0; c < nc; ++c)
      if (mode[c] != ExactMode::Apart)
        precond.segment(first[c], mode[c] == ExactMode::Stick ? d : 1).setConstant(mred(c));
    gather(v, r, 1.0);
    const double r0 = r.norm();
    Eigen::VectorXd z = precond.cwiseProduct(r), dir = z, kd(unknowns);
    double rz = r.dot(z);
    for (int it = 0; it < kMaxCg && r.norm() > 1e-14 * r0 && r0 > 0; ++it) {
      apply_k(dir, kd);
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
    scatter(y, q);
    p += q;
    respond(q, u);
    v += u;
    for (size_t c = 0; c < nc; ++c) {
      if (mode[c] == ExactMode::Stick)
        cn.net[c].head(d) += y.segment(first[c], d);
      else if (mode[c] == ExactMode::Normal)
        cn.net[c] += y[first[c]] * cn.nodes[c].normal;
    }
  }
  throw NumericalError("the contact of the exact update did not converge in " +
                       std::to_string(kMaxOuter) +
                       " passes (the law's contact and slip sets keep changing); use FMPM(k)");
}

} // namespace smpm
