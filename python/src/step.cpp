// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.Stepper: the library's Stepper (one step) and advance() (the run loop of `smpm
// run`), with the GIL released while they run.

#include "bindings.hpp"
#include "convert.hpp"
#include "interrupt.hpp"

#include <sparsempm/advance.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/scheme.hpp>

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
                            double energy_growth, const py::kwargs& earlier) {
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
}

} // namespace

void bind_step(py::module_& m) {
  py::class_<AdvanceReport>(
      m, "AdvanceReport",
      "What advance did: the steps, the total energy at start and end, the wall time.")
      .def_readonly("steps", &AdvanceReport::steps, "steps taken")
      .def_readonly("energy_start", &AdvanceReport::energy_start,
                    "total energy the failure test compared with")
      .def_readonly("energy_end", &AdvanceReport::energy_end, "total energy at the end")
      .def_readonly("wall_seconds", &AdvanceReport::wall_seconds, "wall time of the loop (s)");

  py::class_<Stepper>(m, "Stepper",
                      "Advances a Model by explicit MPM steps with fixed options (step.hpp); "
                      "keeps the operators and grid fields from step to step.")
      .def(py::init<const StepOptions&>(), py::arg("options"))
      .def(
          "step", [](Stepper& s, PyModel& pm, double dt) { s.step(pm.model, dt); },
          py::arg("model"), py::arg("dt"), py::call_guard<py::gil_scoped_release>(),
          "One step of length dt (USL/USF/... of the options). Raises NumericalError naming the "
          "step, time and particle when the state becomes invalid.")
      .def("advance", &advance_model, py::arg("model"), py::arg("end") = py::none(),
           py::arg("courant") = py::none(), py::arg("callback") = py::none(),
           py::arg("stop_every") = 0.0, py::arg("land_on_stops") = true,
           py::arg("energy_growth") = 10.0,
           "Steps to end (default model.end) with Δt = C Δx_min / max(c, max|V|), C = courant "
           "(default model.courant), before every step (the loop of "
           "`smpm run`; advance.hpp): callback(model, energies, at_stop) after every step, "
           "stops at multiples of stop_every (steps shortened to land on them unless "
           "land_on_stops is False), NumericalError when the total energy exceeds "
           "energy_growth times its start; Ctrl-C stops it after the step in progress "
           "(KeyboardInterrupt, the model at that step).")
      .def_property_readonly("options", &Stepper::options,
                             "the StepOptions the stepper was made with")
      .def_property_readonly(
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
          "FMPM; step.dynamic_limit = 0 runs it to the order)");
  bind_courant(m);
}

} // namespace smpm::python
