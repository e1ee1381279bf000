#pragma once
/// \file bindings.hpp
/// The objects the Python module adds around the library's, and the functions that bind each
/// part of the library (one file each).

#include <sparsempm/input.hpp>
#include <sparsempm/model.hpp>
#include <sparsempm/operators.hpp>
#include <sparsempm/step.hpp>
#include <sparsempm/step_preparation.hpp>

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>

namespace smpm::python {

namespace py = pybind11;

/// sparsempm.Model: the library's Model with the step options and clock settings of its input
/// ([step] and [time] of a TOML file; defaults for a model built from arrays).
struct PyModel {
  Model model;
  StepOptions options;
  TimeSettings time_settings;
  std::string source; ///< input file, or "<arrays>"
};

/// sparsempm.Operators: the preparation of a step from one configuration (prepare_step, as the
/// Stepper makes it) on the whole grid: the operators, the velocity BCs with the walls' nodes at
/// the model's time, the contact nodes; m̃ in its stencil storage on first use (FMPM passes,
/// exact solve, spectra). A multimaterial model's velocity fields are blocks of columns of S.
struct PyOperators {
  Shape shape = Shape::Linear;
  StepPreparation prep;
  const Operators& ops() const { return prep.ops; }
  const Grid& grid() const { return prep.ops.grid; }
};

/// Parses a name of the input files' vocabulary into a shape etc.; InputError on a bad name.
Shape shape_arg(const py::object& shape, const PyModel* model);

void bind_options(py::module_& m);
void bind_model(py::module_& m);
void bind_operators(py::module_& m);
void bind_step(py::module_& m);
void bind_analysis(py::module_& m);

} // namespace smpm::python
