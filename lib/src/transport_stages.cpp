// SPDX-License-Identifier: BSD-3-Clause
// The transport stages of one step (scheme.hpp; FMPM 2026 §3.5): the heat part's hooks
// (parts/heat.cpp) run them beside the mechanics' tasks 1–4, and the linearised transport step
// of the stability analysis (transport_stability.hpp) on their own.
#include "sparsempm/scheme.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/transport.hpp"

namespace smpm {

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
