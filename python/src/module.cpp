// The module _sparsempm: the library's operators, steps and analyses for Python (the package
// sparsempm re-exports it). Errors come out as the exceptions of the command line, with its
// messages: InputError (ValueError), NumericalError and UsageError (RuntimeError).

#include "bindings.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/version.hpp>

PYBIND11_MODULE(_sparsempm, m) {
  using namespace smpm;
  using namespace smpm::python;
  m.doc() = "sparsempm: the Material Point Method with explicit sparse operators";
  m.attr("__version__") = std::string(kVersion);
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception<UsageError>(m, "UsageError", PyExc_RuntimeError);
  bind_model(m);
  bind_operators(m);
  bind_step(m);
  bind_analysis(m);
}
