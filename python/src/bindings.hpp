// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file bindings.hpp
/// The objects the Python module adds around the library's, and the functions that bind each
/// part of the library (one file each).

#include <sparsempm/input.hpp>
#include <sparsempm/model.hpp>
#include <sparsempm/operators.hpp>
#include <sparsempm/particle_columns.hpp>
#include <sparsempm/step.hpp>
#include <sparsempm/step_preparation.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

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
  Field X; ///< the particles' positions of the assembly (the velocity-gradient transfer's m̃_L)
  const Operators& ops() const { return prep.ops; }
  const Grid& grid() const { return prep.ops.grid; }
};

/// sparsempm.Transport: the heat-transport operators of one configuration (prepare_step and
/// prepare_heat_transport with a transport update, as the Stepper makes them, on the whole grid): 𝗖
/// = M C_V, V κ, c, the active transport nodes, the temperature conditions at the model's time, S
/// and G with their velocity fields' block columns folded onto the grid nodes (what transport
/// applies); c̃ on first use.
struct PyTransport {
  Shape shape = Shape::Linear;
  TransportUpdate update = TransportUpdate::FMPM;
  StepPreparation prep;
  SparseRowMatrix S;              ///< N × n_g: folded_columns(ops, ops.S)
  std::vector<SparseRowMatrix> G; ///< N × n_g each: the folded G_b
  const Operators& ops() const { return prep.ops; }
  const TransportOperators& transport() const { return prep.transport; }
};

/// A DeprecationWarning of the one vocabulary: "'old' is the earlier name of 'name' (accepted
/// in this release only)"; `note` given: that text instead (the input's notes).
void warn_earlier_name(const std::string& old_name, const std::string& name,
                       const std::string& note = {});

/// A Python value as TOML text: bool, number, string (quoted with `quote`; a top-level string of
/// an override as `--set` takes it), list, dict (an inline table). InputError otherwise.
std::string toml_value(const py::handle& v, bool quote);
/// The tables as TOML text: one [[name]] table for each dict.
std::string toml_tables(const char* name, const std::vector<py::dict>& tables);
/// An axis given as 0, 1, 2 or "x", "y", "z", as its name.
std::string axis_name(const py::handle& axis);
/// Fixed directions as the input files name them: ["x", "y"] (or the earlier "xy").
py::list axis_names(const py::handle& fixed);
/// Model.add_bc, Model.set_contact and Model.fix_plane: the tables read by the input reader.
Index add_bc(PyModel& pm, const py::dict& table);
void set_contact(PyModel& pm, const std::vector<py::dict>& tables);
Index fix_plane(PyModel& pm, const py::handle& axis, double at, const py::handle& fixed);

/// validate(mat) of the library, and the heat keys non-negative and finite (0: not given), as
/// the input reader holds them.
void validate_material(const Material& mat);

/// Parses a name of the input files' vocabulary into a shape etc.; InputError on a bad name.
Shape shape_arg(const py::object& shape, const PyModel* model);

void bind_options(py::module_& m);
void bind_model(py::module_& m);
/// sparsempm.Grid (particles.cpp).
void bind_grid(py::module_& m);
/// sparsempm.Particles (particles.cpp).
void bind_particles(py::module_& m);
/// Column `col` of the particles (particle_columns) from a number or the particles' values (N,
/// or N × width), each in the column's range; the storage is kept when the particles have the
/// column already (numpy views stay valid). Throws InputError naming the particle and value.
void set_part_column(Particles& P, const ParticleColumn& col,
                     const py::array_t<double, py::array::forcecast>& a);
void bind_operators(py::module_& m);
/// sparsempm.transport_operators, Transport, fmpm_temperature and exact_temperature.
void bind_transport(py::module_& m);
void bind_step(py::module_& m);
void bind_analysis(py::module_& m);

} // namespace smpm::python
