// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.Grid, Particles and Model: the state of a run, read from a TOML input (the reader of
// `smpm run`) or built from numpy arrays, with the tables of the input files (add_bc,
// set_contact) read by the same reader.

#include "bindings.hpp"
#include "convert.hpp"

#include <sparsempm/contact.hpp>
#include <sparsempm/diagnostics.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>
#include <sparsempm/particle_columns.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <sstream>

namespace smpm::python {

namespace {

using DoubleArray = py::array_t<double, py::array::forcecast>;

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

// What the model holds: its particles, grid, materials, conditions, velocity fields and gravity.
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
}

// The step options and time settings of the input, and the model's clock.
void bind_model_settings(py::class_<PyModel>& c) {
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

// The contact law at one node (contact_momentum_change): Δp of field α from Δp(0) and n̂, for
// d = len(dp0) components.
py::tuple contact_law(const std::vector<double>& dp0, const std::vector<double>& normal,
                      const std::string& law, double friction, double separation,
                      const std::string& detection) {
  if (dp0.empty() || dp0.size() > 3 || normal.size() != dp0.size())
    throw InputError("contact_momentum_change: dp0 and normal need the same 1 to 3 components");
  if (!(friction >= 0))
    throw InputError("contact_momentum_change: friction = " + number_text(friction) +
                     ": must be non-negative");
  ContactPair pair;
  pair.law = contact_law_from_string(law);
  pair.friction = friction;
  pair.detection = contact_detection_from_string(detection);
  Eigen::Vector3d d0 = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero(), dp;
  for (size_t a = 0; a < dp0.size(); ++a) {
    d0[Index(a)] = dp0[a];
    n[Index(a)] = normal[a];
  }
  const bool in_contact = contact_momentum_change(pair, d0, n, separation, dp);
  return py::make_tuple(in_contact, std::vector<double>(dp.data(), dp.data() + dp0.size()));
}

void bind_model(py::module_& m) {
  m.def("contact_momentum_change", &contact_law, py::arg("dp0"), py::arg("normal"),
        py::arg("law") = "coulomb", py::arg("friction") = 0.0, py::arg("separation") = -1.0,
        py::arg("detection") = "LR",
        "The contact law at one node (contact.hpp, FMPM 2026 Eq. 18): (in_contact, dp), the "
        "momentum change of field α given Δp(0) = (m^α p^β − m^β p^α)/(m^α + m^β) and the unit "
        "normal n̂ from α to β (d components each), the law ('stick' | 'frictionless' | "
        "'coulomb' with friction μ), the separation (negative: the materials touch) and the "
        "detection; with N_c = −Δp(0)·n̂ and T_c = |Δp(0) − (Δp(0)·n̂) n̂| (per A_c Δt), "
        "|dp| = √(N_c² + min(T_c, μ N_c)²) in contact (FMPM 2026 Fig. 6).");
  bind_grid(m);
  bind_particles(m); // particles.cpp
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
  bind_model_settings(c);
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
