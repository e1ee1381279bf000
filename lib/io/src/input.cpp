// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/input.hpp"
#include "sparsempm/run_file.hpp"

#include "expression.hpp"
#include "reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/exact.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/plasticity.hpp"
#include "toml_text.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace smpm {

namespace {

using detail::schema;
using detail::suggest;

using detail::kMaxNodes;
using detail::Reader;

Grid read_grid(const Reader& r, const toml::table& root) {
  const toml::table& g = *r.table(root, "grid", "[grid]", true);
  r.check_keys(g, "grid");
  const toml::node* dn = r.node(g, "dim", "grid.dim", true);
  const auto dim = dn->value<int64_t>();
  if (!dim || !dn->is_integer() || *dim < 1 || *dim > 3)
    r.fail(dn, "grid.dim", "must be 1, 2 or 3");
  const int d = int(*dim);
  const auto origin = r.vector(g, "origin", "grid.origin", d, true);
  const auto h = r.vector(g, "cell_size", "grid.cell_size", d, true);
  for (int a = 0; a < d; ++a)
    if (!(h[a] > 0))
      r.fail(g.get("cell_size"), "grid.cell_size", "every cell size must be positive");
  const auto cells = r.counts(g, "cells", "grid.cells", d);
  // Sizes whose products overflow would surface only as a failure of the first step.
  double cell_volume = 1;
  for (int a = 0; a < d; ++a) {
    cell_volume *= h[a];
    if (!std::isfinite(origin[a] + cells[a] * h[a]))
      r.fail(g.get("cell_size"), "grid.cell_size",
             "the grid's extent along axis " + std::to_string(a) + " overflows");
  }
  if (!std::isfinite(cell_volume) || !(cell_volume > 0))
    r.fail(g.get("cell_size"), "grid.cell_size",
           "the cell volume " + number_text(cell_volume) + " is not a positive finite number");
  double total = 1;
  for (int a = 0; a < d; ++a)
    total *= cells[a] + 1.0;
  if (total > kMaxNodes)
    r.fail(g.get("cells"), "grid.cells",
           "the grid would have " + std::to_string(long(total)) + " nodes, more than the " +
               std::to_string(long(kMaxNodes)) + " this build accepts");
  std::array<double, 3> o{0, 0, 0}, hh{1, 1, 1};
  for (int a = 0; a < d; ++a) {
    o[a] = origin[a];
    hh[a] = h[a];
  }
  return Grid(d, o, hh, cells);
}

// Shock physics (contact 2020 Eqs. 51–52): K, G, γ₀, S₁ and the viscosity [A₁, A₂].
void read_mie_gruneisen(const Reader& r, const toml::table& t, const std::string& key,
                        Material& m) {
  for (const char* k : {"youngs", "poisson"})
    if (t.get(k))
      r.fail(t.get(k), key + k, "model = \"mie-gruneisen\" takes bulk and shear instead");
  m.bulk = r.positive(t, "bulk", key + "bulk", std::nullopt);
  auto nonnegative = [&](const char* k, std::optional<double> fallback) {
    const double v = r.number(t, k, key + k, fallback);
    if (!(v >= 0))
      r.fail(t.get(k), key + k, "must be non-negative");
    return v;
  };
  m.shear = nonnegative("shear", 0.0);
  m.gruneisen = nonnegative("gruneisen", std::nullopt);
  m.hugoniot_slope = nonnegative("s1", std::nullopt);
  if (t.get("viscosity")) {
    const auto av = r.vector(t, "viscosity", key + "viscosity", 2, true);
    if (!(av[0] >= 0 && av[1] >= 0))
      r.fail(t.get("viscosity"), key + "viscosity", "A1 and A2 must be non-negative");
    m.av_linear = av[0];
    m.av_quadratic = av[1];
  }
  // E and ν of the same K and G (wave speed, Lamé constants): E = 9KG/(3K + G).
  m.youngs = 9 * m.bulk * m.shear / (3 * m.bulk + m.shear);
  m.poisson = (3 * m.bulk - 2 * m.shear) / (2 * (3 * m.bulk + m.shear));
}

// Heat transport: C_V > 0, κ ≥ 0, T_ref > 0 (each optional here; transport checks that every
// material has C_V and T_ref).
void read_heat_properties(const Reader& r, const toml::table& t, const std::string& key,
                          Material& m) {
  if (t.get("heat_capacity"))
    m.heat_capacity = r.positive(t, "heat_capacity", key + "heat_capacity", std::nullopt);
  m.conductivity = r.number(t, "conductivity", key + "conductivity", 0.0);
  if (!(m.conductivity >= 0))
    r.fail(t.get("conductivity"), key + "conductivity", "must be non-negative");
  if (t.get("reference_temperature"))
    m.reference_temperature =
        r.positive(t, "reference_temperature", key + "reference_temperature", std::nullopt);
  m.thermal_expansion = r.number(t, "thermal_expansion", key + "thermal_expansion", 0.0);
  if (m.thermal_expansion != 0 && m.model == MaterialModel::MieGruneisen)
    r.fail(t.get("thermal_expansion"), key + "thermal_expansion",
           "not for model = \"mie-gruneisen\" (its thermal pressure is gruneisen rho0 U)");
}

std::vector<Material> read_materials(const Reader& r, const toml::table& root) {
  std::vector<Material> mats;
  const std::vector<const toml::table*> tables = r.tables(root, "material", true);
  if (tables.size() > size_t(kMaxMaterials))
    r.fail(nullptr, "[[material]]",
           std::to_string(tables.size()) + " tables, more than the " +
               std::to_string(kMaxMaterials) + " materials a model takes");
  std::set<std::string> names;
  for (const toml::table* t : tables) {
    r.check_keys(*t, "material");
    Material m;
    m.name = r.string(*t, "name", "material.name", std::nullopt);
    if (!names.insert(m.name).second)
      r.fail(t->get("name"), "material.name", "duplicate material name");
    const std::string key = "material." + m.name + ".";
    const std::string model = r.string(*t, "model", key + "model", "linear");
    try {
      m.model = material_model_from_string(model);
    } catch (const InputError& e) {
      r.fail(t->get("model"), key + "model", e.what());
    }
    m.density = r.positive(*t, "density", key + "density", std::nullopt);
    read_heat_properties(r, *t, key, m);
    // J2 plasticity (plasticity.hpp): hyperelastic and mie-gruneisen only.
    m.yield_stress = r.number(*t, "yield_stress", key + "yield_stress", 0.0);
    m.hardening = r.number(*t, "hardening", key + "hardening", 0.0);
    for (const char* k : {"yield_stress", "hardening"})
      if (t->get(k) && m.model != MaterialModel::Hyperelastic &&
          m.model != MaterialModel::MieGruneisen)
        r.fail(t->get(k), key + k, "only the hyperelastic and mie-gruneisen models take it");
    if (!(m.yield_stress >= 0))
      r.fail(t->get("yield_stress"), key + "yield_stress", "must be non-negative (0: elastic)");
    if (!(m.hardening >= 0))
      r.fail(t->get("hardening"), key + "hardening", "must be non-negative");
    if (t->get("hardening") && !(m.yield_stress > 0))
      r.fail(t->get("hardening"), key + "hardening", "needs a yield_stress");
    if (m.model == MaterialModel::Rigid) { // rigid.hpp: density, and velocity (read_rigid)
      for (const char* k : {"youngs", "poisson", "bulk", "shear", "gruneisen", "s1", "viscosity"})
        if (t->get(k))
          r.fail(t->get(k), key + k, "a rigid material does not take it");
      mats.push_back(m);
      continue;
    }
    if (m.model == MaterialModel::MieGruneisen) {
      read_mie_gruneisen(r, *t, key, m);
      if (!std::isfinite(m.wave_speed(3)))
        r.fail(t->get("bulk"), key + "bulk",
               "gives an infinite wave speed (the modulus over the density overflows)");
      mats.push_back(m);
      continue;
    }
    for (const char* k : {"bulk", "shear", "gruneisen", "s1", "viscosity"})
      if (t->get(k))
        r.fail(t->get(k), key + k, "only model = \"mie-gruneisen\" takes it");
    m.youngs = r.positive(*t, "youngs", key + "youngs", std::nullopt);
    m.poisson = r.number(*t, "poisson", key + "poisson", 0.0);
    if (!(m.poisson > -1 && m.poisson < 0.5))
      r.fail(t->get("poisson"), key + "poisson", "must lie in (-1, 0.5)");
    if (!std::isfinite(m.wave_speed(1)) || !std::isfinite(m.wave_speed(3)))
      r.fail(t->get("youngs"), key + "youngs",
             "gives an infinite wave speed (the modulus over the density overflows)");
    mats.push_back(m);
  }
  return mats;
}

// An integer key (its range is checked by the library's validate).
std::optional<int> integer(const Reader& r, const toml::table& t, const char* key,
                           const std::string& name) {
  const toml::node* n = t.get(key);
  if (!n)
    return std::nullopt;
  const auto v = n->value<int64_t>();
  if (!v || !n->is_integer())
    r.fail(n, name, "expected an integer");
  return int(
      std::clamp<int64_t>(*v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

// FMPM(k), XPIC(m), blending, periodic and dynamic FMPM, BC method, exact solver options.
void read_fmpm(const Reader& r, const toml::table& t, StepOptions& step) {
  FmpmOptions& f = step.fmpm;
  if (const auto k = integer(r, t, "order", "step.order"))
    f.order = *k;
  else if (step.velocity == VelocityUpdate::FMPM || step.velocity == VelocityUpdate::XPIC)
    r.fail(nullptr, "step.order", "missing required key (the order k of FMPM or m of XPIC)");
  f.blend_alpha = r.number(t, "blend_alpha", "step.blend_alpha", 1.0);
  if (const auto m = integer(r, t, "blend_every", "step.blend_every"))
    f.blend_every = *m;
  step.periodic_cx = r.number(t, "periodic_cx", "step.periodic_cx", 0.0);
  f.metric =
      r.choice(t, "dynamic_metric", "step.dynamic_metric", "none", &convergence_metric_from_string);
  f.dynamic_limit = r.number(t, "dynamic_limit", "step.dynamic_limit", 0.0);
  if (f.metric != ConvergenceMetric::None && !t.get("dynamic_limit"))
    r.fail(t.get("dynamic_metric"), "step.dynamic_metric",
           "needs step.dynamic_limit (the convergence limit)");
  f.bc_method = r.choice(t, "bc_method", "step.bc_method", "incremental", &bc_method_from_string);
  step.exact.regularization = r.number(t, "exact_regularization", "step.exact_regularization", 0.0);
  step.exact.mass_cutoff = r.number(t, "exact_mass_cutoff", "step.exact_mass_cutoff", 0.0);
  // Always set, so that analyses adding an exact row (smpm stability) use these options.
  step.exact_solver = exact_solver_factory();
}

// [step]: update scheme, velocity update, shape functions, α, F update and the FMPM family.
void read_step(const Reader& r, const toml::table& root, StepOptions& step) {
  static const toml::table empty;
  const toml::table* table = r.table(root, "step", "[step]", false);
  const toml::table& t = table ? *table : empty;
  r.check_keys(t, "step");
  step.scheme = r.choice(t, "scheme", "step.scheme", "USL", &update_scheme_from_string);
  step.velocity = r.choice(t, "velocity", "step.velocity", "FLIP", &velocity_update_from_string);
  step.shape = r.choice(t, "shape", "step.shape", "cpdi", &shape_from_string);
  // α of Eqs. (8)–(9); unset: default_position_alpha (1 for FLIP, ½ otherwise).
  if (t.get("position_alpha"))
    step.position_alpha = r.number(t, "position_alpha", "step.position_alpha", 0.0);
  step.deformation =
      r.choice(t, "deformation", "step.deformation", "linear", &deformation_update_from_string);
  step.xpic_contact =
      r.choice(t, "xpic_contact", "step.xpic_contact", "increments", &xpic_contact_from_string);
  step.transfer = r.choice(t, "transfer", "step.transfer", "standard", &transfer_from_string);
  step.transport.update =
      r.choice(t, "transport", "step.transport", "off", &transport_update_from_string);
  if (const auto k = integer(r, t, "transport_order", "step.transport_order"))
    step.transport.order = *k;
  read_fmpm(r, t, step);
  // The library's limits (validate of step_options.hpp), at the line of the key they name.
  try {
    validate(step);
  } catch (const OptionError& e) {
    r.fail(t.get(e.key()), "step." + e.key(), e.reason());
  }
}

// [output]: file (default: the input's name with .h5), frame interval (default end/10), CSR
// matrices.
OutputSettings read_output(const Reader& r, const toml::table& root, const std::string& source,
                           double end) {
  static const toml::table empty;
  OutputSettings out;
  const toml::table* output = r.table(root, "output", "[output]", false);
  if (!output)
    output = &empty;
  r.check_keys(*output, "output");
  const std::string stem = std::filesystem::path(source).stem().string();
  out.file = r.string(*output, "file", "output.file", (stem.empty() ? "run" : stem) + ".h5");
  out.every = r.positive(*output, "every", "output.every", end / 10);
  if (end / out.every > double(kMaxFrames)) {
    std::ostringstream why;
    why << "gives " << std::ceil(end / out.every) << " frames up to time.end = " << end
        << ", more than the " << kMaxFrames << " accepted";
    r.fail(output->get("every"), "output.every", why.str());
  }
  out.matrices = r.boolean(*output, "matrices", "output.matrices", false);
  return out;
}

} // namespace

namespace {
// The key a line of TOML text sets, with the table it is in ("time.end"; "" when the line sets
// none): for the message of a value the parser refuses (a float out of range, 1e309).
std::string key_of_line(const std::string& text, size_t line) {
  std::istringstream in(text);
  std::string row, table;
  for (size_t k = 1; std::getline(in, row) && k <= line; ++k) {
    const size_t first = row.find_first_not_of(" \t");
    if (first == std::string::npos || row[first] == '#')
      continue;
    if (row[first] == '[') { // [table] or [[array of tables]]
      const size_t open = row.find_first_not_of('[', first), close = row.find(']', open);
      if (close != std::string::npos)
        table = row.substr(open, close - open);
      continue;
    }
    const size_t eq = row.find('=');
    if (k == line && eq != std::string::npos) {
      std::string key = row.substr(first, eq - first);
      key.erase(key.find_last_not_of(" \t") + 1);
      return table.empty() ? key : table + "." + key;
    }
  }
  return "";
}

// The TOML text of `source`, parsed; InputError naming the line (and the key) of a syntax error.
toml::table parse_text(const std::string& text, const std::string& source) {
  detail::check_non_ascii(text, source);
  try {
    return toml::parse(text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ":" << e.source().begin.line << ": ";
    if (const std::string key = key_of_line(text, e.source().begin.line); !key.empty())
      os << key << ": ";
    os << e.description();
    throw InputError(os.str());
  }
}

// The tables `text` holds, parsed, with no top-level key but `key` (an array of tables).
toml::table parse_tables(const Reader& r, const std::string& text, const std::string& source,
                         const char* key) {
  toml::table root = parse_text(text, source);
  for (auto&& [k, v] : root)
    if (k.str() != key)
      r.fail(&v, std::string(k.str()), std::string("expected [[") + key + "]] tables only");
  return root;
}
TimeSettings read_time(const Reader& r, const toml::table& root) {
  const toml::table* time = r.table(root, "time", "[time]", true);
  r.check_keys(*time, "time");
  TimeSettings t;
  t.courant = r.positive(*time, "courant", "time.courant", 0.5);
  t.end = r.positive(*time, "end", "time.end", std::nullopt);
  t.land_on_frames = r.boolean(*time, "land_on_frames", "time.land_on_frames", true);
  if (time->get("fourier"))
    t.fourier = r.positive(*time, "fourier", "time.fourier", std::nullopt);
  if (const toml::node* n = time->get("max_steps")) {
    const double v = r.positive(*time, "max_steps", "time.max_steps", std::nullopt);
    if (!n->is_integer() || v > 1e15)
      r.fail(n, "time.max_steps", "expected a whole number of steps from 1 to 1e15");
    t.max_steps = long(v);
  }
  return t;
}

// Heat transport: every material has C_V and T_ref; without transport no body, material or
// condition asks for temperatures (a forgotten step.transport), and the particles carry none.
void check_heat(const Reader& r, const toml::table& root, RunConfig& cfg) {
  Model& m = cfg.model;
  const bool on = cfg.step.transport.update != TransportUpdate::Off;
  if (!on) {
    const std::string off = "needs step.transport (lumped | FMPM | exact): heat transport is off";
    const std::vector<const toml::table*> bodies = r.tables(root, "body", true);
    for (size_t k = 0; k < bodies.size(); ++k)
      for (const char* key : {"temperature", "heat_source"})
        if (bodies[k]->get(key))
          r.fail(bodies[k]->get(key), "body." + std::to_string(k) + "." + key, off);
    if (!m.temperature_bcs.conditions.empty())
      r.fail(nullptr, m.temperature_bcs.conditions[0].label, off);
    const std::vector<const toml::table*> mats = r.tables(root, "material", true);
    for (size_t k = 0; k < mats.size(); ++k)
      if (m.materials[k].thermal_expansion != 0)
        r.fail(mats[k]->get("thermal_expansion"),
               "material." + m.materials[k].name + ".thermal_expansion", off);
    m.particles.temperature.resize(0);
    m.particles.heat_source.resize(0);
    return;
  }
  const std::vector<const toml::table*> tables = r.tables(root, "material", true);
  for (size_t k = 0; k < m.materials.size(); ++k) {
    const std::string key = "material." + m.materials[k].name + ".";
    const std::string why = std::string("is required with step.transport = ") +
                            std::string(to_string(cfg.step.transport.update));
    if (!(m.materials[k].heat_capacity > 0))
      r.fail(tables[k], key + "heat_capacity", why);
    if (!(m.materials[k].reference_temperature > 0))
      r.fail(tables[k], key + "reference_temperature", why);
  }
}

// The shape functions of every particle must fit in the grid (checked on the particles' window:
// storage proportional to the particles, not the grid).
void check_supports(const RunConfig& cfg) {
  try {
    Operators ops;
    ops.node_range = NodeRange::Particles;
    assemble(cfg.model.grid, cfg.model.particles, cfg.step.shape, ops);
  } catch (const NumericalError& e) {
    throw InputError(cfg.source + ": particles outside the grid for step.shape = \"" +
                     std::string(to_string(cfg.step.shape)) + "\": " + e.what());
  }
}

} // namespace

ConditionTables read_bc_tables(const std::string& text, const std::string& source,
                               const Grid& grid) {
  const Reader r(source);
  return read_bcs(r, parse_tables(r, text, source, "bc"), grid);
}

Contact read_contact_tables(const std::string& text, const std::string& source,
                            const std::vector<Material>& materials, int dim) {
  const Reader r(source);
  return detail::read_contact(r, parse_tables(r, text, source, "contact"), materials, dim);
}

RunConfig read_input(const std::string& input_text, const std::string& source,
                     const std::vector<std::string>& overrides,
                     const std::vector<std::string>& file_directories) {
  const Reader r(source, file_directories);
  // A UTF-8 byte-order mark (written by some editors) is not part of the TOML text.
  const std::string bom = "\xEF\xBB\xBF";
  const std::string text = input_text.rfind(bom, 0) == 0 ? input_text.substr(3) : input_text;
  toml::table root = parse_text(text, source);
  RunConfig cfg;
  cfg.notes = detail::apply_aliases(root, source);
  for (const auto& o : overrides)
    if (std::string note = detail::apply_override(root, o); !note.empty())
      cfg.notes.push_back(std::move(note));
  r.check_keys(root, "");

  cfg.source = source;
  cfg.overrides = overrides;
  cfg.text = text;
  if (!overrides.empty()) {
    cfg.text += "\n# overrides applied with --set:\n";
    for (const auto& o : overrides)
      cfg.text += "#   " + o + "\n";
  }
  Grid grid = read_grid(r, root);
  cfg.model = Model(grid);
  cfg.model.materials = read_materials(r, root);
  cfg.model.rigid = detail::read_rigid(r, root, cfg.model.materials, grid.dim());
  std::vector<detail::BodyRange> bodies;
  cfg.model.particles = read_bodies(r, root, grid, cfg.model.materials, &bodies);
  for (RigidMotion& m : cfg.model.rigid) { // the rigid particles start with the body's velocity
    Eigen::Vector3d v0;
    try {
      v0 = m.at(0.0);
    } catch (const NumericalError& e) { // not finite from the start: the input's value
      const std::string name = cfg.model.materials[size_t(m.material)].name;
      const auto tables = r.tables(root, "material", true);
      r.fail(tables[size_t(m.material)]->get("velocity"), "material." + name + ".velocity",
             std::string(e.what()) + " (a rigid velocity must be finite at t = 0)");
    }
    for (Index p = 0; p < cfg.model.particles.size(); ++p)
      if (cfg.model.particles.material[p] == m.material)
        for (int a = 0; a < grid.dim(); ++a)
          cfg.model.particles.V(p, a) = v0[a];
  }
  const Particles& P = cfg.model.particles;
  for (Index p = 0; p < P.size(); ++p)
    if (!std::isfinite(P.mass[p]))
      r.fail(nullptr, "material." + cfg.model.materials[size_t(P.material[p])].name + ".density",
             "gives particle " + std::to_string(p) + " an infinite mass");
  ConditionTables conditions = read_bcs(r, root, grid);
  cfg.model.bcs = std::move(conditions.velocity);
  cfg.model.temperature_bcs = std::move(conditions.temperature);

  cfg.time = read_time(r, root);
  read_step(r, root, cfg.step);
  cfg.model.contact = detail::read_contact(r, root, cfg.model.materials, grid.dim());
  try {
    check_rigid_motions(cfg.model.rigid, cfg.model.contact.material_field, cfg.step);
  } catch (const InputError& e) { // "<key>: <what is wrong>", the key a material's
    const std::string what = e.what();
    const size_t colon = what.find(": ");
    r.fail(nullptr, what.substr(0, colon), what.substr(colon + 2));
  }
  if (const toml::table* loads = r.table(root, "loads", "[loads]", false)) {
    r.check_keys(*loads, "loads");
    cfg.model.gravity = r.vector(*loads, "gravity", "loads.gravity", grid.dim(), false);
    cfg.model.loads = detail::read_loads(r, *loads, cfg.model.particles, bodies);
  }
  cfg.output = read_output(r, root, source, cfg.time.end);
  check_heat(r, root, cfg);
  if (uses_plasticity(cfg.model.materials)) // the plastic state at the start (every frame has it)
    initial_plastic_state(cfg.model.particles);
  if (cfg.step.transfer == Transfer::VelocityGradient) // the state of the transfer: L_p = 0 at
    cfg.model.particles.gradient.setZero(P.size(), P.dim * P.dim); // the start (every frame has it)
  check_supports(cfg);
  return cfg;
}

RunConfig read_input_file(const std::string& path, const std::vector<std::string>& overrides) {
  check_regular_file(path, kMaxInputBytes, "input file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path + ": cannot open the input file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return read_input(ss.str(), path, overrides);
}

} // namespace smpm
