// SPDX-License-Identifier: BSD-3-Clause
// The conditions of an input: the [[bc]] tables (fixed axes, velocities and temperatures on planes
// and boxes of nodes, moving walls) and the prescribed velocities of the rigid materials, their
// values numbers or expressions of t.
#include "expression.hpp"
#include "reader.hpp"

#include <functional>

namespace smpm::detail {

int axis_index(const Reader& r, const toml::node* n, const std::string& name, int dim) {
  const auto s = n ? n->value<std::string>() : std::nullopt;
  const std::string valid = std::string("xyz").substr(0, size_t(dim));
  if (!s || s->size() != 1 || valid.find((*s)[0]) == std::string::npos)
    r.fail(n, name,
           "expected one of the axes of a " + std::to_string(dim) + "D grid (" + valid + ")");
  return int(valid.find((*s)[0]));
}

namespace {
// The nodes of a [[bc]]: plane = {axis, at} or box = {min, max}.
std::vector<Index> bc_nodes(const Reader& r, const toml::table& t, const std::string& key,
                            const Grid& g) {
  const int d = g.dim();
  const toml::table* plane = r.table(t, "plane", key + "plane", false);
  const toml::table* box = r.table(t, "box", key + "box", false);
  if (bool(plane) == bool(box))
    r.fail(plane ? t.get("plane") : t.get("box"), key + "plane/box",
           "give exactly one of plane = {...} or box = {...}");
  try {
    if (plane) {
      r.check_keys(*plane, "bc.plane");
      const int axis = axis_index(r, plane->get("axis"), key + "plane.axis", d);
      return nodes_on_plane(g, axis, r.number(*plane, "at", key + "plane.at", std::nullopt));
    }
    r.check_keys(*box, "bc.box");
    return nodes_in_box(g, r.vector(*box, "min", key + "box.min", d, true),
                        r.vector(*box, "max", key + "box.max", d, true));
  } catch (const InputError& e) {
    if (std::string(e.what()).find(": ") != std::string::npos &&
        std::string(e.what()).rfind(r.source_, 0) == 0)
      throw;
    // No node on the plane (its position `at` misses the grid) or in the box.
    r.fail(plane ? plane->get("at") : t.get("box"), key + (plane ? "plane.at" : "box"), e.what());
  }
}

// A condition's value: a number or an expression of t, x, y, z (held by value: a copy of the
// condition, of the Model, evaluates its own parser). A temperature (`absolute`) must be
// positive.
VelocityCondition value_condition(const Reader& r, const toml::node* vn, const std::string& name,
                                  bool absolute) {
  VelocityCondition c;
  c.label = name;
  if (vn->is_string()) {
    c.value = [expr = Expression(*vn->value<std::string>(), {"t", "x", "y", "z"},
                                 r.where(vn, name))](double time, const Eigen::Vector3d& x) {
      const double v[4] = {time, x[0], x[1], x[2]};
      return expr(v);
    };
  } else if (auto num = vn->value<double>(); num && !vn->is_boolean()) {
    const double value = *num;
    if (!std::isfinite(value))
      r.fail(vn, name, "must be finite");
    if (absolute && !(value > 0))
      r.fail(vn, name, "must be positive (temperatures are absolute)");
    c.value = [value](double, const Eigen::Vector3d&) { return value; };
  } else {
    r.fail(vn, name, "expected a number or an expression of t, x, y, z");
  }
  return c;
}

// velocity = {direction, value}: a number or an expression of t, x, y, z.
VelocityCondition velocity_condition(const Reader& r, const toml::table& vel,
                                     const std::string& key, int d) {
  r.check_keys(vel, "bc.velocity");
  const toml::node* vn = r.node(vel, "value", key + "velocity.value", true);
  VelocityCondition c = value_condition(r, vn, key + "velocity.value", false);
  c.direction = r.unit_vector(vel, "direction", key + "velocity.direction", d);
  c.label = key + "velocity";
  return c;
}

// A function of t from a number or an expression of t (held by value: copies re-parse).
std::function<double(double)> time_function(const Reader& r, const toml::table& t,
                                            const std::string& key, const std::string& name,
                                            bool required) {
  const toml::node* n = r.node(t, key, name, required);
  if (!n)
    return nullptr;
  if (n->is_string())
    return [e = Expression(*n->value<std::string>(), {"t"}, r.where(n, name))](double time) {
      return e(&time);
    };
  if (!(n->is_integer() || n->is_floating_point()))
    r.fail(n, name, "expected a number or an expression of t");
  const double value = *n->value<double>();
  if (!std::isfinite(value))
    r.fail(n, name, "must be finite");
  return [value](double) { return value; };
}

// wall = {normal, position, velocity, gradient, depth | depth_cells}: a moving wall (§3.1).
MovingWall moving_wall(const Reader& r, const toml::table& w, const std::string& key,
                       const Grid& g) {
  r.check_keys(w, "bc.wall");
  const int d = g.dim();
  MovingWall wall;
  wall.normal = r.unit_vector(w, "normal", key + "wall.normal", d);
  wall.position = time_function(r, w, "position", key + "wall.position", true);
  wall.velocity = time_function(r, w, "velocity", key + "wall.velocity", false);
  wall.gradient = time_function(r, w, "gradient", key + "wall.gradient", false);
  if (w.get("depth") && w.get("depth_cells"))
    r.fail(w.get("depth_cells"), key + "wall.depth_cells", "give depth or depth_cells, not both");
  if (w.get("depth_cells"))
    wall.depth = r.number(w, "depth_cells", key + "wall.depth_cells", 0.0) * g.min_cell_size();
  else
    wall.depth = r.number(w, "depth", key + "wall.depth", 0.0);
  if (!(wall.depth >= 0))
    r.fail(w.get(w.get("depth_cells") ? "depth_cells" : "depth"),
           key + (w.get("depth_cells") ? "wall.depth_cells" : "wall.depth"),
           "must be non-negative");
  wall.label = key + "wall";
  return wall;
}

// fixed = ["x", ...]: a zero-velocity condition on the nodes for each axis it names.
void add_fixed(const Reader& r, const toml::node* fixed, const std::string& key, int d,
               const std::vector<Index>& nodes, BoundaryConditions& bcs) {
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
}

// The conditions of one [[bc]] table: a moving wall alone, or on its plane or box of nodes a
// temperature, a velocity or fixed axes.
void read_bc(const Reader& r, const toml::table& t, const std::string& key, const Grid& g,
             ConditionTables& out) {
  const int d = g.dim();
  BoundaryConditions& bcs = out.velocity;
  if (const toml::table* w = r.table(t, "wall", key + "wall", false)) {
    for (const char* other : {"plane", "box", "fixed", "velocity", "temperature"})
      if (t.get(other))
        r.fail(t.get(other), key + other,
               "a wall selects its own nodes and values; give wall = {...} alone");
    bcs.add_wall(moving_wall(r, *w, key, g));
    return;
  }
  const std::vector<Index> nodes = bc_nodes(r, t, key, g);
  if (const toml::node* tn = t.get("temperature")) {
    for (const char* other : {"fixed", "velocity"})
      if (t.get(other))
        r.fail(t.get(other), key + other,
               "a [[bc]] sets a temperature or velocities; give them in separate tables");
    VelocityCondition c = value_condition(r, tn, key + "temperature", true);
    c.nodes = nodes;
    out.temperature.conditions.push_back(std::move(c));
    return;
  }
  const toml::node* fixed = t.get("fixed");
  const toml::table* vel = r.table(t, "velocity", key + "velocity", false);
  if (bool(fixed) == bool(vel))
    r.fail(fixed ? fixed : t.get("velocity"), key + "fixed/velocity",
           "give exactly one of fixed = [...] or velocity = {...}");
  if (vel) {
    VelocityCondition c = velocity_condition(r, *vel, key, d);
    c.nodes = nodes;
    bcs.conditions.push_back(std::move(c));
    return;
  }
  add_fixed(r, fixed, key, d, nodes, bcs);
}

// The static velocity conditions superpose (walls are checked every step) and each node has one
// temperature condition at most.
void check_conditions(const Reader& r, ConditionTables& out) {
  try {
    out.velocity.check_superposition(); // static conditions; walls are checked every step
  } catch (const InputError& e) {
    throw InputError(r.source_ + ": [[bc]]: " + e.what());
  }
  try {
    out.temperature.check_one_condition_per_node();
  } catch (const InputError& e) {
    throw InputError(r.source_ + ": [[bc]]: " + e.what());
  }
}

} // namespace

std::vector<RigidMotion> read_rigid(const Reader& r, const toml::table& root,
                                    const std::vector<Material>& mats, int dim) {
  std::vector<RigidMotion> motions;
  const std::vector<const toml::table*> tables = r.tables(root, "material", true);
  for (size_t k = 0; k < tables.size() && k < mats.size(); ++k) {
    const toml::table& t = *tables[k];
    const std::string key = "material." + mats[k].name + ".";
    if (mats[k].model != MaterialModel::Rigid) {
      for (const char* only : {"velocity", "free"})
        if (t.get(only))
          r.fail(t.get(only), key + only, "only model = \"rigid\" takes it");
      continue;
    }
    const toml::node* vn = r.node(t, "velocity", key + "velocity", true);
    const toml::array* va = vn->as_array();
    if (!va || int(va->size()) != dim)
      r.fail(vn, key + "velocity",
             "expected " + std::to_string(dim) + " numbers or expressions of t");
    RigidMotion m;
    m.material = int(k);
    m.label = "material." + mats[k].name;
    m.free = r.boolean(t, "free", key + "free", false);
    if (m.free)
      for (int a = 0; a < dim; ++a)
        if (!(*va)[size_t(a)].is_number())
          r.fail(vn, key + "velocity",
                 "a free rigid body takes its initial velocity: " + std::to_string(dim) +
                     " numbers");
    for (int a = 0; a < dim; ++a) {
      toml::table axis; // the component as a key of its own, for time_function's messages
      axis.insert("v", (*va)[size_t(a)]);
      m.velocity[size_t(a)] =
          time_function(r, axis, "v", key + "velocity[" + std::to_string(a) + "]", true);
    }
    motions.push_back(std::move(m));
  }
  return motions;
}

ConditionTables read_bcs(const Reader& r, const toml::table& root, const Grid& g) {
  ConditionTables out;
  int index = 0;
  for (const toml::table* t : r.tables(root, "bc", false)) {
    r.check_keys(*t, "bc");
    read_bc(r, *t, "bc." + std::to_string(index++) + ".", g, out);
  }
  check_conditions(r, out);
  return out;
}

} // namespace smpm::detail
