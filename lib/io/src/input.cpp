#include "sparsempm/input.hpp"

#include "expression.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/exact.hpp"
#include "sparsempm/operators.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

#ifndef SMPM_INPUT_MAX_PARTICLES
#define SMPM_INPUT_MAX_PARTICLES 20000000 // ~20 GB of particle and operator storage
#endif
#ifndef SMPM_INPUT_MAX_NODES
#define SMPM_INPUT_MAX_NODES 50000000
#endif

namespace smpm {

namespace {

constexpr double kMaxParticles = SMPM_INPUT_MAX_PARTICLES;
constexpr double kMaxNodes = SMPM_INPUT_MAX_NODES;

// Valid keys of every table of the schema ("" is the top level).
const std::map<std::string, std::vector<std::string>>& schema() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"", {"grid", "material", "body", "bc", "time", "scheme", "output", "loads"}},
      {"grid", {"dim", "origin", "cell_size", "cells"}},
      {"material", {"name", "model", "density", "youngs", "poisson"}},
      {"body",
       {"material", "region", "min", "max", "center", "radius", "semi_axes", "ppc", "velocity"}},
      {"bc", {"plane", "box", "fixed", "velocity"}},
      {"bc.plane", {"axis", "at"}},
      {"bc.box", {"min", "max"}},
      {"bc.velocity", {"direction", "value"}},
      {"time", {"courant", "end"}},
      {"scheme",
       {"update", "velocity", "shape", "position_alpha", "order", "blend_alpha", "blend_every",
        "periodic_cx", "dynamic_metric", "dynamic_limit", "bc_method", "exact_regularization"}},
      {"output", {"file", "every", "matrices"}},
      {"loads", {"gravity"}},
  };
  return keys;
}

// toml++ 3.3 reaches undefined behaviour (an unreachable branch in
// is_non_ascii_horizontal_whitespace) when a non-ASCII character stands where it tests for
// whitespace: after a bare value, between tokens, after a backslash in a string (found by
// tests/fuzz). Non-ASCII text is therefore accepted only where its role is unambiguous, and
// rejected with its line everywhere else:
//   - in a comment line (first non-blank character '#'),
//   - in a trailing comment ' # ...' after an ASCII part without quotes,
//   - in the string of a line  key = "text"  or  key = 'text'  (no backslash, no inner quote),
// and nowhere in a file with multi-line strings.
void check_non_ascii(const std::string& text, const std::string& source) {
  static const std::regex string_line(
      R"re(^[ \t]*[A-Za-z0-9_.-]+[ \t]*=[ \t]*("[^"\\]*"|'[^']*')[ \t]*(#.*)?$)re");
  const bool multi_line_strings =
      text.find("\"\"\"") != std::string::npos || text.find("'''") != std::string::npos;
  auto ascii = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(),
                       [](char c) { return static_cast<unsigned char>(c) < 0x80; });
  };
  std::istringstream in(text);
  long number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (ascii(line))
      continue;
    const size_t first = line.find_first_not_of(" \t");
    bool allowed = false;
    if (!multi_line_strings) {
      if (first != std::string::npos && line[first] == '#') {
        allowed = true; // a comment line
      } else if (std::regex_match(line, string_line)) {
        allowed = true; // key = "text" [# comment]
      } else {
        const size_t hash = line.find('#');
        const std::string code = line.substr(0, hash);
        allowed = hash != std::string::npos && hash > 0 &&
                  (line[hash - 1] == ' ' || line[hash - 1] == '\t') &&
                  code.find_first_of("\"'") == std::string::npos && ascii(code);
      }
    }
    if (!allowed)
      throw InputError(source + ":" + std::to_string(number) +
                       (multi_line_strings
                            ? ": non-ASCII characters cannot be used in a file with multi-line "
                              "strings"
                            : ": non-ASCII characters are accepted only in comments and in "
                              "simple key = \"text\" strings"));
  }
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string suggest(const std::string& key, const std::vector<std::string>& valid) {
  std::string best;
  size_t dist = 1000;
  for (const auto& v : valid)
    if (const size_t e = edit_distance(key, v); e < dist) {
      dist = e;
      best = v;
    }
  if (dist <= std::max<size_t>(2, key.size() / 3))
    return " (did you mean '" + best + "'?)";
  std::string list;
  for (const auto& v : valid)
    list += (list.empty() ? "" : ", ") + v;
  return " (valid keys: " + list + ")";
}

// Reads one input; carries the file name for messages.
class Reader {
public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  // "file:line: key = value" for a node, "file: key" without one.
  std::string where(const toml::node* n, const std::string& key) const {
    std::ostringstream os;
    std::string file = source_;
    long line = 0;
    if (n) {
      const auto& src = n->source();
      if (src.path && !src.path->empty())
        file = *src.path;
      line = long(src.begin.line);
    }
    os << file;
    if (line > 0)
      os << ":" << line;
    os << ": " << key;
    if (n && n->is_value())
      n->visit([&](auto&& v) { os << " = " << v; });
    return os.str();
  }
  [[noreturn]] void fail(const toml::node* n, const std::string& key,
                         const std::string& msg) const {
    throw InputError(where(n, key) + ": " + msg);
  }

  void check_keys(const toml::table& t, const std::string& section) const {
    const auto& valid = schema().at(section);
    for (auto&& [k, v] : t) {
      const std::string key(k.str());
      if (std::find(valid.begin(), valid.end(), key) == valid.end())
        throw InputError(where(&v, section.empty() ? key : section + "." + key).substr(0) +
                         ": unknown key" + suggest(key, valid));
    }
  }

  const toml::table* table(const toml::table& parent, const std::string& key,
                           const std::string& name, bool required) const {
    const toml::node* n = parent.get(key);
    if (!n) {
      if (required)
        fail(nullptr, name, "missing required table");
      return nullptr;
    }
    if (!n->is_table())
      fail(n, name, "expected a table");
    return n->as_table();
  }

  const toml::node* node(const toml::table& t, const std::string& key, const std::string& name,
                         bool required) const {
    const toml::node* n = t.get(key);
    if (!n && required)
      fail(nullptr, name, "missing required key");
    return n;
  }

  double number(const toml::table& t, const std::string& key, const std::string& name,
                std::optional<double> fallback) const {
    const toml::node* n = node(t, key, name, !fallback);
    if (!n)
      return *fallback;
    const auto v = n->value<double>();
    if (!v || !(n->is_integer() || n->is_floating_point()))
      fail(n, name, "expected a number");
    if (!std::isfinite(*v))
      fail(n, name, "must be finite");
    return *v;
  }
  double positive(const toml::table& t, const std::string& key, const std::string& name,
                  std::optional<double> fallback) const {
    const double v = number(t, key, name, fallback);
    if (!(v > 0))
      fail(t.get(key), name, "must be positive");
    return v;
  }
  std::string string(const toml::table& t, const std::string& key, const std::string& name,
                     std::optional<std::string> fallback) const {
    const toml::node* n = node(t, key, name, !fallback);
    if (!n)
      return *fallback;
    if (!n->is_string())
      fail(n, name, "expected a string");
    return *n->value<std::string>();
  }
  bool boolean(const toml::table& t, const std::string& key, const std::string& name,
               bool fallback) const {
    const toml::node* n = t.get(key);
    if (!n)
      return fallback;
    if (!n->is_boolean())
      fail(n, name, "expected true or false");
    return *n->value<bool>();
  }
  // An array of exactly `count` numbers.
  std::array<double, 3> vector(const toml::table& t, const std::string& key,
                               const std::string& name, int count, bool required,
                               std::array<double, 3> fallback = {0, 0, 0}) const {
    const toml::node* n = node(t, key, name, required);
    if (!n)
      return fallback;
    const toml::array* a = n->as_array();
    if (!a || int(a->size()) != count)
      fail(n, name, "expected an array of " + std::to_string(count) + " numbers");
    std::array<double, 3> out{0, 0, 0};
    for (int k = 0; k < count; ++k) {
      const auto v = (*a)[size_t(k)].value<double>();
      if (!v || !std::isfinite(*v))
        fail(n, name, "expected an array of " + std::to_string(count) + " numbers");
      out[k] = *v;
    }
    return out;
  }
  std::array<int, 3> counts(const toml::table& t, const std::string& key, const std::string& name,
                            int count) const {
    const toml::node* n = node(t, key, name, true);
    const toml::array* a = n->as_array();
    if (!a || int(a->size()) != count)
      fail(n, name, "expected an array of " + std::to_string(count) + " integers");
    std::array<int, 3> out{1, 1, 1};
    for (int k = 0; k < count; ++k) {
      const auto v = (*a)[size_t(k)].value<int64_t>();
      if (!v || !(*a)[size_t(k)].is_integer() || *v < 1 || *v > 100000000)
        fail(n, name, "expected positive integers");
      out[k] = int(*v);
    }
    return out;
  }

  // The tables of an array of tables ([[section]]).
  std::vector<const toml::table*> tables(const toml::table& root, const std::string& key,
                                         bool required) const {
    std::vector<const toml::table*> out;
    const toml::node* n = root.get(key);
    if (!n) {
      if (required)
        fail(nullptr, "[[" + key + "]]", "at least one is required");
      return out;
    }
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables())
      fail(n, key, "expected [[" + key + "]] tables");
    for (auto&& e : *a)
      out.push_back(e.as_table());
    return out;
  }

  std::string source_;
};

int axis_index(const Reader& r, const toml::node* n, const std::string& name, int dim) {
  const auto s = n ? n->value<std::string>() : std::nullopt;
  const std::string valid = std::string("xyz").substr(0, size_t(dim));
  if (!s || s->size() != 1 || valid.find((*s)[0]) == std::string::npos)
    r.fail(n, name,
           "expected one of the axes of a " + std::to_string(dim) + "D grid (" + valid + ")");
  return int(valid.find((*s)[0]));
}

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

std::vector<Material> read_materials(const Reader& r, const toml::table& root) {
  std::vector<Material> mats;
  for (const toml::table* t : r.tables(root, "material", true)) {
    r.check_keys(*t, "material");
    Material m;
    m.name = r.string(*t, "name", "material.name", std::nullopt);
    for (const auto& other : mats)
      if (other.name == m.name)
        r.fail(t->get("name"), "material.name", "duplicate material name");
    const std::string key = "material." + m.name + ".";
    const std::string model = r.string(*t, "model", key + "model", "linear");
    try {
      m.model = material_model_from_string(model);
    } catch (const InputError& e) {
      r.fail(t->get("model"), key + "model", e.what());
    }
    m.density = r.positive(*t, "density", key + "density", std::nullopt);
    m.youngs = r.positive(*t, "youngs", key + "youngs", std::nullopt);
    m.poisson = r.number(*t, "poisson", key + "poisson", 0.0);
    if (!(m.poisson > -1 && m.poisson < 0.5))
      r.fail(t->get("poisson"), key + "poisson", "must lie in (-1, 0.5)");
    mats.push_back(m);
  }
  return mats;
}

// Particles on the grid-aligned lattice of spacing h/ppc inside a disk/sphere or ellipse.
Particles lattice_in(const Grid& g, const std::array<double, 3>& center,
                     const std::array<double, 3>& semi, const std::array<int, 3>& ppc,
                     double density, int id) {
  const int d = g.dim();
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int a = 0; a < d; ++a) {
    const double h = g.cell_size(a);
    lo[a] = g.origin(a) + h * std::floor((center[a] - semi[a] - g.origin(a)) / h);
    hi[a] = g.origin(a) + h * std::ceil((center[a] + semi[a] - g.origin(a)) / h);
    lo[a] = std::max(lo[a], g.origin(a));
    hi[a] = std::min(hi[a], g.origin(a) + h * g.cells(a));
  }
  Particles box = make_block(g, lo, hi, ppc, density, id);
  std::vector<Index> keep;
  for (Index p = 0; p < box.size(); ++p) {
    double r2 = 0;
    for (int a = 0; a < d; ++a) {
      const double u = (box.X(p, a) - center[a]) / semi[a];
      r2 += u * u;
    }
    if (r2 <= 1)
      keep.push_back(p);
  }
  Particles P;
  P.resize(d, Index(keep.size()));
  for (Index k = 0; k < Index(keep.size()); ++k) {
    const Index p = keep[size_t(k)];
    P.X.row(k) = box.X.row(p);
    P.half_length.row(k) = box.half_length.row(p);
    P.mass[k] = box.mass[p];
    P.volume0[k] = box.volume0[p];
    P.material[k] = id;
  }
  return P;
}

Particles read_bodies(const Reader& r, const toml::table& root, const Grid& g,
                      const std::vector<Material>& mats) {
  const int d = g.dim();
  Particles all;
  all.resize(d, 0);
  int index = 0;
  for (const toml::table* t : r.tables(root, "body", true)) {
    r.check_keys(*t, "body");
    const std::string key = "body." + std::to_string(index++) + ".";
    const std::string mname = r.string(*t, "material", key + "material", std::nullopt);
    int id = -1;
    std::vector<std::string> names;
    for (size_t k = 0; k < mats.size(); ++k) {
      names.push_back(mats[k].name);
      if (mats[k].name == mname)
        id = int(k);
    }
    if (id < 0)
      r.fail(t->get("material"), key + "material", "no such material" + suggest(mname, names));
    const std::string region = r.string(*t, "region", key + "region", "box");
    const auto ppc = r.counts(*t, "ppc", key + "ppc", d);
    double estimate = 1; // particles of the body's bounding lattice
    for (int a = 0; a < d; ++a)
      estimate *= (g.cells(a) + 1.0) * ppc[a];
    if (estimate > kMaxParticles)
      r.fail(t->get("ppc"), key + "ppc",
             "up to " + std::to_string(long(estimate)) + " particles, more than the " +
                 std::to_string(long(kMaxParticles)) + " this build accepts");
    Particles P;
    if (region == "box") {
      const auto lo = r.vector(*t, "min", key + "min", d, true);
      const auto hi = r.vector(*t, "max", key + "max", d, true);
      for (int a = 0; a < d; ++a)
        if (!(hi[a] > lo[a]))
          r.fail(t->get("max"), key + "max", "must exceed min on every axis");
      if (!g.contains(lo) || !g.contains(hi))
        r.fail(t->get("max"), key + "min/max", "particles outside the grid");
      P = make_block(g, lo, hi, ppc, mats[size_t(id)].density, id);
    } else if (region == "disk" || region == "ellipse") {
      const auto c = r.vector(*t, "center", key + "center", d, true);
      std::array<double, 3> semi{1, 1, 1};
      if (region == "disk") {
        const double rad = r.positive(*t, "radius", key + "radius", std::nullopt);
        semi = {rad, rad, rad};
      } else {
        semi = r.vector(*t, "semi_axes", key + "semi_axes", d, true);
        for (int a = 0; a < d; ++a)
          if (!(semi[a] > 0))
            r.fail(t->get("semi_axes"), key + "semi_axes", "must be positive");
      }
      std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
      for (int a = 0; a < d; ++a) {
        lo[a] = c[a] - semi[a];
        hi[a] = c[a] + semi[a];
      }
      if (!g.contains(lo) || !g.contains(hi))
        r.fail(t->get("center"), key + "center", "particles outside the grid");
      P = lattice_in(g, c, semi, ppc, mats[size_t(id)].density, id);
    } else {
      r.fail(t->get("region"), key + "region", "unknown region (expected box | disk | ellipse)");
    }
    if (P.size() == 0)
      r.fail(t->get("region"), key + "region", "holds no particle");
    // Initial velocity: numbers or expressions of the initial position X, Y, Z.
    if (const toml::node* vn = t->get("velocity")) {
      const toml::array* va = vn->as_array();
      if (!va || int(va->size()) != d)
        r.fail(vn, key + "velocity", "expected " + std::to_string(d) + " numbers or expressions");
      for (int a = 0; a < d; ++a) {
        const toml::node& e = (*va)[size_t(a)];
        if (auto num = e.value<double>(); num && !e.is_string()) {
          P.V.col(a).setConstant(*num);
          continue;
        }
        if (!e.is_string())
          r.fail(vn, key + "velocity", "expected numbers or expression strings");
        const Expression expr(*e.value<std::string>(), {"X", "Y", "Z"},
                              r.where(vn, key + "velocity"));
        for (Index p = 0; p < P.size(); ++p) {
          double x[3] = {0, 0, 0};
          for (int b = 0; b < d; ++b)
            x[b] = P.X(p, b);
          P.V(p, a) = expr(x);
          if (!std::isfinite(P.V(p, a)))
            r.fail(vn, key + "velocity", "is not finite at particle " + std::to_string(p));
        }
      }
    }
    all.append(P);
  }
  return all;
}

BoundaryConditions read_bcs(const Reader& r, const toml::table& root, const Grid& g) {
  const int d = g.dim();
  BoundaryConditions bcs;
  int index = 0;
  for (const toml::table* t : r.tables(root, "bc", false)) {
    r.check_keys(*t, "bc");
    const std::string key = "bc." + std::to_string(index++) + ".";
    std::vector<Index> nodes;
    const toml::table* plane = r.table(*t, "plane", key + "plane", false);
    const toml::table* box = r.table(*t, "box", key + "box", false);
    if (bool(plane) == bool(box))
      r.fail(plane ? t->get("plane") : t->get("box"), key + "plane/box",
             "give exactly one of plane = {...} or box = {...}");
    try {
      if (plane) {
        r.check_keys(*plane, "bc.plane");
        const int axis = axis_index(r, plane->get("axis"), key + "plane.axis", d);
        nodes = nodes_on_plane(g, axis, r.number(*plane, "at", key + "plane.at", std::nullopt));
      } else {
        r.check_keys(*box, "bc.box");
        nodes = nodes_in_box(g, r.vector(*box, "min", key + "box.min", d, true),
                             r.vector(*box, "max", key + "box.max", d, true));
      }
    } catch (const InputError& e) {
      if (std::string(e.what()).find(": ") != std::string::npos &&
          std::string(e.what()).rfind(r.source_, 0) == 0)
        throw;
      r.fail(plane ? t->get("plane") : t->get("box"), key + (plane ? "plane" : "box"), e.what());
    }
    const toml::node* fixed = t->get("fixed");
    const toml::table* vel = r.table(*t, "velocity", key + "velocity", false);
    if (bool(fixed) == bool(vel))
      r.fail(fixed ? fixed : t->get("velocity"), key + "fixed/velocity",
             "give exactly one of fixed = [...] or velocity = {...}");
    if (fixed) {
      const toml::array* fa = fixed->as_array();
      if (!fa || fa->empty())
        r.fail(fixed, key + "fixed", "expected an array of axes, e.g. [\"x\"]");
      for (auto&& e : *fa) {
        VelocityCondition c;
        const int a = axis_index(r, &e, key + "fixed", d);
        c.nodes = nodes;
        c.direction = Eigen::Vector3d::Unit(a);
        c.label = key + "fixed";
        bcs.conditions.push_back(std::move(c));
      }
    } else {
      r.check_keys(*vel, "bc.velocity");
      const auto dir = r.vector(*vel, "direction", key + "velocity.direction", d, true);
      Eigen::Vector3d n(dir[0], dir[1], dir[2]);
      if (!(n.norm() > 0))
        r.fail(vel->get("direction"), key + "velocity.direction", "must be a non-zero vector");
      VelocityCondition c;
      c.nodes = nodes;
      c.direction = n.normalized();
      c.label = key + "velocity";
      const toml::node* vn = r.node(*vel, "value", key + "velocity.value", true);
      if (vn->is_string()) {
        auto expr = std::make_shared<Expression>(*vn->value<std::string>(),
                                                 std::vector<std::string>{"t", "x", "y", "z"},
                                                 r.where(vn, key + "velocity.value"));
        c.value = [expr](double time, const Eigen::Vector3d& x) {
          const double v[4] = {time, x[0], x[1], x[2]};
          return (*expr)(v);
        };
      } else if (auto num = vn->value<double>()) {
        const double value = *num;
        c.value = [value](double, const Eigen::Vector3d&) { return value; };
      } else {
        r.fail(vn, key + "velocity.value", "expected a number or an expression of t, x, y, z");
      }
      bcs.conditions.push_back(std::move(c));
    }
  }
  return bcs;
}

// FMPM(k), XPIC(m), blending, periodic and dynamic FMPM, BC method, exact solver options.
void read_fmpm(const Reader& r, const toml::table& scheme, StepOptions& step) {
  FmpmOptions& f = step.fmpm;
  const toml::node* on = scheme.get("order");
  if (on) {
    const auto k = on->value<int64_t>();
    if (!k || !on->is_integer() || *k < 1 || *k > 100000)
      r.fail(on, "scheme.order", "must be an integer of at least 1");
    f.order = int(*k);
  } else if (step.velocity == VelocityUpdate::FMPM || step.velocity == VelocityUpdate::XPIC) {
    r.fail(nullptr, "scheme.order", "missing required key (the order k of FMPM or m of XPIC)");
  }
  f.blend_alpha = r.number(scheme, "blend_alpha", "scheme.blend_alpha", 1.0);
  if (!(f.blend_alpha >= 0 && f.blend_alpha <= 1))
    r.fail(scheme.get("blend_alpha"), "scheme.blend_alpha", "must lie in [0, 1]");
  if (const toml::node* mn = scheme.get("blend_every")) {
    const auto m = mn->value<int64_t>();
    if (!m || !mn->is_integer() || *m < 1 || *m > 100000)
      r.fail(mn, "scheme.blend_every", "must be an integer of at least 1");
    f.blend_every = int(*m);
  }
  step.periodic_cx = r.number(scheme, "periodic_cx", "scheme.periodic_cx", 0.0);
  if (scheme.get("periodic_cx") && !(step.periodic_cx > 0))
    r.fail(scheme.get("periodic_cx"), "scheme.periodic_cx", "must be positive");
  try {
    f.metric = convergence_metric_from_string(
        r.string(scheme, "dynamic_metric", "scheme.dynamic_metric", "none"));
  } catch (const InputError& e) {
    r.fail(scheme.get("dynamic_metric"), "scheme.dynamic_metric", e.what());
  }
  f.dynamic_limit = r.number(scheme, "dynamic_limit", "scheme.dynamic_limit", 0.0);
  if (!(f.dynamic_limit >= 0))
    r.fail(scheme.get("dynamic_limit"), "scheme.dynamic_limit", "must be non-negative");
  if (f.metric != ConvergenceMetric::None && !scheme.get("dynamic_limit"))
    r.fail(scheme.get("dynamic_metric"), "scheme.dynamic_metric",
           "needs scheme.dynamic_limit (the convergence limit)");
  try {
    f.bc_method =
        bc_method_from_string(r.string(scheme, "bc_method", "scheme.bc_method", "incremental"));
  } catch (const InputError& e) {
    r.fail(scheme.get("bc_method"), "scheme.bc_method", e.what());
  }
  const double reg = r.number(scheme, "exact_regularization", "scheme.exact_regularization", 0.0);
  if (!(reg >= 0))
    r.fail(scheme.get("exact_regularization"), "scheme.exact_regularization",
           "must be non-negative");
  if (step.velocity == VelocityUpdate::Exact)
    step.solver = make_cholmod_solver(reg);
}

// Parses a --set value as a TOML value, or keeps it as a string.
void assign(toml::table& t, const std::string& key, const std::string& value) {
  check_non_ascii("v = " + value, "--set " + key);
  try {
    toml::table v = toml::parse("v = " + value, std::string_view("--set"));
    toml::node* n = v.get("v");
    if (n->is_integer())
      t.insert_or_assign(key, *n->value<int64_t>());
    else if (n->is_floating_point())
      t.insert_or_assign(key, *n->value<double>());
    else if (n->is_boolean())
      t.insert_or_assign(key, *n->value<bool>());
    else if (n->is_string())
      t.insert_or_assign(key, *n->value<std::string>());
    else if (n->is_array())
      t.insert_or_assign(key, *n->as_array());
    else if (n->is_table())
      t.insert_or_assign(key, *n->as_table());
    else
      t.insert_or_assign(key, value);
  } catch (const toml::parse_error&) {
    t.insert_or_assign(key, value);
  }
}

void apply_override(const Reader& r, toml::table& root, const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set " + spec + ": expected section.key=value");
  const std::string path = spec.substr(0, eq), value = spec.substr(eq + 1);
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');)
    parts.push_back(part);
  const auto& top = schema().at("");
  if (parts.size() < 2 || parts.size() > 3 ||
      std::find(top.begin(), top.end(), parts[0]) == top.end())
    throw InputError("--set " + spec + ": expected section.key=value with a section of " +
                     "grid, material, body, bc, time, scheme, output, loads" +
                     (parts.empty() ? "" : suggest(parts[0], top)));
  toml::node* sec = root.get(parts[0]);
  const bool listed = parts[0] == "material" || parts[0] == "body" || parts[0] == "bc";
  toml::table* target = nullptr;
  if (listed) {
    if (parts.size() != 3)
      throw InputError("--set " + spec + ": [[" + parts[0] + "]] entries are addressed as " +
                       parts[0] + ".<name or index>.key=value");
    toml::array* arr = sec ? sec->as_array() : nullptr;
    if (arr)
      for (size_t k = 0; k < arr->size() && !target; ++k) {
        toml::table* t = (*arr)[k].as_table();
        const auto name = t ? t->get("name") : nullptr;
        if (t &&
            ((name && name->value<std::string>() == parts[1]) || std::to_string(k) == parts[1]))
          target = t;
      }
    if (!target)
      throw InputError("--set " + spec + ": no [[" + parts[0] + "]] named or numbered '" +
                       parts[1] + "'");
  } else {
    if (parts.size() != 2)
      throw InputError("--set " + spec + ": expected " + parts[0] + ".key=value");
    if (!sec)
      sec = &root.insert_or_assign(parts[0], toml::table{}).first->second;
    target = sec->as_table();
    if (!target)
      throw InputError("--set " + spec + ": '" + parts[0] + "' is not a table");
  }
  const std::string& key = parts.back();
  const auto& valid = schema().at(parts[0]);
  if (std::find(valid.begin(), valid.end(), key) == valid.end())
    throw InputError("--set " + spec + ": unknown key '" + parts[0] + "." + key + "'" +
                     suggest(key, valid));
  assign(*target, key, value);
  (void)r;
}

} // namespace

RunConfig read_input(const std::string& text, const std::string& source,
                     const std::vector<std::string>& overrides) {
  const Reader r(source);
  check_non_ascii(text, source);
  toml::table root;
  try {
    root = toml::parse(text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ":" << e.source().begin.line << ": " << e.description();
    throw InputError(os.str());
  }
  for (const auto& o : overrides)
    apply_override(r, root, o);
  r.check_keys(root, "");

  RunConfig cfg;
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
  cfg.model.particles = read_bodies(r, root, grid, cfg.model.materials);
  cfg.model.bcs = read_bcs(r, root, grid);

  const toml::table* time = r.table(root, "time", "[time]", true);
  r.check_keys(*time, "time");
  cfg.time.courant = r.positive(*time, "courant", "time.courant", 0.5);
  cfg.time.end = r.positive(*time, "end", "time.end", std::nullopt);

  static const toml::table empty;
  const toml::table* scheme = r.table(root, "scheme", "[scheme]", false);
  if (!scheme)
    scheme = &empty;
  r.check_keys(*scheme, "scheme");
  try {
    cfg.step.scheme =
        update_scheme_from_string(r.string(*scheme, "update", "scheme.update", "USL"));
  } catch (const InputError& e) {
    r.fail(scheme->get("update"), "scheme.update", e.what());
  }
  try {
    cfg.step.velocity =
        velocity_update_from_string(r.string(*scheme, "velocity", "scheme.velocity", "FLIP"));
  } catch (const InputError& e) {
    r.fail(scheme->get("velocity"), "scheme.velocity", e.what());
  }
  try {
    cfg.step.shape = shape_from_string(r.string(*scheme, "shape", "scheme.shape", "cpdi"));
  } catch (const InputError& e) {
    r.fail(scheme->get("shape"), "scheme.shape", e.what());
  }
  // α of Eqs. (8)–(9): 1 for FLIP (the common choice), ½ for grid-velocity updates (Eq. 9's
  // consistent choice, FMPM 2026 §2.3).
  const double alpha_default = cfg.step.velocity == VelocityUpdate::FLIP ? 1.0 : 0.5;
  cfg.step.position_alpha =
      r.number(*scheme, "position_alpha", "scheme.position_alpha", alpha_default);
  if (!(cfg.step.position_alpha >= 0 && cfg.step.position_alpha <= 1))
    r.fail(scheme->get("position_alpha"), "scheme.position_alpha", "must lie in [0, 1]");
  read_fmpm(r, *scheme, cfg.step);

  const toml::table* loads = r.table(root, "loads", "[loads]", false);
  if (loads) {
    r.check_keys(*loads, "loads");
    cfg.model.body_force = r.vector(*loads, "gravity", "loads.gravity", grid.dim(), false);
  }

  const toml::table* output = r.table(root, "output", "[output]", false);
  if (!output)
    output = &empty;
  r.check_keys(*output, "output");
  const std::string stem = std::filesystem::path(source).stem().string();
  cfg.output.file = r.string(*output, "file", "output.file", (stem.empty() ? "run" : stem) + ".h5");
  cfg.output.every = r.positive(*output, "every", "output.every", cfg.time.end / 10);
  cfg.output.matrices = r.boolean(*output, "matrices", "output.matrices", false);

  // The shape functions of every particle must fit in the grid.
  try {
    (void)assemble(grid, cfg.model.particles, cfg.step.shape);
  } catch (const NumericalError& e) {
    throw InputError(source + ": particles outside the grid for scheme.shape = \"" +
                     std::string(to_string(cfg.step.shape)) + "\": " + e.what());
  }
  return cfg;
}

RunConfig read_input_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path + ": cannot open the input file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return read_input(ss.str(), path, overrides);
}

} // namespace smpm
