// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/boundary.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace smpm {

Index BoundaryConditions::num_constrained() const {
  Index n = 0;
  for (const auto& c : conditions)
    n += Index(c.nodes.size());
  return n;
}

namespace {
using Mask = Eigen::Array<bool, Eigen::Dynamic, 1>;
/// A change of one row of a node field (d ≤ 3 entries, on the stack).
using RowChange = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, 3>;

// FMPM 2026 Table 2 (top block) on every constrained node: first zero each constrained
// direction, x_i ← x_i − (x_i · n̂_b) n̂_b, then add the values, x_i ← x_i + w_i v_b(t, x_i) n̂_b
// (w_i = weight(r), r the row; 0 only zeroes). Parallel conditions thus add their values,
// perpendicular ones set their own components. changed(r, Δ) sees every change Δ (a d-vector)
// of row r. A node field of several velocity fields (block columns, operators.hpp) holds node i
// in rows α n_g + i: a condition acts on node i of every field, or of its `field` alone.
template <class Weight, class Changed>
void set_components(const std::vector<VelocityCondition>& conditions, const Grid& grid, double t,
                    Field& x, const Mask* active, Weight&& weight, Changed&& changed) {
  const int d = int(x.cols());
  const Index ng = grid.num_nodes();
  SMPM_VERIFY(ng > 0 && x.rows() % ng == 0, "velocity BCs: a node field of " +
                                                std::to_string(x.rows()) + " rows on a grid of " +
                                                std::to_string(ng) + " nodes");
  // The conditions name nodes of the whole grid; a window of it (Grid::window) holds some. A
  // node beyond the whole grid is a condition of another grid: refused, never written.
  const bool window = grid.is_window();
  const Index whole_nodes = grid.whole_num_nodes();
  auto node = [&](const VelocityCondition& c, Index whole) {
    if (whole < 0 || whole >= whole_nodes)
      throw InputError("condition '" + c.label + "' names node " + std::to_string(whole) +
                       ", not a node of this grid of " + std::to_string(whole_nodes) +
                       " nodes (the conditions of another model?)");
    return window ? grid.node_of_whole(whole) : whole;
  };
  for (Index block = 0; block < x.rows(); block += ng) {
    auto skips = [&](const VelocityCondition& c) { return c.field >= 0 && block != c.field * ng; };
    for (const auto& c : conditions) {
      if (skips(c))
        continue;
      for (Index g : c.nodes) {
        const Index i = node(c, g), r = block + i;
        if (i < 0 || (active && !(*active)[r]))
          continue;
        const auto n = c.direction.head(d);
        auto xi = x.row(r);
        const RowChange delta = -xi.dot(n) * n.transpose();
        xi += delta;
        changed(r, delta);
      }
    }
    for (const auto& c : conditions) {
      if ((!c.value && !c.wall_state) || skips(c))
        continue;
      for (Index g : c.nodes) {
        const Index i = node(c, g), r = block + i;
        if (i < 0 || (active && !(*active)[r]))
          continue;
        const double w = weight(r);
        if (w == 0)
          continue;
        const double vb = c.value_at(t, grid.node_position(i));
        if (!std::isfinite(vb))
          throw NumericalError("condition '" + c.label + "' gives " + number_text(vb) +
                               " at node " + std::to_string(g) + " at t = " + number_text(t));
        const RowChange delta = (w * vb) * c.direction.head(d).transpose();
        x.row(r) += delta;
        changed(r, delta);
      }
    }
  }
}
} // namespace

void BoundaryConditions::constrain_momentum(const Grid& grid, const Eigen::VectorXd& m, double t,
                                            Field& p) const {
  set_components(
      conditions, grid, t, p, nullptr, [&](Index i) { return m[i]; }, [](Index, const auto&) {});
}

void BoundaryConditions::constrain_update(const Grid& grid, const Eigen::VectorXd& m, double t,
                                          double dt, Field& p_plus, Field& f) const {
  // Δp = (m v_b − p⁺·n̂) n̂ and the reaction f^(BC) = Δp / Δt.
  set_components(
      conditions, grid, t, p_plus, nullptr, [&](Index i) { return m[i]; },
      [&](Index i, const auto& delta) { f.row(i) += delta / dt; });
}

void BoundaryConditions::constrain_velocity(const Grid& grid, double t, Field& v,
                                            const Mask* active) const {
  set_components(
      conditions, grid, t, v, active, [](Index) { return 1.0; }, [](Index, const auto&) {});
}

void BoundaryConditions::zero_directions(const Grid& grid, Field& v) const {
  set_components(
      conditions, grid, 0.0, v, nullptr, [](Index) { return 0.0; }, [](Index, const auto&) {});
}

void BoundaryConditions::check_one_condition_per_node() const {
  pairs_.clear();
  for (size_t k = 0; k < conditions.size(); ++k)
    for (Index node : conditions[k].nodes)
      pairs_.emplace_back(node, Index(k));
  std::sort(pairs_.begin(), pairs_.end());
  for (size_t k = 1; k < pairs_.size(); ++k)
    if (pairs_[k].first == pairs_[k - 1].first)
      throw InputError("node " + std::to_string(pairs_[k].first) + " is held by both '" +
                       conditions[size_t(pairs_[k - 1].second)].label + "' and '" +
                       conditions[size_t(pairs_[k].second)].label +
                       "' (a node takes one temperature condition)");
}

WallState MovingWall::at(double t) const {
  const WallState s{position(t), velocity ? velocity(t) : 0.0, gradient ? gradient(t) : 0.0};
  const std::pair<const char*, double> values[] = {
      {"position", s.position}, {"velocity", s.velocity}, {"gradient", s.gradient}};
  for (const auto& [name, value] : values)
    if (!std::isfinite(value))
      throw NumericalError(label + "." + name + " is " + number_text(value) +
                           " at t = " + number_text(t) + " (the moving wall needs finite values)");
  return s;
}

namespace {
// FMPM 2026 §3.1: the wall constrains the nodes with s_i ≥ s_w − d.
bool wall_selects(const WallState& s, const MovingWall& w, const Eigen::Vector3d& x,
                  double tolerance) {
  return x.dot(w.normal) >= s.position - w.depth - tolerance; // beyond, or inside within d
}
} // namespace

double MovingWall::value_at(double t, const Eigen::Vector3d& x) const {
  return at(t).value(normal, x);
}

bool MovingWall::selects(double t, const Eigen::Vector3d& x, double tolerance) const {
  return wall_selects(at(t), *this, x, tolerance);
}

void BoundaryConditions::add_wall(const MovingWall& wall) {
  SMPM_VERIFY(wall.position, "add_wall: a wall needs its position s_w(t)");
  walls.push_back(wall);
  VelocityCondition c;
  c.direction = wall.normal;
  c.label = wall.label;
  c.wall = int(walls.size()) - 1;
  c.value = [w = wall](double t, const Eigen::Vector3d& x) { return w.value_at(t, x); };
  conditions.push_back(std::move(c));
}

void BoundaryConditions::append(const BoundaryConditions& other) {
  const int offset = int(walls.size());
  walls.insert(walls.end(), other.walls.begin(), other.walls.end());
  for (VelocityCondition c : other.conditions) {
    if (c.wall >= 0)
      c.wall += offset;
    conditions.push_back(std::move(c));
  }
}

namespace {
// The nodes of `grid` with mass in some velocity field that the wall constrains at time t, as
// nodes of the whole grid.
void wall_nodes(const MovingWall& w, const WallState& state, const Grid& grid, const Mask& active,
                std::vector<Index>& nodes) {
  const double tol = 1e-9 * grid.min_cell_size();
  nodes.clear(); // keeps its capacity: no allocation once the wall's reach is settled
  const Index ng = grid.num_nodes();
  for (Index i = 0; i < ng; ++i) {
    bool mass = false; // node i has mass in some velocity field
    for (Index r = i; r < active.size() && !mass; r += ng)
      mass = active[r];
    if (mass && wall_selects(state, w, grid.node_position(i), tol))
      nodes.push_back(grid.whole_node(i));
  }
}
} // namespace

void BoundaryConditions::select_wall_nodes(const Grid& grid, const Mask& active, double t) {
  if (walls.empty())
    return;
  for (VelocityCondition& c : conditions)
    if (c.wall >= 0) {
      const MovingWall& w = walls[size_t(c.wall)];
      wall_nodes(w, w.at(t), grid, active, c.nodes);
    }
  check_superposition();
}

void BoundaryConditions::step_conditions(const Grid& grid, const Mask& active, double t,
                                         BoundaryConditions& step) const {
  step.walls.clear();
  step.conditions.resize(conditions.size());
  for (size_t k = 0; k < conditions.size(); ++k) {
    const VelocityCondition& c = conditions[k];
    VelocityCondition& s = step.conditions[k];
    s.direction = c.direction;
    s.label = c.label;
    s.field = c.field;
    s.wall = -1;
    s.value = nullptr;
    s.wall_state.reset();
    if (c.wall >= 0) {
      const MovingWall& w = walls[size_t(c.wall)];
      s.wall_state = w.at(t);
      wall_nodes(w, *s.wall_state, grid, active, s.nodes);
    } else {
      s.nodes = c.nodes;
      if (c.value) // a pointer in the closure: no allocation, no copy of an expression
        s.value = [f = &c.value](double time, const Eigen::Vector3d& x) { return (*f)(time, x); };
    }
  }
  step.check_superposition();
}

void BoundaryConditions::check_superposition() const {
  // The (node, condition) pairs sorted by node, then by condition: every condition on a node
  // against the node's first (storage proportional to the constrained nodes, not the grid).
  pairs_.clear();
  for (size_t b = 0; b < conditions.size(); ++b)
    for (Index i : conditions[b].nodes)
      pairs_.emplace_back(i, Index(b));
  std::sort(pairs_.begin(), pairs_.end());
  for (size_t k = 1, first = 0; k < pairs_.size(); ++k) {
    if (pairs_[k].first != pairs_[first].first) {
      first = k;
      continue;
    }
    const VelocityCondition &a = conditions[size_t(pairs_[first].second)],
                            &b = conditions[size_t(pairs_[k].second)];
    const double cosine = std::abs(a.direction.dot(b.direction));
    if (cosine > 1e-9 && std::abs(cosine - 1) > 1e-9)
      throw InputError("node " + std::to_string(pairs_[k].first) + " has velocity conditions '" +
                       a.label + "' and '" + b.label +
                       "' at an angle: superposed BCs must be parallel or perpendicular "
                       "(FMPM 2026 Table 2)");
  }
}

bool BoundaryConditions::driven() const {
  for (const auto& c : conditions)
    if (c.value || c.wall >= 0 || c.wall_state)
      return true;
  return false;
}

namespace {
// The node indices q (in the whole grid, within the grid's own range along `axis`) whose
// coordinate x_q = origin + q h passes `inside`: a contiguous range, found from the bounds
// [lo, hi] of the coordinate (the predicate decides at the ends, as it would on every node).
template <class Inside>
std::pair<int, int> index_range(const Grid& grid, int axis, double lo, double hi, Inside&& inside) {
  const int first = grid.first_node(axis), last = first + grid.nodes(axis) - 1;
  if (!std::isfinite(lo) || !std::isfinite(hi))
    return {first, first - 1}; // no node
  const double o = grid.origin(axis), h = grid.cell_size(axis);
  const double qlo = std::floor((lo - o) / h) - 1, qhi = std::ceil((hi - o) / h) + 1;
  int a = int(std::clamp(qlo, double(first), double(last) + 1));
  int b = int(std::clamp(qhi, double(first) - 1, double(last)));
  while (a <= b && !inside(o + h * a))
    ++a;
  while (b >= a && !inside(o + h * b))
    --b;
  return {a, b};
}

// The nodes of the box of index ranges r (inclusive), in increasing node order.
std::vector<Index> nodes_of(const Grid& grid, const std::array<std::pair<int, int>, 3>& r) {
  std::vector<Index> nodes;
  for (int a = 0; a < 3; ++a)
    if (r[size_t(a)].first > r[size_t(a)].second)
      return nodes;
  nodes.reserve(size_t(r[0].second - r[0].first + 1) * size_t(r[1].second - r[1].first + 1) *
                size_t(r[2].second - r[2].first + 1));
  for (int k = r[2].first; k <= r[2].second; ++k)
    for (int j = r[1].first; j <= r[1].second; ++j)
      for (int i = r[0].first; i <= r[0].second; ++i)
        nodes.push_back(grid.node_index(i, j, k));
  return nodes;
}

// The whole range of the grid's nodes along axis a.
std::pair<int, int> all_of(const Grid& grid, int a) {
  return {grid.first_node(a), grid.first_node(a) + grid.nodes(a) - 1};
}
} // namespace

std::vector<Index> nodes_on_plane(const Grid& grid, int axis, double at) {
  if (axis < 0 || axis >= grid.dim())
    throw InputError("boundary plane axis " + std::to_string(axis) + " is not an axis of a " +
                     std::to_string(grid.dim()) + "D grid");
  // The nodes within 10⁻⁹ of a cell of the plane, found by their index along the axis: a plane
  // costs its own nodes, not a scan of the grid's (3,000 planes on 10⁶ nodes took 26 s).
  const double tol = 1e-9 * grid.cell_size(axis);
  std::array<std::pair<int, int>, 3> r{all_of(grid, 0), all_of(grid, 1), all_of(grid, 2)};
  r[size_t(axis)] =
      index_range(grid, axis, at, at, [&](double x) { return std::abs(x - at) <= tol; });
  std::vector<Index> nodes = nodes_of(grid, r);
  if (nodes.empty())
    throw InputError("boundary plane at " + number_text(at) + " on axis " + std::to_string(axis) +
                     " contains no grid node");
  return nodes;
}

std::vector<Index> nodes_in_box(const Grid& grid, const std::array<double, 3>& lo,
                                const std::array<double, 3>& hi) {
  std::array<std::pair<int, int>, 3> r{all_of(grid, 0), all_of(grid, 1), all_of(grid, 2)};
  for (int a = 0; a < grid.dim(); ++a) {
    const double tol = 1e-9 * grid.cell_size(a);
    r[size_t(a)] = index_range(grid, a, lo[size_t(a)], hi[size_t(a)], [&](double x) {
      return x >= lo[size_t(a)] - tol && x <= hi[size_t(a)] + tol;
    });
  }
  std::vector<Index> nodes = nodes_of(grid, r);
  if (nodes.empty())
    throw InputError("boundary box contains no grid node");
  return nodes;
}

namespace {
Index add_fixed(const Grid& grid, const std::vector<Index>& nodes, const std::array<bool, 3>& dirs,
                BoundaryConditions& bc) {
  for (int a = 0; a < grid.dim(); ++a)
    if (dirs[a]) {
      VelocityCondition c;
      c.nodes = nodes;
      c.direction = Eigen::Vector3d::Unit(a);
      c.label = std::string("fixed ") + "xyz"[a];
      bc.conditions.push_back(std::move(c));
    }
  return Index(nodes.size());
}
} // namespace

Index fix_plane(const Grid& grid, int axis, double at, const std::array<bool, 3>& dirs,
                BoundaryConditions& bc) {
  return add_fixed(grid, nodes_on_plane(grid, axis, at), dirs, bc);
}

Index fix_box(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
              const std::array<bool, 3>& dirs, BoundaryConditions& bc) {
  return add_fixed(grid, nodes_in_box(grid, lo, hi), dirs, bc);
}

} // namespace smpm
