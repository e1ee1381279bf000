// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.assemble and sparsempm.Operators: S, G, M, m and the active nodes of one
// configuration as scipy.sparse matrices and numpy arrays (views of the library's storage),
// m̃, S⁺ and A on request, and the grid velocity of FMPM(k) and of the exact inverse (the same
// for heat transport: transport.cpp).

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

// The grid momentum p (n or n × d) as a field with one row per node.
Field momentum(const PyOperators& o, const DoubleArray& p) {
  return to_field(p, o.ops().num_nodes(), "p");
}

// v⁺(k) of FMPM 2026 Eqs. (5)–(6) from an updated momentum p⁺, by the step's own sequence
// (updated_velocity of fmpm.hpp): the lumped BCs of Table 2 on p⁺ by the BC method, v⁺(1) = m⁻¹ p⁺,
// then the loop of Table 1.
py::array fmpm_grid_velocity(PyOperators& o, const DoubleArray& p_in, int order, double blend_alpha,
                             int blend_every, const BoundaryConditions* bcs, double time,
                             const std::string& bc_method, const std::string& polynomial,
                             double interval_low, const py::kwargs& earlier) {
  FmpmOptions opt{.order = order, .blend_alpha = blend_alpha, .blend_every = blend_every};
  opt.polynomial = polynomial_from_string(polynomial);
  opt.interval_low = interval_low;
  for (const auto& [key, value] : earlier) { // k, alpha, every: accepted in this release only
    const std::string name = py::str(key);
    const char* current = name == "k"       ? "order"
                          : name == "alpha" ? "blend_alpha"
                          : name == "every" ? "blend_every"
                                            : nullptr;
    if (!current)
      throw InputError("fmpm_velocity: unexpected argument '" + clip(name) + "'");
    warn_earlier_name(name, current);
    if (name == "k")
      opt.order = value.cast<int>();
    else if (name == "alpha")
      opt.blend_alpha = value.cast<double>();
    else
      opt.blend_every = value.cast<int>();
  }
  opt.bc_method = bc_method_from_string(bc_method);
  validate(opt);
  check_wall_nodes(bcs);
  Field p = momentum(o, p_in);
  const SparseRowMatrix* mt = opt.order > 1 ? &o.prep.consistent_mass() : nullptr;
  Field v;
  {
    py::gil_scoped_release release;
    FmpmWorkspace w;
    updated_velocity(o.ops(), mt, opt, LoopConstraints{&o.grid(), bcs, time}, true, 0, p, nullptr,
                     v, w);
  }
  return from_field(std::move(v), p_in.ndim() == 1);
}

// v = m̃⁻¹ p on the active nodes with the BCs (CHOLMOD, exact.hpp).
py::array exact_grid_velocity(PyOperators& o, const DoubleArray& p_in,
                              const BoundaryConditions* bcs, double time, double regularization,
                              double mass_cutoff) {
  check_wall_nodes(bcs);
  const Field p = momentum(o, p_in);
  const SparseRowMatrix& mt = o.prep.consistent_mass();
  CholmodSolver solver({.regularization = regularization, .mass_cutoff = mass_cutoff});
  Field v;
  {
    py::gil_scoped_release release;
    solver.solve(o.ops(), mt, LoopConstraints{&o.grid(), bcs, time}, p, v);
  }
  return from_field(std::move(v), p_in.ndim() == 1);
}

} // namespace

namespace {

void bind_matrices(py::class_<PyOperators>& c) {
  c.def_property_readonly(
       "S", [](py::object self) { return csr_view(self.cast<PyOperators&>().prep.ops.S, self); },
       "N × n shape-function weights S_pi")
      .def_property_readonly(
          "G",
          [](py::object self) {
            PyOperators& o = self.cast<PyOperators&>();
            py::list G;
            for (int a = 0; a < o.ops().dim; ++a)
              G.append(csr_view(o.prep.ops.G[size_t(a)], self));
            return G;
          },
          "[G_x, ...]: N × n gradient weights ∂S_pi/∂x_a, one per axis")
      .def_property_readonly(
          "M",
          [](py::object self) {
            return vector_view(self.cast<PyOperators&>().prep.ops.M, self, false);
          },
          "N particle masses")
      .def_property_readonly(
          "m",
          [](py::object self) {
            return vector_view(self.cast<PyOperators&>().prep.ops.m, self, false);
          },
          "n lumped nodal masses m = Sᵀ M")
      .def_property_readonly(
          "m_inv",
          [](py::object self) {
            return vector_view(self.cast<PyOperators&>().prep.ops.m_inv, self, false);
          },
          "n: 1/m_i on active nodes, 0 elsewhere")
      .def_property_readonly(
          "active",
          [](const PyOperators& o) {
            py::array_t<bool> a(o.ops().active.size());
            std::copy(o.ops().active.data(), o.ops().active.data() + o.ops().active.size(),
                      a.mutable_data());
            return a;
          },
          "n booleans: m_i > 1e-10 max m (Buzzi §4.4)")
      .def_property_readonly(
          "active_nodes",
          [](const PyOperators& o) {
            Eigen::VectorXi a = active_nodes(o.ops());
            return py::array_t<int>(a.size(), a.data());
          },
          "indices of the active nodes, ascending");
}

void bind_numbering(py::class_<PyOperators>& c) {
  c.def_property_readonly(
       "dim", [](const PyOperators& o) { return o.ops().dim; }, "dimension d")
      .def_property_readonly(
          "fields", [](const PyOperators& o) { return o.ops().fields; },
          "velocity fields n_f: blocks of n_g columns of S (1 unless the model has [[contact]] "
          "fields); node i of field α is column α n_g + i")
      .def_property_readonly(
          "grid_node_count", [](const PyOperators& o) { return o.ops().grid_node_count; },
          "n_g, nodes of the grid (num_nodes = fields · n_g)")
      .def_property_readonly(
          "particle_field",
          [](const PyOperators& o) {
            py::array_t<int> a(o.ops().num_particles());
            if (o.prep.field.size() == 0)
              std::fill_n(a.mutable_data(), a.size(), 0);
            else
              std::copy_n(o.prep.field.data(), o.prep.field.size(), a.mutable_data());
            return a;
          },
          "N ints: the velocity field of each particle (the block of its row of S)")
      .def_property_readonly(
          "num_nodes", [](const PyOperators& o) { return o.ops().num_nodes(); },
          "n: the nodes of the operators (columns of S, every velocity field's)")
      .def_property_readonly(
          "num_particles", [](const PyOperators& o) { return o.ops().num_particles(); },
          "N: the particles (rows of S)")
      .def_property_readonly(
          "shape", [](const PyOperators& o) { return std::string(to_string(o.shape)); },
          "the shape function: linear | gimp | bspline2 | cpdi | b2cpdi")
      .def_property_readonly(
          "grid", [](const PyOperators& o) { return o.grid(); },
          "the grid window the operators live on")
      .def_property_readonly(
          "bcs", [](PyOperators& o) -> const BoundaryConditions& { return o.prep.bcs; },
          py::return_value_policy::reference_internal,
          "the model's velocity BCs with the walls' nodes at the model's time: those of a step "
          "from this configuration (pass them to fmpm_velocity and exact_velocity)");
}

void bind_products(py::class_<PyOperators>& c) {
  c.def(
       "consistent_mass",
       [](const PyOperators& o) { return csr_owned(SparseRowMatrix(consistent_mass(o.ops()))); },
       "m̃ = Sᵀ diag(M) S, n × n (rows sum to m)")
      .def(
          "transfer_mass",
          [](PyOperators& o) { return csr_owned(SparseRowMatrix(o.prep.transfer_mass(o.X))); },
          "m̃_L = Sᵀ M S + Σ_b D_bᵀ M G_b, D_b = S ∘ (x_ib − X_pb), n × n: the mass operator of the "
          "velocity-gradient transfer (P2G with L_p after G2P of v), which takes m̃'s place in "
          "FMPM(k) and XPIC with step.transfer = 'velocity_gradient'; not symmetric, rows sum to "
          "m, m̃_L v = m v for affine v. Structural zeros kept (stencil storage)")
      .def(
          "apic_mass",
          [](PyOperators& o) {
            ConsistentMass mt;
            assemble_apic_mass(o.ops(), o.X, o.shape, mt);
            return csr_owned(SparseRowMatrix(mt.matrix));
          },
          "m̃_A, n × n: the mass operator of the APIC transfer (Jiang et al. 2015), (m̃_A)_ij = "
          "Σ_p M_p S_pi S_pj (1 + Δ_piᵀ D_p⁻¹ Δ_pj) with Δ_pi = x_i − X_p and D_p = Σ_i S_pi Δ_pi "
          "Δ_piᵀ, which takes m̃'s place in FMPM(k), XPIC and the exact update with "
          "step.transfer = 'apic'; symmetric, rows sum to m, m̃ ≤ m̃_A ≤ m, m̃_A v = m v for "
          "affine v; with linear hats it is transfer_mass(). Structural zeros kept")
      .def(
          "S_plus",
          [](const PyOperators& o) { return csr_owned(SparseRowMatrix(S_plus(o.ops()))); },
          "S⁺ = m⁻¹ Sᵀ M, n × N (rows of inactive nodes zero)")
      .def(
          "expansion_matrix",
          [](const PyOperators& o) {
            return csr_owned(SparseRowMatrix(expansion_matrix(o.ops())));
          },
          "A = I − m⁻¹ m̃ = I − S⁺ S (FMPM 2026 Eq. 1), zero on inactive nodes")
      .def(
          "momentum",
          [](const PyOperators& o, const DoubleArray& V) {
            Field p;
            map_momentum(particle_operators(o.ops()), to_field(V, o.ops().num_particles(), "V"), p);
            return from_field(std::move(p), V.ndim() == 1);
          },
          py::arg("V"), "p = Sᵀ (M ∘ V), one row per node");
}

} // namespace

void bind_operators(py::module_& m) {
  py::class_<PyOperators> c(m, "Operators",
                            "The operators of one configuration (FMPM 2026 §2.1): S, G, M, m and "
                            "the active nodes; consistent_mass(), S_plus() and expansion_matrix() "
                            "on request. Matrices are scipy.sparse.csr_matrix; S, G, M, m and "
                            "active share the library's storage (read-only).");
  bind_matrices(c);
  bind_numbering(c);
  bind_products(c);
  m.def(
      "assemble",
      [](const PyModel& model, const py::object& shape) {
        PyOperators o;
        o.shape = shape_arg(shape, &model);
        prepare_step(model.model, o.shape, o.prep); // the Stepper's preparation, whole grid
        o.X = model.model.particles.X;
        // ops.bcs outlives this call: its values copied from the model's (which they call),
        // and a wall's evaluated at the time a product is given (not frozen at the model's).
        // (The rigid materials' conditions follow the model's and keep their own values.)
        for (size_t k = 0; k < model.model.bcs.conditions.size(); ++k) {
          o.prep.bcs.conditions[k].value = model.model.bcs.conditions[k].value;
          o.prep.bcs.conditions[k].wall_state.reset();
        }
        return o;
      },
      py::arg("model"), py::arg("shape") = py::none(),
      "The operators of the model's configuration for a shape ('linear', 'gimp', 'bspline2', "
      "'cpdi', 'b2cpdi'; default: the model's options.shape). A model with velocity fields "
      "([[contact]]) has them as blocks of columns of S: n = fields · grid_node_count, node i "
      "of field α is column α·grid_node_count + i, and m, active and m̃ hold every field.");
  m.def("fmpm_velocity", &fmpm_grid_velocity, py::arg("ops"), py::arg("p"), py::arg("order") = 1,
        py::arg("blend_alpha") = 1.0, py::arg("blend_every") = 1, py::arg("bcs") = nullptr,
        py::arg("time") = 0.0, py::arg("bc_method") = "incremental",
        py::arg("polynomial") = "series", py::arg("interval_low") = 0.0,
        "v⁺(k) = m̃_k⁻¹ p = Σ_{ℓ=1}^{k} Δv(ℓ), Δv(1) = m⁻¹ p, Δv(ℓ) = c_ℓ A Δv(ℓ−1) (FMPM 2026 "
        "Eqs. 5-6, Table 1, k = order; c_ℓ = blend_alpha on every blend_every-th pass, §3.3): "
        "without blending "
        "Σ_{j<k} Aʲ m⁻¹ p. With bcs (ops.bcs: the model's, walls included) the velocity BCs "
        "of bc_method (§3.1) as a step applies them to its updated momentum: Table 2 on p in "
        "momentum form (unless 'velocity'), then the loop. p: n or n × d; the result has its "
        "shape. polynomial 'chebyshev', 'least_squares' or 'chebyshev_squared' (interval "
        "[interval_low, 1]): the "
        "same k − 1 products with m̃ applying that member's q(m⁻¹m̃) m⁻¹ p "
        "(docs/studies/polynomials.md).");
  m.def(
      "residual_polynomial",
      [](const DoubleArray& lam, int order, const std::string& polynomial, double interval_low,
         double blend_alpha, int blend_every) {
        FmpmOptions opt{.order = order, .blend_alpha = blend_alpha, .blend_every = blend_every};
        opt.polynomial = polynomial_from_string(polynomial);
        opt.interval_low = interval_low;
        validate(opt);
        py::array_t<double> out(lam.request().shape);
        const py::array_t<double, py::array::c_style | py::array::forcecast> flat = lam;
        const double* in = flat.data();
        double* o = out.mutable_data();
        for (py::ssize_t i = 0; i < lam.size(); ++i)
          o[i] = residual_polynomial(opt, in[i]);
        return out;
      },
      py::arg("lam"), py::arg("order"), py::arg("polynomial") = "series",
      py::arg("interval_low") = 0.0, py::arg("blend_alpha") = 1.0, py::arg("blend_every") = 1,
      "R_k(λ) = 1 − λ q(λ) of FMPM(k)'s polynomial member at each λ of `lam` (an eigenvalue of "
      "m⁻¹m̃): what the member leaves of that mode of v = m̃⁻¹ p (series: (1 − λ)^k).");
  m.def("exact_velocity", &exact_grid_velocity, py::arg("ops"), py::arg("p"),
        py::arg("bcs") = nullptr, py::arg("time") = 0.0, py::arg("regularization") = 0.0,
        py::arg("mass_cutoff") = 0.0,
        "v = m̃⁻¹ p on the active nodes (zero elsewhere), with the velocity BCs of bcs "
        "(CHOLMOD; exact.hpp). Raises NumericalError when m̃ is not positive definite there.");
  bind_transport(m);
}

} // namespace smpm::python
