// SPDX-License-Identifier: BSD-3-Clause
// Spectra and stability from Python: the linearised step T (stability.hpp) with its
// matrix-vector product for scipy's LinearOperator, ρ(T), the critical Courant numbers by the
// spectral and the simulation methods (FMPM 2026 §3.3, Fig. 12), the critical Fourier number of
// heat transport (transport_stability.hpp) and the spectrum of the mass matrices (spectrum.hpp).
// The GIL is released while they compute. The results' names are the tables' columns.

#include "bindings.hpp"
#include "convert.hpp"
#include "interrupt.hpp"

#include <sparsempm/advance.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>
#include <sparsempm/transport_stability.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>

namespace smpm::python {

namespace {

// T at Courant number C: the time step of the Courant relation, as `smpm spectrum --courant`
// takes it.
LinearizedStep linearized(const PyModel& pm, const StepOptions& options, double courant) {
  return LinearizedStep(pm.model, options, stable_time_step(pm.model, courant));
}

const StepOptions& options_or(const PyModel& pm, const std::optional<StepOptions>& options) {
  return options ? *options : pm.options;
}

void bind_linearized_step(py::module_& m) {
  py::class_<LinearizedStep>(m, "LinearizedStep",
                             "One step linearised at the model's frozen configuration: a linear "
                             "map T on x = (V, σ), N d + N d² entries (stability.hpp).")
      .def(
          py::init([](const PyModel& pm, const std::optional<StepOptions>& options,
                      double courant) { return linearized(pm, options_or(pm, options), courant); }),
          py::arg("model"), py::arg("options") = py::none(), py::arg("courant") = 0.5)
      .def_property_readonly("rows", &LinearizedStep::rows, "rows of T: the state x = (V, sigma)")
      .def_property_readonly("dt", &LinearizedStep::dt, "the time step of T at its Courant number")
      .def_property_readonly("steps_per_application", &LinearizedStep::steps_per_application,
                             "steps s one product with T spans (rho per step: rho^(1/s))")
      .def(
          "matvec",
          [](const LinearizedStep& T,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& x) {
            // c_style: a strided x (a column of a C-ordered X in T @ X) arrives as a copy.
            if (x.ndim() != 1 || x.shape(0) != T.rows())
              throw std::invalid_argument("matvec: expected a vector of " +
                                          std::to_string(T.rows()) + " entries");
            py::array_t<double> y(T.rows());
            const double* in = x.data();
            double* out = y.mutable_data();
            {
              py::gil_scoped_release release;
              T.perform_op(in, out);
            }
            return y;
          },
          py::arg("x"), "y = T x")
      .def(
          "dense",
          [](const LinearizedStep& T) {
            Eigen::MatrixXd D;
            {
              py::gil_scoped_release release;
              D = T.dense();
            }
            py::array_t<double> a({D.rows(), D.cols()});
            for (Index i = 0; i < D.rows(); ++i)
              for (Index j = 0; j < D.cols(); ++j)
                a.mutable_at(i, j) = D(i, j);
            return a;
          },
          "T as a dense rows × rows array (one product per column)");
}

// The value of an earlier attribute name, with its DeprecationWarning (this release only).
template <class T>
auto earlier(const char* old_name, const char* name, double T::*member) {
  return [=](const T& r) {
    warn_earlier_name(old_name, name);
    return r.*member;
  };
}

// ρ(T), C* and F* with their searches' counts.
void bind_results(py::module_& m) {
  py::class_<SpectralRadius>(m, "SpectralRadius", "rho(T) and how it was found (stability.hpp).")
      .def_readonly("rho_T", &SpectralRadius::rho_T, "rho(T), the largest |eigenvalue|")
      .def_property_readonly(
          "status", [](const SpectralRadius& r) { return std::string(to_string(r.status)); },
          "converged | not converged | non-finite")
      .def_property_readonly("rho", earlier("rho", "rho_T", &SpectralRadius::rho_T),
                             "the earlier name of rho_T (this release only)")
      .def("__float__", [](const SpectralRadius& r) { return r.rho_T; });
  py::class_<CriticalCourant>(
      m, "CriticalCourant",
      "The spectral critical Courant number C* and the search's counts (stability.hpp).")
      .def_readonly("critical_courant", &CriticalCourant::critical_courant,
                    "C*: the upper end of the stable interval [stable_from, C*], the largest C "
                    "found with rho(T(C)) <= 1 + tol (within the resolution) above the smallest "
                    "stable C; the critical_courant column of `smpm stability`")
      .def_readonly("stable_from", &CriticalCourant::stable_from,
                    "the lower end of the stable interval: 0 when every C examined below C* is "
                    "stable, else the first stable grid point above the highest unstable C")
      .def_property_readonly(
          "small", [](const CriticalCourant& c) { return std::string(to_string(c.small)); },
          "what lies below the interval: stable | stable to floor | unstable below | unstable")
      .def_property_readonly(
          "small_courant", [](const CriticalCourant& c) { return small_courant_text(c); },
          "the small_courant column of `smpm stability`, e.g. 'unstable "
          "below 0.0406' or 'stable to 0'")
      .def_readonly("floor", &CriticalCourant::floor,
                    "the lowest C examined (min(0.05, c_max) / 4^j), the limit C -> 0 aside")
      .def_readonly("rho_limit", &CriticalCourant::rho_limit,
                    "rho(T) as C -> 0, the zero-order term (NaN: not examined)")
      .def_readonly("growth_rate", &CriticalCourant::growth_rate,
                    "gamma in rho(T(C)) ~ rho(T(0)) + gamma C + a C^2 as C -> 0 (Richardson from "
                    "the two lowest points): the growth over the time of one C = 1 step; the limit "
                    "is stable when gamma <= tol (NaN: not examined)")
      .def_readonly("rho_T", &CriticalCourant::rho_T, "rho(T) at C* (the growth per step)")
      .def_readonly("evaluations", &CriticalCourant::evaluations, "spectral radii computed")
      .def_readonly("not_converged", &CriticalCourant::not_converged,
                    "of them, Arnoldi runs that did not converge")
      .def_readonly("non_finite", &CriticalCourant::non_finite,
                    "of them, non-finite results (counted as unstable)")
      .def_property_readonly(
          "courant", earlier("courant", "critical_courant", &CriticalCourant::critical_courant),
          "the earlier name of critical_courant (this release only)")
      .def_property_readonly("rho", earlier("rho", "rho_T", &CriticalCourant::rho_T),
                             "the earlier name of rho_T (this release only)")
      .def("__float__", [](const CriticalCourant& c) { return c.critical_courant; });
  py::class_<CriticalFourier>(
      m, "CriticalFourier",
      "The critical Fourier number F* of heat transport and the search's counts "
      "(transport_stability.hpp).")
      .def_readonly("critical_fourier", &CriticalFourier::critical_fourier,
                    "F*: the upper end of the stable interval [stable_from, F*], the largest "
                    "Fourier number F found with rho(T(F)) <= 1 + tol (within the resolution) "
                    "above the smallest stable F; the critical_fourier column of `smpm "
                    "transport-stability`")
      .def_readonly("stable_from", &CriticalFourier::stable_from,
                    "the lower end of the stable interval [stable_from, F*]: 0 when every F "
                    "examined below F* is stable")
      .def_property_readonly(
          "small", [](const CriticalFourier& c) { return std::string(to_string(c.small)); },
          "what lies below the interval: stable | stable to floor | unstable below | unstable")
      .def_property_readonly(
          "small_fourier",
          [](const CriticalFourier& c) {
            return small_courant_text(c.small, c.stable_from, c.floor);
          },
          "the words of the small_fourier column of `smpm transport-stability`, e.g. 'stable "
          "to 0'")
      .def_readonly("floor", &CriticalFourier::floor,
                    "the lowest F examined (0.05 / 4^j), the limit F -> 0 aside")
      .def_readonly("rho_limit", &CriticalFourier::rho_limit, "rho(T) as F -> 0")
      .def_readonly("growth_rate", &CriticalFourier::growth_rate,
                    "gamma in rho(T(F)) ~ rho(T(0)) + gamma F as F -> 0")
      .def_readonly("rho_T", &CriticalFourier::rho_T, "rho(T) of the transport step at F*")
      .def_readonly("evaluations", &CriticalFourier::evaluations, "spectral radii computed")
      .def_readonly("not_converged", &CriticalFourier::not_converged,
                    "of them, Arnoldi runs that did not converge")
      .def_readonly("non_finite", &CriticalFourier::non_finite,
                    "of them, non-finite results (counted as unstable)")
      .def("__float__", [](const CriticalFourier& c) { return c.critical_fourier; });
}

// The results of the searches over configurations and by simulation, and the mass spectrum.
void bind_sweep_results(py::module_& m) {
  py::class_<ConfigurationSweep>(
      m, "ConfigurationSweep",
      "C* over configurations (lattice shifts, frames): the smallest and each (stability.hpp).")
      .def_readonly("minimum", &ConfigurationSweep::minimum,
                    "the CriticalCourant of the configuration with the smallest C*")
      .def_readonly("configuration", &ConfigurationSweep::configuration,
                    "which configuration set it, e.g. 'shift 0.25'")
      .def_readonly("lowest", &ConfigurationSweep::lowest,
                    "the CriticalCourant whose small C are the worst (unstable, unstable below, "
                    "then the largest stable_from): every configuration is stable on "
                    "[lowest.stable_from, minimum.critical_courant] at the points examined")
      .def_readonly("lowest_configuration", &ConfigurationSweep::lowest_configuration,
                    "which configuration set it")
      .def_readonly("all", &ConfigurationSweep::all,
                    "every configuration and its C*, as (name, C*) pairs");
  py::class_<SimulationCourant>(
      m, "SimulationCourant",
      "The simulation C*: the largest Courant number whose run does not fail (stability.hpp).")
      .def_readonly("simulation_courant", &SimulationCourant::simulation_courant,
                    "simulation C*: the largest C whose run does not fail (NaN: none in the "
                    "bracket); the simulation_courant column of `smpm stability`")
      .def_readonly("energy_change", &SimulationCourant::energy_change,
                    "(E_end - E_0)/E_0 of the run at C*")
      .def_readonly("runs", &SimulationCourant::runs, "runs made by the search")
      .def_property_readonly(
          "courant",
          earlier("courant", "simulation_courant", &SimulationCourant::simulation_courant),
          "the earlier name of simulation_courant (this release only)")
      .def("__float__", [](const SimulationCourant& c) { return c.simulation_courant; });
  py::class_<MassSpectrum>(
      m, "MassSpectrum",
      "The spectrum of the mass matrices: rho(A), lambda_min(m^-1 m~), cond(m~) (spectrum.hpp).")
      .def_readonly("rho_A", &MassSpectrum::rho_A,
                    "rho(A) = 1 - lambda_min(m^-1 m~) on the active nodes")
      .def_readonly("min_eig_minv_mt", &MassSpectrum::min_eig_minv_mt, "lambda_min(m^-1 m~)")
      .def_readonly("cond_mt", &MassSpectrum::cond_mt,
                    "lambda_max(m~)/lambda_min(m~) on the active nodes")
      .def_readonly("active", &MassSpectrum::active, "number of active nodes");
}

// The critical Courant numbers: spectral at one configuration and over lattice shifts, and by
// simulation (FMPM 2026 §3.3).
void bind_courant_searches(py::module_& m) {
  m.def(
      "critical_courant",
      [](const PyModel& pm, const std::optional<StepOptions>& options, double tol, double c_max,
         double resolution, double hint) {
        const StepOptions& o = options_or(pm, options);
        return interruptible([&](const std::atomic<int>* interrupt) {
          return critical_courant(pm.model, o, tol, c_max, resolution, hint, interrupt);
        });
      },
      py::arg("model"), py::arg("options") = py::none(), py::arg("tol") = 1e-6,
      py::arg("c_max") = 2.0, py::arg("resolution") = 1e-3, py::arg("hint") = 0.0,
      "C* = max{C : ρ(T(C)) ≤ 1 + tol} at the model's configuration (bisection to "
      "resolution); options default to model.options. hint > 0 (the C* of a neighbouring "
      "scheme) starts the search there: the same C*, fewer evaluations (.evaluations).");
  m.def(
      "sweep_shifts",
      [](const PyModel& pm, const std::optional<StepOptions>& options, int shifts, double tol,
         double resolution, int workers) {
        const StepOptions& o = options_or(pm, options);
        return interruptible([&](const std::atomic<int>* interrupt) {
          return sweep_shifts(pm.model, o, shifts, tol, resolution, workers, interrupt);
        });
      },
      py::arg("model"), py::arg("options") = py::none(), py::arg("shifts") = 4,
      py::arg("tol") = 1e-6, py::arg("resolution") = 1e-3, py::arg("workers") = 0,
      "The minimum of C* over `shifts` lattice shifts: the spectral column of `smpm "
      "stability` (--shifts), one shift per task on `workers` threads (0: threads()).");
  m.def(
      "simulation_courant",
      [](const PyModel& pm, const std::optional<StepOptions>& options, std::optional<double> end,
         double lo, double hi, double resolution, double energy_growth, double max_energy_change) {
        SimulationCourantOptions sim;
        sim.end = end ? *end : pm.time_settings.end;
        sim.lo = lo;
        sim.hi = hi;
        sim.resolution = resolution;
        sim.failure.energy_growth = energy_growth;
        sim.max_energy_change = max_energy_change;
        const StepOptions& o = options_or(pm, options);
        return interruptible([&](const std::atomic<int>* interrupt) {
          sim.interrupt = interrupt;
          return simulation_courant(pm.model, o, sim);
        });
      },
      py::arg("model"), py::arg("options") = py::none(), py::arg("end") = py::none(),
      py::arg("lo") = 0.02, py::arg("hi") = 1.5, py::arg("resolution") = 0.005,
      py::arg("energy_growth") = 10.0,
      py::arg("max_energy_change") = std::numeric_limits<double>::infinity(),
      "The largest C whose full run to `end` (default model.end) does not fail, by bisection: "
      "the simulation column of `smpm stability`.");
}

// The critical Fourier number F* of heat transport (transport_stability.hpp).
void bind_fourier_search(py::module_& m) {
  m.def(
      "critical_fourier",
      [](const PyModel& pm, const std::optional<StepOptions>& options, double tol, double f_max,
         double resolution, double hint) {
        const StepOptions& o = options_or(pm, options);
        return interruptible([&](const std::atomic<int>* interrupt) {
          return critical_fourier(pm.model, o, tol, f_max, resolution, hint, interrupt);
        });
      },
      py::arg("model"), py::arg("options") = py::none(), py::arg("tol") = 1e-6,
      py::arg("f_max") = 4.0, py::arg("resolution") = 1e-3, py::arg("hint") = 0.0,
      "F* = max{F : rho(T(F)) <= 1 + tol} of heat transport at the model's configuration, T(F) "
      "the transport step with dt = F * diffusion_time(model) (bisection to resolution; one "
      "configuration of `smpm transport-stability`, which takes the smallest over lattice "
      "shifts). options default to model.options and must have heat transport "
      "(options.transport 'lumped', 'FMPM' or 'exact'). Returns a CriticalFourier.");
}

} // namespace

void bind_analysis(py::module_& m) {
  bind_linearized_step(m);
  bind_results(m);
  bind_sweep_results(m);
  bind_courant_searches(m);
  bind_fourier_search(m);
  m.def(
      "_spectral_radius",
      [](const LinearizedStep& T, Index dense_limit) { return spectral_radius(T, dense_limit); },
      py::arg("T"), py::arg("dense_limit") = 1500, py::call_guard<py::gil_scoped_release>());
  m.def(
      "mass_spectrum",
      [](PyOperators& o, Index dense_limit) {
        const SparseRowMatrix& mt = o.prep.consistent_mass();
        py::gil_scoped_release release;
        return mass_spectrum(o.ops(), mt, dense_limit);
      },
      py::arg("ops"), py::arg("dense_limit") = 2000,
      "ρ(A), λ_min(m⁻¹m̃) and cond(m̃) on the active nodes (spectrum.hpp)");
}

} // namespace smpm::python
