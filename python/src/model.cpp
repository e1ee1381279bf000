// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.Grid, Particles and Model: the state of a run, read from a TOML input (the reader of
// `smpm run`) or built from numpy arrays, with the tables of the input files (add_bc,
// set_contact) read by the same reader.

#include "bindings.hpp"
#include "convert.hpp"

#include <sparsempm/diagnostics.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/particle_columns.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <deque>
#include <sstream>

namespace smpm::python {

namespace {

using DoubleArray = py::array_t<double, py::array::forcecast>;

std::array<double, 3> triple(const std::vector<double>& v, double fill, const char* name) {
  if (v.size() > 3)
    throw InputError(std::string(name) + ": at most 3 entries, got " + std::to_string(v.size()));
  std::array<double, 3> t{fill, fill, fill};
  std::copy(v.begin(), v.end(), t.begin());
  return t;
}

// The particles of sparsempm.Model(grid, X, mass, volume0, ...), with the checks of the input
// reader in its words.
Particles
particles_from_arrays(const Grid& grid, const DoubleArray& X, const DoubleArray& mass,
                      const DoubleArray& volume0, const std::optional<DoubleArray>& V,
                      const std::optional<py::array_t<int, py::array::forcecast>>& material,
                      size_t materials) {
  const int d = grid.dim();
  const Field x = to_field(X, -1, "X");
  const Index N = x.rows();
  if (x.cols() != d)
    throw InputError("X: expected " + std::to_string(d) + " columns (the grid's dimension), got " +
                     std::to_string(x.cols()));
  Particles P;
  P.resize(d, N);
  P.X = x;
  P.mass = to_field(mass, N, "mass").col(0);
  P.volume0 = to_field(volume0, N, "volume0").col(0);
  if (V)
    P.V = to_field(*V, N, "V");
  if (P.V.cols() != d)
    throw InputError("V: expected " + std::to_string(d) + " columns");
  if (material)
    for (Index p = 0; p < N; ++p)
      P.material[p] = material->at(p);
  for (Index p = 0; p < N; ++p) {
    if (!(P.mass[p] > 0) || !std::isfinite(P.mass[p]) || !(P.volume0[p] > 0) ||
        !std::isfinite(P.volume0[p]))
      throw InputError("particle " + std::to_string(p) + ": mass and volume must be positive");
    if (P.material[p] < 0 || P.material[p] >= int(materials))
      throw InputError("particle " + std::to_string(p) + ": material id " +
                       std::to_string(P.material[p]) + " has no material (" +
                       std::to_string(materials) + " given)");
    std::array<double, 3> at{0, 0, 0};
    for (int a = 0; a < d; ++a)
      at[size_t(a)] = P.X(p, a);
    if (!grid.contains(at))
      throw InputError("particle " + std::to_string(p) + " lies outside the grid");
  }
  for (Index p = 0; p < N; ++p) // default domain: the cube of the particle's volume
    P.half_length.row(p).setConstant(0.5 * std::pow(P.volume0[p], 1.0 / d));
  return P;
}

// Column `col` of the particles (particle_columns) from a number or the particles' values (N,
// or N × width), each in the column's range (positive temperatures, non-negative plastic
// strains, finite values), as the input reader holds [[body]] temperature and heat_source. The
// particles' storage is kept when it has the column already (numpy views stay valid).
void set_part_column(Particles& P, const ParticleColumn& col, const DoubleArray& a) {
  const std::string name(col.name);
  Field v(P.size(), column_width(col, P.dim));
  if (col.vector) // a number or shape (N,)
    v.col(0) = particle_vector(a, P.size(), name.c_str());
  else if (a.ndim() == 0)
    v.setConstant(*a.data());
  else
    assign_field(v, a, name.c_str());
  for (Index k = 0; k < v.size(); ++k) {
    const double x = v.data()[k];
    const bool ok = std::isfinite(x) && (col.range == ColumnRange::Positive      ? x > 0
                                         : col.range == ColumnRange::NonNegative ? x >= 0
                                                                                 : true);
    if (!ok)
      throw InputError(
          name + ": particle " + std::to_string(k / v.cols()) + " has " + number_text(x) +
          (col.range == ColumnRange::Positive      ? " (it must be positive and finite)"
           : col.range == ColumnRange::NonNegative ? " (it must be non-negative and finite)"
                                                   : " (it must be finite)"));
  }
  if (has_column(P, col))
    column_values(P, col) = v; // copied into the same storage: numpy views of it stay valid
  else
    set_column(P, col, v); // was empty: no view holds any of it
}

// sparsempm.Model(grid, X, mass, volume0, ...): `earlier` holds the earlier names volume and
// body_force (accepted in this release only).
PyModel model_from_arrays(const Grid& grid, const DoubleArray& X, const DoubleArray& mass,
                          std::optional<DoubleArray> volume0, const std::optional<DoubleArray>& V,
                          const std::optional<py::array_t<int, py::array::forcecast>>& material,
                          const std::vector<Material>& materials,
                          const std::optional<DoubleArray>& half_length, const py::list& fixed,
                          std::vector<double> gravity,
                          const std::optional<DoubleArray>& temperature,
                          const std::optional<DoubleArray>& heat_source,
                          const py::kwargs& earlier) {
  for (const auto& [key, value] : earlier) {
    const std::string k = py::str(key);
    if (k == "volume") {
      warn_earlier_name("volume", "volume0");
      volume0 = value.cast<DoubleArray>();
    } else if (k == "body_force") {
      warn_earlier_name("body_force", "gravity");
      gravity = value.cast<std::vector<double>>();
    } else {
      throw InputError("Model: unexpected argument '" + clip(k) + "'");
    }
  }
  if (!volume0)
    throw InputError("Model: give volume0, the initial volume of every particle");
  if (materials.empty())
    throw InputError("materials: give at least one Material");
  for (const Material& mat : materials)
    validate_material(mat);
  PyModel pm;
  pm.source = "<arrays>";
  pm.model = Model(grid);
  pm.model.materials = materials;
  Particles& P = pm.model.particles;
  P = particles_from_arrays(grid, X, mass, *volume0, V, material, materials.size());
  if (half_length)
    P.half_length = to_field(*half_length, P.size(), "half_length");
  if (P.half_length.cols() != grid.dim())
    throw InputError("half_length: expected " + std::to_string(grid.dim()) + " columns");
  update_stress(pm.model.materials, P.material, P.F, P.stress);
  for (const ParticleColumn& col : particle_columns()) {
    if (col.name == "temperature" && temperature)
      set_part_column(P, col, *temperature);
    if (col.name == "heat_source" && heat_source)
      set_part_column(P, col, *heat_source);
  }
  for (const py::handle plane : fixed) {
    const py::tuple t = plane.cast<py::tuple>();
    if (t.size() != 3)
      throw InputError("fixed: expected (axis, at, [directions]) for every plane");
    fix_plane(pm, t[0], t[1].cast<double>(), t[2]);
  }
  pm.model.gravity = triple(gravity, 0.0, "gravity");
  return pm;
}

void bind_grid(py::module_& m) {
  py::class_<Grid>(m, "Grid", "A structured grid in 1, 2 or 3 dimensions (grid.hpp).")
      .def(py::init([](const std::vector<int>& cells, const std::vector<double>& cell_size,
                       const std::vector<double>& origin) {
             if (cells.empty() || cells.size() > 3)
               throw InputError("cells: give 1 to 3 cell counts (one per axis)");
             const auto h =
                 triple(cell_size.empty() ? std::vector<double>(cells.size(), 1.0) : cell_size, 1.0,
                        "cell_size");
             std::array<int, 3> n{1, 1, 1};
             std::copy(cells.begin(), cells.end(), n.begin());
             return Grid(int(cells.size()), triple(origin, 0.0, "origin"), h, n);
           }),
           py::arg("cells"), py::arg("cell_size") = std::vector<double>{},
           py::arg("origin") = std::vector<double>{},
           "Grid(cells, cell_size=[1, ...], origin=[0, ...]); the dimension is len(cells).")
      .def_property_readonly("dim", &Grid::dim, "dimension d (1, 2 or 3)")
      .def_property_readonly("num_nodes", &Grid::num_nodes, "number of grid nodes")
      .def_property_readonly(
          "cells",
          [](const Grid& g) {
            std::vector<int> c;
            for (int a = 0; a < g.dim(); ++a)
              c.push_back(g.cells(a));
            return c;
          },
          "cells along each axis")
      .def_property_readonly(
          "cell_size",
          [](const Grid& g) {
            std::vector<double> h;
            for (int a = 0; a < g.dim(); ++a)
              h.push_back(g.cell_size(a));
            return h;
          },
          "cell size along each axis")
      .def_property_readonly(
          "origin",
          [](const Grid& g) {
            std::vector<double> o;
            for (int a = 0; a < g.dim(); ++a)
              o.push_back(g.origin(a));
            return o;
          },
          "position of node (0, 0, 0)")
      .def(
          "node_positions", [](const Grid& g) { return from_field(g.node_positions(), false); },
          "n × d node positions, one row per node (node i + nx (j + ny k)).");
}

// A field property of Particles: a numpy view of the C++ storage (read and write in place);
// assigning an array copies into it (same shape).
template <class Member>
void field_property(py::class_<Particles>& c, const char* name, Member member, const char* doc) {
  c.def_property(
      name, [member](py::object self) { return field_view(self.cast<Particles&>().*member, self); },
      [member, name](Particles& P, const DoubleArray& a) { assign_field(P.*member, a, name); },
      doc);
}

// A column a part of the step adds to the particles (particle_columns): a numpy view of the C++
// storage, empty when absent; assigning a number or the particles' values (N, or N × width)
// sets it (set_part_column).
void column_property(py::class_<Particles>& c, const ParticleColumn& col) {
  static std::deque<std::string> docs; // pybind11 keeps the pointer
  docs.push_back(std::string(col.shape) + " " + std::string(col.meaning) + "; empty: none" +
                 (col.needs.empty() ? "" : " (" + std::string(col.needs) + " brings it)") +
                 ". Assign a number or the particles' values to set them");
  c.def_property(
      std::string(col.name).c_str(),
      [col](py::object self) {
        Particles& P = self.cast<Particles&>();
        return col.vector ? vector_view(P.*col.vector, self) : field_view(P.*col.field, self);
      },
      [col](Particles& P, const DoubleArray& a) { set_part_column(P, col, a); },
      docs.back().c_str());
}

void bind_particles(py::module_& m) {
  py::class_<Particles> c(m, "Particles",
                          "Material points as numpy views of the library's arrays (one row per "
                          "particle; tensors row-major, d² columns).");
  field_property(c, "X", &Particles::X, "N × d positions");
  field_property(c, "V", &Particles::V, "N × d velocities");
  field_property(c, "F", &Particles::F, "N × d² deformation gradients");
  field_property(c, "stress", &Particles::stress, "N × d² Cauchy stresses");
  field_property(c, "half_length", &Particles::half_length, "N × d initial half-lengths r⁰");
  c.def_property(
      "mass", [](py::object self) { return vector_view(self.cast<Particles&>().mass, self); },
      [](Particles& P, const DoubleArray& a) { assign_vector(P.mass, a, "mass"); }, "N masses");
  c.def_property(
      "volume0", [](py::object self) { return vector_view(self.cast<Particles&>().volume0, self); },
      [](Particles& P, const DoubleArray& a) { assign_vector(P.volume0, a, "volume0"); },
      "N initial volumes");
  for (const ParticleColumn& col : particle_columns()) // the parts' columns, one rule
    column_property(c, col);
  c.def_property_readonly(
      "material",
      [](py::object self) { return vector_view(self.cast<Particles&>().material, self); },
      "N material ids");
  c.def_readonly("dim", &Particles::dim, "dimension d of the positions");
  c.def("__len__", &Particles::size);
  // Copies as numpy arrays (the module does not convert Eigen types itself).
  c.def(
      "volume",
      [](const Particles& P) {
        const Eigen::VectorXd v = P.volume();
        return py::array_t<double>(v.size(), v.data());
      },
      "Current volumes det(F) V⁰, N.");
  c.def(
      "jacobian",
      [](const Particles& P) {
        const Eigen::VectorXd J = P.jacobian();
        return py::array_t<double>(J.size(), J.data());
      },
      "det F per particle, N.");
}

} // namespace

Shape shape_arg(const py::object& shape, const PyModel* model) {
  if (shape.is_none())
    return model ? model->options.shape : StepOptions{}.shape;
  return shape_from_string(shape.cast<std::string>());
}

namespace {

void bind_conditions(py::module_& m) {
  py::class_<BoundaryConditions>(m, "BoundaryConditions",
                                 "Grid velocity conditions and moving walls (boundary.hpp).")
      .def_property_readonly("num_constrained", &BoundaryConditions::num_constrained,
                             "velocity conditions: the (node, condition) pairs")
      .def("__len__", [](const BoundaryConditions& b) { return b.conditions.size(); })
      .def_property_readonly(
          "walls", [](const BoundaryConditions& b) { return b.walls.size(); }, "moving walls")
      .def_property_readonly("driven", &BoundaryConditions::driven,
                             "whether a condition or wall prescribes a non-zero velocity");
  py::class_<Energies>(m, "Energies",
                       "Energies, momentum and largest speed of the particles (diagnostics.hpp).")
      .def_readonly("kinetic", &Energies::kinetic, "K = 1/2 sum_p M_p |V_p|^2")
      .def_readonly("strain", &Energies::strain, "W = sum_p V0_p W(F_p)")
      .def_readonly("total", &Energies::total, "K + W")
      .def_readonly("max_speed", &Energies::max_speed, "max_p |V_p|")
      .def_property_readonly(
          "momentum",
          [](const Energies& e) {
            return std::vector<double>(e.momentum.data(), e.momentum.data() + 3);
          },
          "sum_p M_p V_p (three entries; unused axes 0)");
}

void bind_thermal_sums(py::module_& m) {
  py::class_<ThermalSums>(m, "ThermalSums",
                          "Temperatures and thermodynamic sums of particles with temperatures "
                          "(diagnostics.hpp): the series of a run with heat transport.")
      .def_readonly("temperature_min", &ThermalSums::temperature_min, "min_p T_p")
      .def_readonly("temperature_max", &ThermalSums::temperature_max, "max_p T_p")
      .def_readonly("temperature_mean", &ThermalSums::temperature_mean,
                    "Σ M C_V T / Σ M C_V, the capacity-weighted mean (conduction conserves it)")
      .def_readonly("heat", &ThermalSums::heat, "Q = Σ M C_V (T − T_ref), the thermal energy")
      .def_readonly("internal", &ThermalSums::internal, "U = W + Q (with the coupling's T c)")
      .def_readonly("entropy", &ThermalSums::entropy, "S = Σ M C_V ln(T / T_ref) (+ Ω c)")
      .def_readonly("helmholtz", &ThermalSums::helmholtz, "A = U − Σ T_p S_p");
  m.def(
      "thermal_sums",
      [](const PyModel& pm, std::optional<double> strain) {
        const Particles& P = pm.model.particles;
        if (P.temperature.size() != P.size())
          throw UsageError("thermal_sums: the particles have no temperatures (set "
                           "particles.temperature, or step with a transport)");
        return thermal_sums(pm.model, strain ? *strain : energies(pm.model).strain);
      },
      py::arg("model"), py::arg("strain") = py::none(),
      "The ThermalSums of the model's particles, W = strain (default model.energies().strain; "
      "after a step, the energies advance's callback receives give the run's series bit for "
      "bit). Raises UsageError when the particles have no temperatures.");
}

PyModel from_toml(const std::string& path, const py::dict& overrides) {
  std::vector<std::string> sets;
  for (const auto& [key, value] : overrides)
    sets.push_back(py::str(key).cast<std::string>() + "=" + toml_value(value, false));
  RunConfig cfg = read_input_file(path, sets);
  for (const std::string& note : cfg.notes) // the earlier names the input used
    warn_earlier_name("", "", note);
  return PyModel{std::move(cfg.model), std::move(cfg.step), cfg.time, path};
}

void bind_model_state(py::class_<PyModel>& c) {
  c.def_property_readonly(
      "particles", [](PyModel& pm) -> Particles& { return pm.model.particles; },
      py::return_value_policy::reference_internal,
      "the particles (a reference: changing its arrays changes the model)");
  c.def_property_readonly(
      "grid", [](const PyModel& pm) { return pm.model.grid; }, "A copy of the grid.");
  c.def_property(
      "materials", [](const PyModel& pm) { return pm.model.materials; },
      [](PyModel& pm, const std::vector<Material>& mats) {
        for (const Material& mat : mats)
          validate_material(mat);
        pm.model.materials = mats;
      },
      "the materials, by material id");
  c.def_property_readonly(
      "bcs", [](PyModel& pm) -> BoundaryConditions& { return pm.model.bcs; },
      py::return_value_policy::reference_internal,
      "the velocity conditions as given (a step selects the walls' nodes on its own copy: "
      "assemble(model).bcs)");
  c.def_property_readonly(
      "temperature_bcs",
      [](PyModel& pm) -> BoundaryConditions& { return pm.model.temperature_bcs; },
      py::return_value_policy::reference_internal,
      "the temperature conditions ([[bc]] temperature, add_bc): one per node, each a condition on "
      "the nodal temperature");
  c.def_property_readonly(
      "velocity_fields", [](const PyModel& pm) { return pm.model.contact.fields(); },
      "velocity fields of the materials ([[contact]], set_contact); 1: single material mode");
  c.def_property(
      "gravity",
      [](const PyModel& pm) {
        return std::vector<double>(pm.model.gravity.begin(),
                                   pm.model.gravity.begin() + pm.model.grid.dim());
      },
      [](PyModel& pm, const std::vector<double>& g) { pm.model.gravity = triple(g, 0, "gravity"); },
      "[loads] gravity: the body acceleration B (per unit mass)");
  c.def_property(
      "options", [](PyModel& pm) -> StepOptions& { return pm.options; },
      [](PyModel& pm, const StepOptions& o) { pm.options = o; },
      py::return_value_policy::reference_internal, "The step options of the input's [step].");
  c.def_property(
      "courant", [](const PyModel& pm) { return pm.time_settings.courant; },
      [](PyModel& pm, double C) { pm.time_settings.courant = C; }, "[time] courant");
  c.def_property(
      "end", [](const PyModel& pm) { return pm.time_settings.end; },
      [](PyModel& pm, double e) { pm.time_settings.end = e; }, "[time] end");
  c.def_property(
      "fourier", [](const PyModel& pm) { return pm.time_settings.fourier; },
      [](PyModel& pm, double F) {
        if (!(F >= 0) || !std::isfinite(F))
          throw InputError("fourier must be non-negative and finite, got " + number_text(F));
        pm.time_settings.fourier = F;
      },
      "[time] fourier: F in dt <= F dx_min^2 / D_max with heat transport (0: 0.1)");
  c.def_property(
      "time", [](const PyModel& pm) { return pm.model.time; },
      [](PyModel& pm, double t) {
        if (!std::isfinite(t))
          throw InputError("time must be finite, got " + number_text(t));
        pm.model.time = t;
      },
      "simulated time t");
  c.def_property_readonly(
      "step", [](const PyModel& pm) { return pm.model.step; }, "steps taken");
  c.def_property_readonly(
      "dim", [](const PyModel& pm) { return pm.model.grid.dim(); }, "dimension d");
  c.def_property_readonly(
      "source", [](const PyModel& pm) { return pm.source; },
      "the input file the model was read from ('' for a model made from arrays)");
}

void bind_model_tables(py::class_<PyModel>& c) {
  c.def("add_bc", &add_bc,
        "Adds one [[bc]] table, its keys and values as in the input files: plane={'axis': 'x', "
        "'at': 0.0} or box={'min': [...], 'max': [...]} with fixed=['x', ...] or "
        "velocity={'direction': [...], 'value': 'expression of t, x, y, z'} or temperature=350.0 "
        "(a number or an expression of t, x, y, z: a temperature condition, one per node); or a "
        "moving wall "
        "wall={'normal': [...], 'position': 'expression of t', 'velocity': ..., 'gradient': "
        "..., 'depth': ...} (FMPM 2026 §3.1). Returns the (node, condition) pairs it adds. "
        "Raises InputError with the message of the input reader.");
  c.def("set_contact", &set_contact, py::arg("tables"),
        "Replaces the [[contact]] tables: a list of dicts with the keys of the input files "
        "(materials=['a', 'b'], law='stick' | 'frictionless' | 'coulomb' | 'single-field', "
        "friction, normal='AG' | 'LR' | 'specified', direction, detection='approaching' | 'CP' "
        "| 'DF' | 'LR' | 'always', critical_separation, df_exponent, df_reach, fmpm_method="
        "'net' | 'evolving'); a table without materials is the law of every other pair.");
  c.def("fix_plane", &fix_plane, py::arg("axis"), py::arg("at"), py::arg("fixed"),
        "Zero velocity in the directions `fixed` (['x', 'y'], as the input files' fixed; 'xy' "
        "is the earlier form) on the nodes of the plane x_axis = at (axis 0, 1, 2 or 'x', 'y', "
        "'z'); returns the number of nodes.");
}

} // namespace

void bind_model(py::module_& m) {
  bind_grid(m);
  bind_particles(m);
  bind_conditions(m);
  bind_thermal_sums(m);
  py::class_<PyModel> c(m, "Model",
                        "A run's state (grid, particles, materials, velocity BCs, contact, clock) "
                        "with the step options and time settings of its input.");
  c.def(py::init(&model_from_arrays), py::arg("grid"), py::arg("X"), py::arg("mass"),
        py::arg("volume0") = py::none(), py::arg("V") = py::none(),
        py::arg("material") = py::none(), py::arg("materials") = std::vector<Material>{},
        py::arg("half_length") = py::none(), py::arg("fixed") = py::list(),
        py::arg("gravity") = std::vector<double>{}, py::arg("temperature") = py::none(),
        py::arg("heat_source") = py::none(),
        "Model(grid, X, mass, volume0, V=None, material=None, materials=[...], "
        "half_length=None, fixed=[(axis, at, ['x', ...]), ...], gravity=[...], "
        "temperature=None, heat_source=None): particles from "
        "arrays (X: N × d, mass and volume0: N; V: N × d, zero by default; material: N ids "
        "into materials, 0 by default; half_length: N × d, by default half the side of the "
        "cube of each volume); fixed: zero-velocity planes x_axis = at in the named "
        "directions (fix_plane); gravity: the body acceleration; temperature and heat_source "
        "(heat transport, [[body]] temperature and heat_source): a number or N values each "
        "(absolute temperatures; power per unit mass). volume and body_force are the earlier "
        "names of volume0 and gravity.");
  c.def_static("from_toml", &from_toml, py::arg("path"), py::arg("overrides") = py::dict(),
               "Reads a TOML input as `smpm run path --set key=value ...` does; overrides maps "
               "'section.key' to a value. Raises InputError with the message of the command.");
  bind_model_state(c);
  bind_model_tables(c);
  c.def("energies", [](const PyModel& pm) { return energies(pm.model); });
  c.def("copy", [](const PyModel& pm) { return pm; });
  c.def("__repr__", [](const PyModel& pm) {
    std::ostringstream os;
    os << "Model(" << pm.source << ": dim " << pm.model.grid.dim() << ", "
       << pm.model.particles.size() << " particles, " << pm.model.grid.num_nodes()
       << " nodes, t = " << pm.model.time << ", step " << pm.model.step << ")";
    return os.str();
  });
}

} // namespace smpm::python
