// SPDX-License-Identifier: BSD-3-Clause
// Python values as the tables of the input files: the --set overrides of Model.from_toml and the
// [[bc]] and [[contact]] tables of Model.add_bc and Model.set_contact, written as TOML text and
// read by the input reader itself (the same checks and messages as `smpm run`).

#include "bindings.hpp"

#include <sparsempm/errors.hpp>

#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <vector>

namespace smpm::python {

void warn_earlier_name(const std::string& old_name, const std::string& name,
                       const std::string& note) {
  const std::string text = !note.empty() ? note
                                         : "'" + old_name + "' is the earlier name of '" + name +
                                               "' (accepted in this release only)";
  if (PyErr_WarnEx(PyExc_DeprecationWarning, text.c_str(), 1) != 0)
    throw py::error_already_set();
}

std::string toml_value(const py::handle& v, bool quote) {
  if (py::isinstance<py::bool_>(v))
    return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))
    return py::repr(v).cast<std::string>();
  if (py::isinstance<py::str>(v)) {
    const std::string s = v.cast<std::string>();
    return quote ? py::repr(v).cast<std::string>() : s; // a top-level string: as `--set` takes it
  }
  if (py::isinstance<py::dict>(v)) { // an inline table, e.g. plane = {axis = "x", at = 0.0}
    std::string out = "{";
    for (const auto& [key, value] : v.cast<py::dict>())
      out += (out.size() > 1 ? ", " : " ") + py::str(key).cast<std::string>() + " = " +
             toml_value(value, true);
    return out + " }";
  }
  if (py::isinstance<py::sequence>(v)) {
    std::string out = "[";
    bool first = true;
    for (const py::handle item : v) {
      out += (first ? "" : ", ") + toml_value(item, true);
      first = false;
    }
    return out + "]";
  }
  throw InputError("value " + py::repr(v).cast<std::string>() +
                   ": expected a bool, number, string, list or dict");
}

std::string toml_tables(const char* name, const std::vector<py::dict>& tables) {
  std::string text;
  for (const py::dict& t : tables) {
    text += std::string("[[") + name + "]]\n";
    for (const auto& [key, value] : t)
      text += py::str(key).cast<std::string>() + " = " + toml_value(value, true) + "\n";
  }
  return text;
}

std::string axis_name(const py::handle& axis) {
  if (py::isinstance<py::str>(axis))
    return axis.cast<std::string>();
  const long a = axis.cast<long>();
  if (a < 0 || a > 2)
    throw InputError("axis " + std::to_string(a) + ": expected 0, 1, 2 or x, y, z");
  return std::string(1, char('x' + a));
}

py::list axis_names(const py::handle& fixed) {
  py::list out;
  if (py::isinstance<py::str>(fixed)) { // "xy": the earlier form of ["x", "y"]
    for (const char c : fixed.cast<std::string>())
      out.append(std::string(1, c));
    return out;
  }
  for (const py::handle a : fixed)
    out.append(axis_name(a));
  return out;
}

Index add_bc(PyModel& pm, const py::dict& table) {
  const ConditionTables read =
      read_bc_tables(toml_tables("bc", {table}), pm.source + " (add_bc)", pm.model.grid);
  if (!read.temperature.conditions.empty()) { // a temperature condition: one per node
    BoundaryConditions added = read.temperature;
    // The reader numbers the tables of its text ("bc.0.temperature"): named here by the call,
    // so that a node held twice names both conditions apart.
    for (VelocityCondition& c : added.conditions)
      c.label =
          "add_bc(temperature=" + clip(py::repr(table["temperature"]).cast<std::string>()) + ")";
    BoundaryConditions all = pm.model.temperature_bcs;
    all.append(added);
    all.check_one_condition_per_node();
    pm.model.temperature_bcs = std::move(all);
    return read.temperature.num_constrained();
  }
  const BoundaryConditions& bcs = read.velocity;
  const Index nodes = bcs.num_constrained();
  BoundaryConditions all = pm.model.bcs;
  all.append(bcs);
  all.check_superposition(); // against the conditions already there, as the input reader does
  pm.model.bcs = std::move(all);
  return nodes;
}

void set_contact(PyModel& pm, const std::vector<py::dict>& tables) {
  pm.model.contact =
      read_contact_tables(toml_tables("contact", tables), pm.source + " (set_contact)",
                          pm.model.materials, pm.model.grid.dim());
}

Index fix_plane(PyModel& pm, const py::handle& axis, double at, const py::handle& fixed) {
  py::dict table;
  py::dict plane;
  plane["axis"] = axis_name(axis);
  plane["at"] = at;
  table["plane"] = plane;
  const py::list axes = axis_names(fixed);
  table["fixed"] = axes;
  return add_bc(pm, table) / Index(std::max<size_t>(1, axes.size())); // nodes, not pairs
}

} // namespace smpm::python
