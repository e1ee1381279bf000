// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.Stepper: the library's Stepper (one step) and advance() (the run loop of `smpm
// run`), with the GIL released while they run, and the transport fields of its last step.

#include "bindings.hpp"
#include "convert.hpp"
#include "interrupt.hpp"

#include <sparsempm/advance.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/scheme.hpp>
#include <sparsempm/transport.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <optional>

namespace smpm::python {

namespace {

// advance() of advance.hpp; `callback(model, energies, at_stop)` after every step, with the
// GIL held (an exception it raises stops the run and propagates). `earlier` holds t_end, the
// earlier name of end (accepted in this release only).
AdvanceReport advance_model(Stepper& stepper, const py::object& model_obj,
                            std::optional<double> end, std::optional<double> courant,
                            const py::object& callback, double stop_every, bool land_on_stops,
                            double energy_growth, std::optional<double> fourier,
                            const py::kwargs& earlier) {
  PyModel& pm = model_obj.cast<PyModel&>();
  for (const auto& [key, value] : earlier) {
    if (py::str(key).cast<std::string>() != "t_end")
      throw InputError("advance: unexpected argument '" + clip(py::str(key).cast<std::string>()) +
                       "'");
    warn_earlier_name("t_end", "end");
    end = value.cast<double>();
  }
  const AdvanceOptions options{.end = end.value_or(pm.time_settings.end),
                               .courant = courant.value_or(pm.time_settings.courant),
                               .fourier = fourier.value_or(pm.time_settings.fourier),
                               .stop_every = stop_every,
                               .land_on_stops = land_on_stops,
                               .failure = {.energy_growth = energy_growth},
                               .energy_start = {},
                               .observer_changes_model = !callback.is_none()};
  if (!(stop_every >= 0) || !std::isfinite(stop_every))
    throw InputError("stop_every must be non-negative, got " + std::to_string(stop_every));
  StepObserver observer;
  if (!callback.is_none())
    observer = [&](const Model&, const Energies& e, bool at_stop) {
      py::gil_scoped_acquire acquire;
      callback(model_obj, e, at_stop);
    };
  return interruptible([&](const std::atomic<int>* interrupt) {
    AdvanceOptions o = options;
    o.interrupt = interrupt;
    return advance(pm.model, stepper, o, observer);
  });
}

// The Courant relation of the time step (diagnostics.hpp).
void bind_courant(py::module_& m) {
  m.def(
      "stable_time_step",
      [](const PyModel& pm, double courant) { return stable_time_step(pm.model, courant); },
      py::arg("model"), py::arg("courant"),
      "Δt = C Δx_min / max(c_wave, max_p |V_p|) (FMPM 2026 §3.3)");
  m.def(
      "courant_of", [](const PyModel& pm, double dt) { return courant_of(pm.model, dt); },
      py::arg("model"), py::arg("dt"), "C = Δt max(c_wave, max_p |V_p|) / Δx_min");
  m.def(
      "diffusion_time",
      [](const PyModel& pm) {
        return diffusion_time(pm.model.grid, pm.model.materials, pm.model.particles);
      },
      py::arg("model"),
      "Δx_min² / D_max with D = κ/(ρ C_V) the largest diffusivity of the particles' materials "
      "(inf when none conducts): with heat transport advance() takes no step longer than F "
      "times this, F the Fourier number (transport.hpp)");
}

// The transport fields of a Stepper's last step (TransportState of scheme.hpp), copied: one
// value per transport node (the n_g nodes of the step's window of the grid, `nodes`).
struct TransportFields {
  py::array tau, T, gradient, q, tau_plus, theta, rate, nodes;
};

py::object transport_fields(const Stepper& s) {
  const Stepper::Exclusive hold(s);
  const TransportState& h = s.transport_state();
  if (s.options().transport.update == TransportUpdate::Off || h.tau.rows() == 0)
    return py::none();
  const Operators& ops = s.operators();
  py::array_t<long> nodes(ops.grid_node_count);
  auto out = nodes.mutable_unchecked<1>();
  for (Index i = 0; i < ops.grid_node_count; ++i)
    out(i) = long(ops.whole_node(i));
  return py::cast(TransportFields{from_field(h.tau, true), from_field(h.T, true),
                                  from_field(h.gradient, false), from_field(h.q, true),
                                  from_field(h.tau_plus, true), from_field(h.theta, true),
                                  from_field(h.rate, true), nodes});
}

void bind_transport_fields(py::module_& m) {
  py::class_<TransportFields>(m, "TransportState",
                              "The transport fields of a step (scheme.hpp, a copy): one value "
                              "per transport node (n_g, the grid nodes `nodes`), gradient one "
                              "row per particle.")
      .def_readonly("tau", &TransportFields::tau, "τ = Sᵀ 𝗖 T, the nodal heat content (task 1)")
      .def_readonly("T", &TransportFields::T,
                    "T = c⁻¹ τ with the temperature conditions set: the conduction's field")
      .def_readonly("gradient", &TransportFields::gradient, "N × d: ∇T_p = Σ_i G_pi T_i")
      .def_readonly("q", &TransportFields::q,
                    "heat flow −K T + Sᵀ M r + contact heat, with the conditions' reaction")
      .def_readonly("tau_plus", &TransportFields::tau_plus,
                    "τ⁺ = τ + q Δt with the conditions set (task 2.a)")
      .def_readonly("theta", &TransportFields::theta,
                    "θ⁺ = c̃_k⁻¹ τ⁺, the updated nodal temperatures (task 3.b)")
      .def_readonly("rate", &TransportFields::rate, "Ṫ = c⁻¹ q, the rate of the lumped update")
      .def_readonly("nodes", &TransportFields::nodes,
                    "the grid index of each row: the step's window of the grid");
}

void bind_advance_report(py::module_& m) {
  py::class_<AdvanceReport>(
      m, "AdvanceReport",
      "What advance did: the steps, the total energy at start and end, the wall time.")
      .def_readonly("steps", &AdvanceReport::steps, "steps taken")
      .def_readonly("energy_start", &AdvanceReport::energy_start,
                    "total energy the failure test compared with")
      .def_readonly("energy_end", &AdvanceReport::energy_end, "total energy at the end")
      .def_readonly("wall_seconds", &AdvanceReport::wall_seconds, "wall time of the loop (s)");
}

// What a Stepper's last step left: v⁺ on its nodes, the FMPM order and metrics it reached, its
// transport fields.
void bind_last_step(py::class_<Stepper>& c) {
  c.def_property_readonly(
       "grid_velocity",
       [](const Stepper& s) {
         const Stepper::Exclusive hold(s); // not while another thread steps it
         return from_field(s.grid_state().v_plus, false);
       },
       "v⁺ of the last step (n × d), the velocity of its particle update, on the nodes of "
       "the step (grid_nodes)")
      .def_property_readonly(
          "grid_nodes",
          [](const Stepper& s) {
            const Stepper::Exclusive hold(s);
            const Operators& ops = s.operators();
            py::array_t<long> nodes(ops.num_nodes());
            auto out = nodes.mutable_unchecked<1>();
            for (Index c = 0; c < ops.num_nodes(); ++c)
              out(c) = long(ops.whole_node(c));
            return nodes;
          },
          "the grid index of each row of grid_velocity: a step works on the window of the grid "
          "that its particles reach (α n_g + i for node i of velocity field α)")
      .def_property_readonly(
          "fmpm_order",
          [](const Stepper& s) {
            const Stepper::Exclusive hold(s);
            return s.last_fmpm().order;
          },
          "the FMPM order reached by the last step's loop")
      .def_property_readonly(
          "fmpm_metrics",
          [](const Stepper& s) {
            const Stepper::Exclusive hold(s);
            return s.last_fmpm_metrics();
          },
          "the convergence metric of passes 2, 3, ... of the last step's FMPM loop (dynamic "
          "FMPM; step.dynamic_limit = 0 runs it to the order)")
      .def_property_readonly("transport_state", &transport_fields,
                             "the transport fields of the last step (a TransportState: τ, T, q, "
                             "θ⁺, ... on its transport nodes); None without heat transport or "
                             "before the first step");
}

} // namespace

void bind_step(py::module_& m) {
  bind_transport_fields(m);
  bind_advance_report(m);
  py::class_<Stepper> c(m, "Stepper",
                        "Advances a Model by explicit MPM steps with fixed options (step.hpp); "
                        "keeps the operators and grid fields from step to step.");
  c.def(py::init<const StepOptions&>(), py::arg("options"))
      .def(
          "step", [](Stepper& s, PyModel& pm, double dt) { s.step(pm.model, dt); },
          py::arg("model"), py::arg("dt"), py::call_guard<py::gil_scoped_release>(),
          "One step of length dt (USL/USF/... of the options). Raises NumericalError naming the "
          "step, time and particle when the state becomes invalid.")
      .def("advance", &advance_model, py::arg("model"), py::arg("end") = py::none(),
           py::arg("courant") = py::none(), py::arg("callback") = py::none(),
           py::arg("stop_every") = 0.0, py::arg("land_on_stops") = true,
           py::arg("energy_growth") = 10.0, py::arg("fourier") = py::none(),
           "Steps to end (default model.end) with Δt = C Δx_min / max(c, max|V|), C = courant "
           "(default model.courant), before every step, and with heat transport at most F "
           "diffusion_time(model), F = fourier (default model.fourier; 0: 0.1) (the loop of "
           "`smpm run`; advance.hpp): callback(model, energies, at_stop) after every step, "
           "stops at multiples of stop_every (steps shortened to land on them unless "
           "land_on_stops is False), NumericalError when the total energy exceeds "
           "energy_growth times its start; Ctrl-C stops it after the step in progress "
           "(KeyboardInterrupt, the model at that step).")
      .def_property_readonly("options", &Stepper::options,
                             "the StepOptions the stepper was made with");
  bind_last_step(c);
  bind_courant(m);
}

} // namespace smpm::python
