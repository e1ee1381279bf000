// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.transport_operators and Transport: the operators of heat transport (transport.hpp;
// FMPM 2026 §3.5) for one configuration: 𝗖, V κ, c, c̃, K, the folded S and G, and the nodal
// temperature of FMPM(k) on c̃ and of the exact inverse c̃⁻¹.

#include "bindings.hpp"
#include "convert.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/fmpm.hpp>
#include <sparsempm/stages.hpp>

#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace smpm::python {

namespace {

using DoubleArray = py::array_t<double, py::array::forcecast>;

// Heat transport: the operators of transport_operators() and the capacity inverses.

// A field of one value per transport node (shape (n_g,) or (n_g, 1)), named `name` in errors.
Field nodal(const PyTransport& t, const DoubleArray& x, const char* name) {
  Field f = to_field(x, t.ops().grid_node_count, name);
  if (f.cols() != 1)
    throw std::invalid_argument(std::string(name) + ": expected one value per node, shape (" +
                                std::to_string(f.rows()) + ",), got " + std::to_string(f.cols()) +
                                " columns");
  return f;
}

PyTransport transport_operators(const PyModel& model, const py::object& shape,
                                const py::object& transport) {
  PyTransport t;
  t.shape = shape_arg(shape, &model);
  if (transport.is_none()) { // the model's; its active nodes are FMPM's when it has none
    t.update = model.options.transport.update;
    if (t.update == TransportUpdate::Off)
      t.update = TransportUpdate::FMPM;
  } else {
    t.update = transport_update_from_string(transport.cast<std::string>());
    if (t.update == TransportUpdate::Off)
      throw InputError("transport_operators: transport 'off' has no operators (give lumped, "
                       "FMPM or exact)");
  }
  // The Stepper's preparation with heat transport, on the whole grid.
  prepare_step(model.model, t.shape, t.prep);
  prepare_heat_transport(model.model, t.prep, t.update);
  // The conditions outlive this call: their values copied from the model's (which they call).
  for (size_t k = 0; k < t.prep.temperature_bcs.conditions.size(); ++k)
    t.prep.temperature_bcs.conditions[k].value = model.model.temperature_bcs.conditions[k].value;
  t.S = SparseRowMatrix(folded_columns(t.ops(), t.ops().S));
  t.S.makeCompressed();
  for (int b = 0; b < t.ops().dim; ++b) {
    t.G.emplace_back(folded_columns(t.ops(), t.ops().G[size_t(b)]));
    t.G.back().makeCompressed();
  }
  return t;
}

// θ = c̃_k⁻¹ τ by the step's own sequence on the transport nodes (updated_velocity with c and c̃
// in the place of m and m̃): the conditions on τ by the BC method, c⁻¹ τ, then the loop of Table 1.
py::array fmpm_temperature(PyTransport& t, const DoubleArray& tau_in, int order, double blend_alpha,
                           int blend_every, const BoundaryConditions* bcs, double time,
                           const std::string& bc_method) {
  FmpmOptions opt{.order = order, .blend_alpha = blend_alpha, .blend_every = blend_every};
  opt.bc_method = bc_method_from_string(bc_method);
  validate(opt);
  check_wall_nodes(bcs);
  Field tau = nodal(t, tau_in, "tau");
  const SparseRowMatrix* ct = opt.order > 1 ? &t.prep.consistent_capacity() : nullptr;
  const Operators& nodes = t.transport().nodes;
  Field theta;
  {
    py::gil_scoped_release release;
    FmpmWorkspace w;
    updated_velocity(nodes, ct, opt, LoopConstraints{&nodes.grid, bcs, time}, true, 0, tau, nullptr,
                     theta, w);
  }
  return from_field(std::move(theta), tau_in.ndim() == 1);
}

// θ = c̃⁻¹ τ on the active transport nodes with the conditions: a solver of the factory the
// module's StepOptions take (CHOLMOD), as the exact transport update makes its own.
py::array exact_temperature(PyTransport& t, const DoubleArray& tau_in,
                            const BoundaryConditions* bcs, double time, double regularization,
                            double mass_cutoff) {
  check_wall_nodes(bcs);
  const Field tau = nodal(t, tau_in, "tau");
  const SparseRowMatrix& ct = t.prep.consistent_capacity();
  const std::unique_ptr<MassSolver> solver =
      exact_solver_factory()({.regularization = regularization, .mass_cutoff = mass_cutoff});
  const Operators& nodes = t.transport().nodes;
  Field theta;
  {
    py::gil_scoped_release release;
    solver->solve(nodes, ct, LoopConstraints{&nodes.grid, bcs, time}, tau, theta);
  }
  return from_field(std::move(theta), tau_in.ndim() == 1);
}

// The operators on the particles: S and G folded onto the grid nodes, 𝗖, V κ and the sources.
void bind_transport_data(py::class_<PyTransport>& c) {
  c.def_property_readonly(
       "S", [](py::object self) { return csr_view(self.cast<PyTransport&>().S, self); },
       "N × n_g: S with the velocity fields' block columns folded onto the grid nodes "
       "(folded_columns; S itself with one field): the interpolation transport applies")
      .def_property_readonly(
          "G",
          [](py::object self) {
            py::list G;
            for (const SparseRowMatrix& Gb : self.cast<PyTransport&>().G)
              G.append(csr_view(Gb, self));
            return G;
          },
          "[G_x, ...]: N × n_g gradient weights, folded as S")
      .def_property_readonly(
          "capacity",
          [](py::object self) {
            return vector_view(self.cast<PyTransport&>().prep.transport.capacity, self, false);
          },
          "N: M_p C_V,p, the heat capacity of each particle (diagonal of 𝗖)")
      .def_property_readonly(
          "conductance",
          [](py::object self) {
            return vector_view(self.cast<PyTransport&>().prep.transport.conductance, self, false);
          },
          "N: V_p κ_p, current volume det(F_p) V_p⁽⁰⁾ times conductivity")
      .def_property_readonly(
          "source",
          [](py::object self) {
            return vector_view(self.cast<PyTransport&>().prep.transport.source, self, false);
          },
          "N: M_p r_p, the particles' heat sources (power); empty: none");
}

// The transport nodes: their lumped capacities, which are active, and their temperature
// conditions.
void bind_transport_nodes(py::class_<PyTransport>& c) {
  c.def_property_readonly(
       "lumped_capacity",
       [](py::object self) {
         return vector_view(self.cast<PyTransport&>().prep.transport.nodes.m, self, false);
       },
       "n_g: c = Sᵀ 𝗖 1, the lumped capacity of each grid node")
      .def_property_readonly(
          "lumped_capacity_inv",
          [](py::object self) {
            return vector_view(self.cast<PyTransport&>().prep.transport.nodes.m_inv, self, false);
          },
          "n_g: 1/c_i on active nodes, 0 elsewhere")
      .def_property_readonly(
          "active",
          [](const PyTransport& t) {
            const auto& a = t.transport().nodes.active;
            py::array_t<bool> out(a.size());
            std::copy(a.data(), a.data() + a.size(), out.mutable_data());
            return out;
          },
          "n_g booleans: the active transport nodes, c_i > 0 (exact: c_i > 1e-10 max c)")
      .def_property_readonly(
          "active_nodes",
          [](const PyTransport& t) {
            Eigen::VectorXi a = active_nodes(t.transport().nodes);
            return py::array_t<int>(a.size(), a.data());
          },
          "indices of the active transport nodes, ascending")
      .def_property_readonly(
          "temperature_bcs",
          [](PyTransport& t) -> const BoundaryConditions& { return t.prep.temperature_bcs; },
          py::return_value_policy::reference_internal,
          "the model's temperature conditions on the transport nodes with capacity: those of a "
          "step from this configuration (pass them to fmpm_temperature and exact_temperature)");
}

void bind_transport_products(py::class_<PyTransport>& c) {
  c.def_property_readonly(
       "grid_node_count", [](const PyTransport& t) { return t.ops().grid_node_count; },
       "n_g: the transport nodes, one per grid node (every material's)")
      .def_property_readonly(
          "num_particles", [](const PyTransport& t) { return t.ops().num_particles(); },
          "N: the particles (rows of S)")
      .def_property_readonly(
          "shape", [](const PyTransport& t) { return std::string(to_string(t.shape)); },
          "the shape function: linear | gimp | bspline2 | cpdi | b2cpdi")
      .def_property_readonly(
          "transport", [](const PyTransport& t) { return std::string(to_string(t.update)); },
          "the transport update the operators were prepared for (lumped | FMPM | exact)")
      .def_property_readonly(
          "grid", [](const PyTransport& t) { return t.ops().grid; }, "the grid of the nodes");
  c.def(
       "consistent_capacity",
       [](const PyTransport& t) {
         return csr_owned(SparseRowMatrix(consistent_capacity(t.ops(), t.transport())));
       },
       "c̃ = Sᵀ 𝗖 S, n_g × n_g with S folded (rows sum to c)")
      .def(
          "conductivity_matrix",
          [](const PyTransport& t) {
            return csr_owned(SparseRowMatrix(conductivity_matrix(t.ops(), t.transport())));
          },
          "K = Σ_b G_bᵀ diag(V κ) G_b, n_g × n_g, symmetric positive semidefinite, K 1 = 0")
      .def(
          "heat_content",
          [](const PyTransport& t, const DoubleArray& T) {
            const Eigen::VectorXd Tp = particle_vector(T, t.ops().num_particles(), "T");
            Field tau;
            map_heat(t.ops(), t.transport(), Tp, tau);
            return from_field(std::move(tau), true);
          },
          py::arg("T"), "τ = Sᵀ (𝗖 T), n_g, of particle temperatures T (N; map_heat)")
      .def(
          "heat_flow",
          [](const PyTransport& t, const DoubleArray& T) {
            const Field Tn = nodal(t, T, "T");
            Field gradient, q;
            temperature_gradient(t.ops(), Tn, gradient);
            heat_flow(t.ops(), t.transport(), gradient, q);
            return from_field(std::move(q), true);
          },
          py::arg("T"),
          "q = −K T + Sᵀ (M r), n_g, of nodal temperatures T (n_g): conduction and the "
          "particles' sources (temperature_gradient, heat_flow)");
}

} // namespace

void bind_transport(py::module_& m) {
  py::class_<PyTransport> c(m, "Transport",
                            "The heat-transport operators of one configuration (transport.hpp; "
                            "FMPM 2026 §3.5): 𝗖 = M C_V, V κ, c = Sᵀ 𝗖 1 and the active nodes "
                            "on the n_g grid nodes, with consistent_capacity() (c̃) and "
                            "conductivity_matrix() (K) on request; S and G folded onto the grid "
                            "nodes. Matrices are scipy.sparse.csr_matrix; the arrays share the "
                            "library's storage (read-only).");
  bind_transport_data(c);
  bind_transport_nodes(c);
  bind_transport_products(c);
  m.def("transport_operators", &transport_operators, py::arg("model"),
        py::arg("shape") = py::none(), py::arg("transport") = py::none(),
        "The heat-transport operators of the model's configuration, as a step prepares them "
        "(with heat transport, whole grid): shape as assemble() takes it; "
        "transport 'lumped' | 'FMPM' | 'exact' (default: model.options.transport, FMPM when "
        "that is off) sets the active nodes: every node with capacity, or c_i > 1e-10 max c for "
        "the exact solve. Every material needs heat_capacity > 0.");
  m.def("fmpm_temperature", &fmpm_temperature, py::arg("transport"), py::arg("tau"),
        py::arg("order") = 1, py::arg("blend_alpha") = 1.0, py::arg("blend_every") = 1,
        py::arg("bcs") = nullptr, py::arg("time") = 0.0, py::arg("bc_method") = "incremental",
        "θ(k) = c̃_k⁻¹ τ: FMPM(k) on the capacity matrices (FMPM 2026 §3.5), "
        "Σ_{ℓ=1}^{k} Δθ(ℓ), Δθ(1) = c⁻¹ τ, Δθ(ℓ) = c_ℓ A_c Δθ(ℓ−1) with A_c = I − c⁻¹ c̃ "
        "(blending as fmpm_velocity): without blending Σ_{j<k} A_cʲ c⁻¹ τ. The step's own "
        "sequence (updated_velocity on the transport nodes): with bcs (transport.temperature_bcs) "
        "the temperature conditions as the step applies them to τ⁺. tau: n_g (a heat content, "
        "e.g. transport.heat_content(T)); the result has its shape.");
  m.def("exact_temperature", &exact_temperature, py::arg("transport"), py::arg("tau"),
        py::arg("bcs") = nullptr, py::arg("time") = 0.0, py::arg("regularization") = 0.0,
        py::arg("mass_cutoff") = 0.0,
        "θ = c̃⁻¹ τ on the active transport nodes (zero elsewhere), with the temperature "
        "conditions of bcs: the exact transport update's solve (CHOLMOD, the solver factory of "
        "StepOptions). Raises NumericalError when c̃ is not positive definite there (prepare "
        "with transport='exact' to leave out nodes of negligible capacity).");
}

} // namespace smpm::python
