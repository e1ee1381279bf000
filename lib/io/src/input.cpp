// SPDX-License-Identifier: BSD-3-Clause
// An input file read into a RunConfig: the TOML text parsed with its aliases and overrides, the
// [grid], [time] and [output] tables, the checks across tables, and the other tables by their
// readers (input_materials.cpp, input_bodies.cpp, input_conditions.cpp, input_step.cpp,
// input_contact.cpp, input_loads.cpp).
#include "sparsempm/input.hpp"
#include "sparsempm/run_file.hpp"

#include "expression.hpp"
#include "reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/plasticity.hpp"
#include "toml_text.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <regex>
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

// [output]: file (default: the input's name with .h5), frame interval (default end/10), CSR
// matrices, the unit system of the labels (default none).
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
  out.units = r.string(*output, "units", "output.units", kUnitSystems[0]);
  if (std::find(std::begin(kUnitSystems), std::end(kUnitSystems), out.units) ==
      std::end(kUnitSystems))
    r.fail(output->get("units"), "output.units", "expected \"none\", \"SI\" or \"mm-ms-g\"");
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

// The text a run file stores as its input: the input with the --set overrides appended as
// comments.
std::string stored_text(const std::string& text, const std::vector<std::string>& overrides) {
  std::string stored = text;
  if (!overrides.empty()) {
    stored += "\n# overrides applied with --set:\n";
    for (const auto& o : overrides)
      stored += "#   " + o + "\n";
  }
  return stored;
}

// The rigid particles start with their material's velocity at t = 0 (finite, or the input's
// value is refused).
void start_rigid_bodies(const Reader& r, const toml::table& root, Model& model) {
  for (RigidMotion& m : model.rigid) {
    Eigen::Vector3d v0;
    try {
      v0 = m.at(0.0);
    } catch (const NumericalError& e) { // not finite from the start: the input's value
      const std::string name = model.materials[size_t(m.material)].name;
      const auto tables = r.tables(root, "material", true);
      r.fail(tables[size_t(m.material)]->get("velocity"), "material." + name + ".velocity",
             std::string(e.what()) + " (a rigid velocity must be finite at t = 0)");
    }
    for (Index p = 0; p < model.particles.size(); ++p)
      if (model.particles.material[p] == m.material)
        for (int a = 0; a < model.grid.dim(); ++a)
          model.particles.V(p, a) = v0[a];
  }
}

// The grid, the materials with their rigid motions, the bodies (their particle ranges in
// `bodies`) and the conditions of the input.
void read_model(const Reader& r, const toml::table& root, Model& model,
                std::vector<detail::BodyRange>& bodies) {
  Grid grid = read_grid(r, root);
  model = Model(grid);
  model.materials = detail::read_materials(r, root);
  model.rigid = detail::read_rigid(r, root, model.materials, grid.dim());
  model.particles = read_bodies(r, root, grid, model.materials, &bodies);
  start_rigid_bodies(r, root, model);
  const Particles& P = model.particles;
  for (Index p = 0; p < P.size(); ++p)
    if (!std::isfinite(P.mass[p]))
      r.fail(nullptr, "material." + model.materials[size_t(P.material[p])].name + ".density",
             "gives particle " + std::to_string(p) + " an infinite mass");
  ConditionTables conditions = read_bcs(r, root, grid);
  model.bcs = std::move(conditions.velocity);
  model.temperature_bcs = std::move(conditions.temperature);
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
  cfg.text = stored_text(text, overrides);
  std::vector<detail::BodyRange> bodies;
  read_model(r, root, cfg.model, bodies);
  const int dim = cfg.model.grid.dim();

  cfg.time = read_time(r, root);
  detail::read_step(r, root, cfg.step);
  cfg.model.contact = detail::read_contact(r, root, cfg.model.materials, dim);
  try {
    check_rigid_motions(cfg.model.rigid, cfg.model.contact.material_field, cfg.step);
  } catch (const InputError& e) { // "<key>: <what is wrong>", the key a material's
    const std::string what = e.what();
    const size_t colon = what.find(": ");
    r.fail(nullptr, what.substr(0, colon), what.substr(colon + 2));
  }
  if (const toml::table* loads = r.table(root, "loads", "[loads]", false)) {
    r.check_keys(*loads, "loads");
    cfg.model.gravity = r.vector(*loads, "gravity", "loads.gravity", dim, false);
    cfg.model.loads = detail::read_loads(r, *loads, cfg.model.particles, bodies);
  }
  cfg.output = read_output(r, root, source, cfg.time.end);
  check_heat(r, root, cfg);
  if (uses_plasticity(cfg.model.materials)) // the plastic state at the start (every frame has it)
    initial_plastic_state(cfg.model.particles);
  if (cfg.step.transfer != Transfer::Standard) { // the state of an affine transfer: L_p = 0
    Particles& P = cfg.model.particles;          // at the start (every frame has it)
    P.gradient.setZero(P.size(), P.dim * P.dim);
  }
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
