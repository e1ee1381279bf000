// SPDX-License-Identifier: BSD-3-Clause
// [[loads.body_force]] and [[loads.traction]]: the ParticleLoads of loads.hpp.
#include "expression.hpp"
#include "reader.hpp"

#include "sparsempm/loads.hpp"

#include <optional>

namespace smpm::detail {

namespace {
// The particles of `body = NAME | INDEX` (every particle without the key).
std::vector<Index> load_particles(const Reader& r, const toml::table& t, const std::string& key,
                                  const Particles& P, const std::vector<BodyRange>& bodies) {
  std::vector<Index> ids;
  const toml::node* n = t.get("body");
  const BodyRange* body = nullptr;
  if (!n) {
    ids.resize(size_t(P.size()));
    for (Index p = 0; p < P.size(); ++p)
      ids[size_t(p)] = p;
    return ids;
  }
  if (n->is_string()) {
    std::vector<std::string> names;
    for (const BodyRange& b : bodies) {
      if (b.name == *n->value<std::string>())
        body = &b;
      if (!b.name.empty())
        names.push_back(b.name);
    }
    if (!body)
      r.fail(n, key + "body",
             "no [[body]] has this name" + (names.empty()
                                                ? std::string(" (give a body name = \"...\")")
                                                : suggest(*n->value<std::string>(), names)));
  } else if (n->is_integer()) {
    const long long k = *n->value<long long>();
    if (k < 0 || k >= (long long)bodies.size())
      r.fail(n, key + "body",
             "expected a body's index from 0 to " + std::to_string(bodies.size() - 1));
    body = &bodies[size_t(k)];
  } else {
    r.fail(n, key + "body", "expected a body's name or its index");
  }
  for (Index p = body->first; p < body->first + body->count; ++p)
    ids.push_back(p);
  return ids;
}

// value = [b_x, b_y, b_z]: numbers or expressions of t, x, y, z (held by value: a copy of the
// Model evaluates its own parsers). Evaluated once per step for all of the load's particles.
std::function<void(double, const Field&, Field&)> load_value(const Reader& r, const toml::table& t,
                                                             const std::string& key, int d) {
  const toml::node* vn = r.node(t, "value", key + "value", true);
  const toml::array* va = vn->as_array();
  if (!va || int(va->size()) != d)
    r.fail(vn, key + "value", "expected " + std::to_string(d) + " numbers or expressions");
  // A copy of the function copies its expressions, and an Expression copy parses its own: copies
  // of a Model never share a parser.
  struct Value {
    std::vector<double> constants;
    std::vector<std::optional<Expression>> exprs;
    void operator()(double time, const Field& x, Field& b) const {
      for (Index k = 0; k < x.rows(); ++k) {
        double v[4] = {time, 0, 0, 0};
        for (int c = 0; c < x.cols(); ++c)
          v[1 + c] = x(k, c);
        for (size_t a = 0; a < constants.size(); ++a)
          b(k, Index(a)) = exprs[a] ? (*exprs[a])(v) : constants[a];
      }
    }
  };
  Value value{std::vector<double>(size_t(d), 0.0),
              std::vector<std::optional<Expression>>(size_t(d))};
  for (int a = 0; a < d; ++a) {
    const toml::node& e = (*va)[size_t(a)];
    if (e.is_string()) {
      value.exprs[size_t(a)].emplace(*e.value<std::string>(),
                                     std::vector<std::string>{"t", "x", "y", "z"},
                                     r.where(vn, key + "value"));
    } else if (auto num = e.value<double>(); num && (e.is_integer() || e.is_floating_point())) {
      if (!std::isfinite(*num))
        r.fail(vn, key + "value", "must be finite");
      value.constants[size_t(a)] = *num;
    } else {
      r.fail(vn, key + "value", "expected numbers or expression strings of t, x, y, z");
    }
  }
  return value;
}
} // namespace

std::vector<ParticleLoad> read_loads(const Reader& r, const toml::table& loads, const Particles& P,
                                     const std::vector<BodyRange>& bodies) {
  std::vector<ParticleLoad> out;
  const int d = P.dim;
  const std::vector<const toml::table*> forces = r.tables(loads, "body_force", false, "loads.");
  for (size_t k = 0; k < forces.size(); ++k) {
    const std::string key = "loads.body_force." + std::to_string(k) + ".";
    r.check_keys(*forces[k], "loads.body_force");
    ParticleLoad load;
    load.kind = LoadKind::BodyForce;
    load.label = key.substr(0, key.size() - 1);
    load.particles = load_particles(r, *forces[k], key, P, bodies);
    load.value = load_value(r, *forces[k], key, d);
    out.push_back(std::move(load));
  }
  const std::vector<const toml::table*> tractions = r.tables(loads, "traction", false, "loads.");
  for (size_t k = 0; k < tractions.size(); ++k) {
    const toml::table& t = *tractions[k];
    const std::string key = "loads.traction." + std::to_string(k) + ".";
    r.check_keys(t, "loads.traction");
    ParticleLoad load;
    load.kind = LoadKind::Traction;
    load.label = key.substr(0, key.size() - 1);
    const std::vector<Index> set = load_particles(r, t, key, P, bodies);
    // face = "+x" | "-x" | "+y" | ...: the side of the particles' domains the traction acts on.
    const std::string face = r.string(t, "face", key + "face", std::nullopt);
    const std::string axes = "xyz";
    if (face.size() != 2 || (face[0] != '+' && face[0] != '-') ||
        axes.find(face[1]) == std::string::npos || int(axes.find(face[1])) >= d)
      r.fail(t.get("face"), key + "face",
             std::string("expected +x or -x") + (d > 1 ? ", +y, -y" : "") +
                 (d > 2 ? ", +z, -z" : ""));
    const int axis = int(axes.find(face[1]));
    std::vector<Index> on_face = exposed_face(P, set, axis, face[0] == '+' ? 1 : -1);
    if (const toml::table* box = r.table(t, "box", key + "box", false)) {
      r.check_keys(*box, "loads.traction.box");
      const auto lo = r.vector(*box, "min", key + "box.min", d, true);
      const auto hi = r.vector(*box, "max", key + "box.max", d, true);
      std::erase_if(on_face, [&](Index p) {
        for (int a = 0; a < d; ++a)
          if (P.X(p, a) < lo[size_t(a)] || P.X(p, a) > hi[size_t(a)])
            return true;
        return false;
      });
    }
    if (on_face.empty())
      r.fail(t.get("face"), key + "face",
             "no particle of the body has this face exposed" +
                 std::string(t.get("box") ? " in the box" : ""));
    load.particles = std::move(on_face);
    load.axis = axis;
    load.side = face[0] == '+' ? 1 : -1;
    load.area.resize(Index(load.particles.size()));
    for (size_t i = 0; i < load.particles.size(); ++i)
      load.area[Index(i)] = face_area(P, load.particles[i], axis);
    load.value = load_value(r, t, key, d);
    out.push_back(std::move(load));
  }
  return out;
}

} // namespace smpm::detail
