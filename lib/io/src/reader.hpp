// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The TOML reader's helper class and the readers of the input's tables that its sources share
// (internal to sparsempm_io).

#include "sparsempm/errors.hpp"
#include "sparsempm/input.hpp"
#include "sparsempm/model.hpp"
#include "toml_text.hpp"

#include <toml++/toml.h>

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#ifndef SMPM_INPUT_MAX_PARTICLES
#define SMPM_INPUT_MAX_PARTICLES 20000000 // ~20 GB of particle and operator storage
#endif
#ifndef SMPM_INPUT_MAX_NODES
#define SMPM_INPUT_MAX_NODES 50000000
#endif

namespace smpm::detail {

inline constexpr double kMaxParticles = SMPM_INPUT_MAX_PARTICLES;
/// Largest bitmap body, in pixels (2^28: a 16384 x 16384 image, 256 MB of grey levels).
inline constexpr double kMaxImagePixels = double(1 << 28);
inline constexpr double kMaxNodes = SMPM_INPUT_MAX_NODES;
inline constexpr long kMaxCount = 100000000; // cells or particles per cell along one axis

// Reads one input; carries the file name for messages.
class Reader {
public:
  explicit Reader(std::string source, std::vector<std::string> file_directories = {})
      : source_(std::move(source)), file_directories_(std::move(file_directories)) {}

  // Where a file the input names by a relative path (an image) is looked for before the input
  // file's own directory: a stored input's first input file's directory (stored_config).
  const std::vector<std::string>& file_directories() const { return file_directories_; }

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
    os << ": " << clip(key, 120); // a key may be as long as the file
    if (n && n->is_value()) {
      std::ostringstream value;
      n->visit([&](auto&& v) { value << v; });
      os << " = " << clip(value.str());
    }
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
  // A name of one of the library's choices (an enum), read by its parser (`*_from_string`):
  // its message, naming the valid choices, at the key's line.
  template <class E>
  E choice(const toml::table& t, const std::string& key, const std::string& name,
           const std::string& fallback, E (*parse)(std::string_view)) const {
    const std::string text = string(t, key, name, fallback);
    try {
      return parse(text);
    } catch (const InputError& e) {
      fail(t.get(key), name, e.what());
    }
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
      if (!v)
        fail(n, name, "expected an array of " + std::to_string(count) + " numbers");
      if (!std::isfinite(*v))
        fail(n, name, "every entry must be finite");
      out[k] = *v;
    }
    return out;
  }
  // A direction: an array of `count` numbers, not all zero, as a unit vector (scaled by its
  // largest entry first, so that entries like 1e200 do not overflow the norm).
  Eigen::Vector3d unit_vector(const toml::table& t, const std::string& key, const std::string& name,
                              int count) const {
    const auto v = vector(t, key, name, count, true);
    Eigen::Vector3d n(v[0], v[1], v[2]);
    const double largest = n.cwiseAbs().maxCoeff();
    if (!(largest > 0))
      fail(t.get(key), name, "must be a non-zero vector");
    n /= largest;
    return n.normalized();
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
      if (!v || !(*a)[size_t(k)].is_integer() || *v < 1)
        fail(n, name, "expected positive integers");
      if (*v > kMaxCount)
        fail(n, name,
             "every entry must be at most " + std::to_string(kMaxCount) + " (got " +
                 std::to_string(*v) + ")");
      out[k] = int(*v);
    }
    return out;
  }

  // The tables of an array of tables ([[section]]).
  // `within`: the path of the table that holds them in messages ("loads." for [[loads.traction]]).
  std::vector<const toml::table*> tables(const toml::table& root, const std::string& key,
                                         bool required, const std::string& within = "") const {
    std::vector<const toml::table*> out;
    const std::string name = within + key;
    const toml::node* n = root.get(key);
    if (!n) {
      if (required)
        fail(nullptr, "[[" + name + "]]", "at least one is required");
      return out;
    }
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables())
      fail(n, name, "expected [[" + name + "]] tables");
    for (auto&& e : *a)
      out.push_back(e.as_table());
    return out;
  }

  std::string source_;
  std::vector<std::string> file_directories_;
};

/// The [[material]] tables, in their order (input_materials.cpp).
std::vector<Material> read_materials(const Reader& r, const toml::table& root);
/// The [step] table into `step`, checked against the library's limits (input_step.cpp).
void read_step(const Reader& r, const toml::table& root, StepOptions& step);
int axis_index(const Reader& r, const toml::node* n, const std::string& name, int dim);
/// The particles [first, first + count) of one [[body]], by its name (body.K.name; "" when
/// it has none).
struct BodyRange {
  std::string name;
  Index first = 0, count = 0;
};
Particles read_bodies(const Reader& r, const toml::table& root, const Grid& g,
                      const std::vector<Material>& mats, std::vector<BodyRange>* ranges = nullptr);
/// The motions of the rigid materials (model = "rigid", velocity = [numbers or expressions of
/// t]), one per rigid material in their order.
std::vector<RigidMotion> read_rigid(const Reader& r, const toml::table& root,
                                    const std::vector<Material>& mats, int dim);
/// [[loads.body_force]] and [[loads.traction]] on the particles of the bodies.
std::vector<ParticleLoad> read_loads(const Reader& r, const toml::table& loads, const Particles& P,
                                     const std::vector<BodyRange>& bodies);
ConditionTables read_bcs(const Reader& r, const toml::table& root, const Grid& g);
Contact read_contact(const Reader& r, const toml::table& root, const std::vector<Material>& mats,
                     int dim);

} // namespace smpm::detail
