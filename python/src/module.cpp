// SPDX-License-Identifier: BSD-3-Clause
// The module _sparsempm: the library's operators, steps and analyses for Python (the package
// sparsempm re-exports it). Errors come out as the exceptions of the command line, with its
// messages: InputError (ValueError), NumericalError and UsageError (RuntimeError).

#include "bindings.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/threads.hpp>
#include <sparsempm/version.hpp>

PYBIND11_MODULE(_sparsempm, m) {
  using namespace smpm;
  using namespace smpm::python;
  m.doc() = "sparsempm: the Material Point Method with explicit sparse operators";
  m.attr("__version__") = std::string(kVersion);
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception<UsageError>(m, "UsageError", PyExc_RuntimeError);
  bind_options(m);
  bind_model(m);
  bind_operators(m);
  bind_step(m);
  bind_analysis(m);
  m.def("threads", &threads,
        "Threads of the library's kernels (SMPM_THREADS, OMP_NUM_THREADS or every core); the "
        "results are the same bit for bit for any number.");
  m.def("set_threads", &set_threads, py::arg("count"),
        "Uses `count` >= 1 threads in the kernels from now on.");
  threads_from_environment(); // SMPM_THREADS at import: a bad value fails the import
}
