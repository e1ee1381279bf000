// SPDX-License-Identifier: BSD-3-Clause
// The transport stages of one step (scheme.hpp; FMPM 2026 §3.5): the heat part's hooks
// (parts/heat.cpp) run them beside the mechanics' tasks 1–4, and the linearised transport step
// of the stability analysis (transport_stability.hpp) on their own.
#include "sparsempm/scheme.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/transport.hpp"

#include <algorithm>
#include <limits>

namespace smpm {

namespace {

// FCT on FMPM(k) transport (TransportLimiter::FCT; Zalesak 1979, J. Comput. Phys. 31:335–362,
// his limiter of the antidiffusive fluxes: P±, Q±, R± and C_ij = min(R⁺, R⁻) per flux). Each pass
// of the loop is c Δθ(ℓ) = (c − c̃) Δθ(ℓ−1), and the rows of c̃ sum to c, so c (θ_k − θ_1) = (c − c̃)
// θ_{k−1} = Σ_j f_ij with the antisymmetric fluxes f_ij = c̃_ij (y_i − y_j), y = θ_{k−1} (h.theta on
// entry). θ_i = θ_1,i + c_i⁻¹ Σ_j α_ij f_ij with α_ij = α_ji keeps Σ c θ = Σ τ⁺; α_ij = min(R_i^±,
// R_j^∓) keeps θ_i within [lower_i, upper_i]: the least and the largest of θ_1 on the nodes of row
// i of c̃ and of the step's particle temperatures on node i. Held nodes take their temperatures
// after (the caller), so their fluxes are not bounded there. Serial: a min/max and sums in a fixed
// order, the same for any number of threads.
void limit_fct(const Operators& ops, const TransportContext& heat, TransportState& h) {
  const Operators& nodes = heat.ops->nodes;
  const SparseRowMatrix& ct = *heat.ct;
  const Index ng = nodes.grid_node_count;
  const Eigen::VectorXd &c = nodes.m, &c_inv = nodes.m_inv;
  const Eigen::VectorXd& T = *heat.temperature;
  constexpr double inf = std::numeric_limits<double>::infinity();
  h.low = c_inv.cwiseProduct(h.tau_plus.col(0)); // θ_1 = c⁻¹ τ⁺
  h.lower.setConstant(ng, inf);
  h.upper.setConstant(ng, -inf);
  for (Index p = 0; p < ops.S.rows(); ++p) // the particles' temperatures on their nodes
    for (SparseRowMatrix::InnerIterator it(ops.S, p); it; ++it) {
      const Index i = it.col() % ng;
      h.lower[i] = std::min(h.lower[i], T[p]);
      h.upper[i] = std::max(h.upper[i], T[p]);
    }
  const int* outer = ct.outerIndexPtr();
  const int* inner = ct.innerIndexPtr();
  const double* val = ct.valuePtr();
  const Field& y = h.theta;
  h.r_plus.setOnes(ng);
  h.r_minus.setOnes(ng);
  for (Index i = 0; i < ng; ++i) {
    if (!(c_inv[i] > 0))
      continue;
    double p_plus = 0, p_minus = 0;
    for (int k = outer[i]; k < outer[i + 1]; ++k) {
      const Index j = inner[k];
      if (val[k] == 0 || !(c_inv[j] > 0)) // c̃'s pattern may hold zeros; no capacity, no bound
        continue;
      h.lower[i] = std::min(h.lower[i], h.low[j]);
      h.upper[i] = std::max(h.upper[i], h.low[j]);
      const double f = val[k] * (y(i, 0) - y(j, 0));
      (f > 0 ? p_plus : p_minus) += f;
    }
    const double q_plus = c[i] * (h.upper[i] - h.low[i]), q_minus = c[i] * (h.lower[i] - h.low[i]);
    if (p_plus > 0)
      h.r_plus[i] = std::min(1.0, q_plus / p_plus);
    if (p_minus < 0)
      h.r_minus[i] = std::min(1.0, q_minus / p_minus);
  }
  if (heat.bcs) // a held node takes its temperature after: no bound on its fluxes
    for (const VelocityCondition& cond : heat.bcs->conditions)
      for (Index g : cond.nodes) {
        const Index i = nodes.grid.is_window() ? nodes.grid.node_of_whole(g) : g;
        if (i >= 0 && i < ng)
          h.r_plus[i] = h.r_minus[i] = 1;
      }
  h.limited.resize(ng);
  for (Index i = 0; i < ng; ++i) {
    double sum = 0;
    if (c_inv[i] > 0)
      for (int k = outer[i]; k < outer[i + 1]; ++k) {
        const Index j = inner[k];
        const double f = val[k] * (y(i, 0) - y(j, 0));
        const double alpha =
            f > 0 ? std::min(h.r_plus[i], h.r_minus[j]) : std::min(h.r_minus[i], h.r_plus[j]);
        sum += alpha * f;
      }
    h.limited[i] = h.low[i] + c_inv[i] * sum;
  }
  h.theta.col(0) = h.limited;
}

} // namespace

void transport_content(const Operators& ops, const TransportContext& heat, double t,
                       TransportState& h) {
  const TransportOperators& top = *heat.ops;
  map_heat(ops, top, *heat.temperature, h.tau);
  // T = c⁻¹ τ on every node with capacity (an average of particle temperatures however small c_i:
  // the exact solve's tolerance leaves its lightest nodes out of the solve, not of the gradient)
  const Index ng = top.nodes.grid_node_count;
  h.T.resize(ng, 1);
  for (Index i = 0; i < ng; ++i)
    h.T(i, 0) = top.nodes.m[i] > 0 ? h.tau(i, 0) / top.nodes.m[i] : 0.0;
  if (!heat.bcs)
    return;
  heat.bcs->constrain_velocity(top.nodes.grid, t, h.T, &top.nodes.active);
  if (!heat.absolute)
    return;
  const Grid& grid = top.nodes.grid;
  for (const VelocityCondition& c : heat.bcs->conditions) // held temperatures are absolute
    for (Index g : c.nodes) {
      const Index i = grid.is_window() ? grid.node_of_whole(g) : g;
      if (i >= 0 && i < ng && top.nodes.active[i] && !(h.T(i, 0) > 0))
        throw NumericalError("temperature condition '" + c.label + "' gives " +
                             number_text(h.T(i, 0)) + " at node " + std::to_string(g) +
                             " at t = " + number_text(t) + " (temperatures are absolute)");
    }
}

void transport_update(const Operators& ops, const TransportContext& heat,
                      const ContactNodes* contact, double t, double dt, TransportState& h) {
  const TransportOperators& top = *heat.ops;
  temperature_gradient(ops, h.T, h.gradient);
  heat_flow(ops, top, h.gradient, h.q);
  if (contact)
    for (size_t k = 0; k < contact->heat.size(); ++k)
      h.q(contact->nodes[k].node, 0) += contact->heat[k] / dt;
  h.tau_plus.noalias() = h.tau + dt * h.q;
  const LoopConstraints bc{&top.nodes.grid, heat.bcs, t};
  if (heat.update == TransportUpdate::Exact) {
    if (heat.bcs)
      heat.bcs->constrain_update(top.nodes.grid, top.nodes.m, t, dt, h.tau_plus, h.q);
    try { // the solver names c~ and the lumped capacities (transport_solver_options)
      heat.solver->solve(top.nodes, *heat.ct, bc, h.tau_plus, h.theta);
    } catch (const NumericalError& e) {
      throw NumericalError(std::string("heat transport: ") + e.what());
    }
  } else if (heat.limiter == TransportLimiter::FCT && heat.fmpm.order > 1) {
    FmpmOptions lower = heat.fmpm; // y = θ_{k−1}, then the limited last pass
    lower.order -= 1;
    updated_velocity(top.nodes, heat.ct, lower, bc, true, dt, h.tau_plus, &h.q, h.theta, h.fmpm);
    limit_fct(ops, heat, h);
    if (heat.bcs)
      heat.bcs->constrain_velocity(top.nodes.grid, t, h.theta, &top.nodes.active);
  } else {
    updated_velocity(top.nodes, heat.ct, heat.fmpm, bc, true, dt, h.tau_plus, &h.q, h.theta,
                     h.fmpm);
  }
  lumped_solve(top.nodes.m_inv, h.q, h.rate);
}

void transport_particles(const Operators& ops, const TransportContext& heat, double dt,
                         TransportState& h) {
  Eigen::VectorXd& T = *heat.temperature;
  const bool shock = heat.energy && heat.materials && uses_shock_physics(*heat.materials);
  if (shock)
    h.before = T;
  if (heat.update == TransportUpdate::Lumped)
    update_temperature_flip(ops, h.rate, dt, T, heat.absolute);
  else
    update_temperature_grid(ops, h.theta, T, heat.absolute);
  if (!shock)
    return;
  const Eigen::VectorXi& id = *heat.material;
  for (Index p = 0; p < T.size(); ++p)
    if (const Material& m = (*heat.materials)[size_t(id[p])];
        m.model == MaterialModel::MieGruneisen)
      (*heat.energy)[p] += m.heat_capacity * (T[p] - h.before[p]);
}
} // namespace smpm
