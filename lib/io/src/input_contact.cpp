// SPDX-License-Identifier: BSD-3-Clause
// [[contact]] tables: the velocity fields of the materials and the contact laws between them
// (contact 2020 §2–3; FMPM 2026 §3.2).

#include "reader.hpp"

#include <numeric>

namespace smpm::detail {

namespace {

int material_index(const Reader& r, const toml::node* n, const std::string& key,
                   const std::string& name, const std::vector<Material>& mats) {
  for (size_t m = 0; m < mats.size(); ++m)
    if (mats[m].name == name)
      return int(m);
  std::string known;
  for (const Material& m : mats)
    known += (known.empty() ? "" : ", ") + m.name;
  r.fail(n, key, "no [[material]] named '" + clip(name) + "' (materials: " + known + ")");
}

// The two materials of a table; {−1, −1} when it has none (the law of every other pair).
std::array<int, 2> table_materials(const Reader& r, const toml::table& t, const std::string& key,
                                   const std::vector<Material>& mats) {
  const toml::node* n = t.get("materials");
  if (!n)
    return {-1, -1};
  const toml::array* a = n->as_array();
  if (!a || a->size() != 2 || !(*a)[0].is_string() || !(*a)[1].is_string())
    r.fail(n, key + "materials", "expected two material names");
  const std::array<int, 2> m{
      material_index(r, n, key + "materials", *(*a)[0].value<std::string>(), mats),
      material_index(r, n, key + "materials", *(*a)[1].value<std::string>(), mats)};
  if (m[0] == m[1])
    r.fail(n, key + "materials", "a material is not in contact with itself");
  return m;
}

// The normal of a table: AG, LR, or a specified direction from the first material to the second.
void read_normal(const Reader& r, const toml::table& t, const std::string& key, int dim,
                 bool has_materials, ContactPair& p) {
  p.normal = r.choice(t, "normal", key + "normal", std::string(to_string(p.normal)),
                      &contact_normal_from_string); // default: ContactPair's (LR)
  if (p.normal != ContactNormal::Specified) {
    if (t.get("direction"))
      r.fail(t.get("direction"), key + "direction",
             "only normal = \"specified\" takes a direction");
    return;
  }
  if (!has_materials)
    r.fail(t.get("normal"), key + "normal",
           "a specified normal needs `materials` (it points from the first to the second)");
  p.direction = r.unit_vector(t, "direction", key + "direction", dim);
}

// The detection of a table and the parameters that belong to it (CP: δ_c; DF: the fit).
void read_detection(const Reader& r, const toml::table& t, const std::string& key, ContactPair& p) {
  p.detection = r.choice(t, "detection", key + "detection", std::string(to_string(p.detection)),
                         &contact_detection_from_string); // default: ContactPair's (LR)
  if (p.detection == ContactDetection::Position) {
    p.critical_separation = r.number(t, "critical_separation", key + "critical_separation", 0.8);
    // δ_c compares (x_i^β − x_i^α)·n̂, the separation of the materials' positions extrapolated
    // to a node, within the few cells of the node's support: beyond 4 cells every node would
    // be in contact. Contact 2020 §2.2 uses 0.8 to 0.96.
    if (!(p.critical_separation >= 0 && p.critical_separation <= 4))
      r.fail(t.get("critical_separation"), key + "critical_separation",
             "must be in [0, 4] cells (contact 2020 uses 0.8 to 0.96)");
  } else if (t.get("critical_separation"))
    r.fail(t.get("critical_separation"), key + "critical_separation",
           "only detection = \"CP\" takes a critical separation");
  if (p.detection != ContactDetection::DistanceFunction) {
    for (const char* k : {"df_exponent", "df_reach"})
      if (t.get(k))
        r.fail(t.get(k), key + k, "only detection = \"DF\" takes the distance-function fit");
    return;
  }
  p.df_exponent = r.number(t, "df_exponent", key + "df_exponent", p.df_exponent);
  if (!(p.df_exponent > 0 && p.df_exponent <= 10))
    r.fail(t.get("df_exponent"), key + "df_exponent", "must be in (0, 10]");
  p.df_reach = r.number(t, "df_reach", key + "df_reach", p.df_reach);
  if (!(p.df_reach > 0 && p.df_reach <= 10))
    r.fail(t.get("df_reach"), key + "df_reach", "must be in (0, 10] cells");
}

ContactPair read_law(const Reader& r, const toml::table& t, const std::string& key, int dim,
                     bool has_materials) {
  ContactPair p;
  try {
    p.law = contact_law_from_string(r.string(t, "law", key + "law", std::nullopt));
  } catch (const InputError& e) {
    r.fail(t.get("law"), key + "law",
           std::string(e.what()) + "; or single-field (one velocity field, a perfect interface)");
  }
  if (p.law == ContactLaw::Coulomb) {
    p.friction = r.number(t, "friction", key + "friction", std::nullopt);
    if (!(p.friction >= 0))
      r.fail(t.get("friction"), key + "friction", "must be non-negative");
  } else if (t.get("friction")) {
    r.fail(t.get("friction"), key + "friction", "only the coulomb law has a friction coefficient");
  }
  read_normal(r, t, key, dim, has_materials, p);
  read_detection(r, t, key, p);
  p.fmpm_method =
      r.choice(t, "fmpm_method", key + "fmpm_method", "net", &contact_fmpm_method_from_string);
  return p;
}

int root_of(std::vector<int>& parent, int m) {
  while (parent[size_t(m)] != m)
    m = parent[size_t(m)] = parent[size_t(parent[size_t(m)])];
  return m;
}

} // namespace

namespace {

bool single_field(const Reader& r, const toml::table& t, const std::string& key) {
  return r.string(t, "law", key + "law", std::nullopt) == "single-field";
}

// The velocity field of each material: its own, merged by the single-field tables.
std::vector<int> material_fields(const Reader& r, const std::vector<const toml::table*>& tables,
                                 const std::vector<Material>& mats) {
  std::vector<int> parent(mats.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t k = 0; k < tables.size(); ++k) {
    const toml::table& t = *tables[k];
    const std::string key = "contact." + std::to_string(k) + ".";
    r.check_keys(t, "contact");
    if (!single_field(r, t, key))
      continue;
    const auto m = table_materials(r, t, key, mats);
    if (m[0] < 0)
      r.fail(t.get("law"), key + "law", "single-field needs `materials`");
    parent[size_t(root_of(parent, m[0]))] = root_of(parent, m[1]);
  }
  std::vector<int> field_of_root(mats.size(), -1), field(mats.size());
  int fields = 0;
  for (size_t m = 0; m < mats.size(); ++m) {
    int& f = field_of_root[size_t(root_of(parent, int(m)))];
    if (f < 0)
      f = fields++;
    field[m] = f;
  }
  return field;
}

// Every pair of fields needs a law when no table is the law of every other pair.
void check_every_pair(const Reader& r, const Contact& c, const std::vector<Material>& mats,
                      const std::vector<std::vector<std::string>>& pair_key) {
  for (size_t m1 = 0; m1 < mats.size(); ++m1)
    for (size_t m2 = m1 + 1; m2 < mats.size(); ++m2) {
      const int a = std::min(c.material_field[m1], c.material_field[m2]);
      const int b = std::max(c.material_field[m1], c.material_field[m2]);
      if (a != b && pair_key[size_t(a)][size_t(b)].empty())
        throw InputError(r.where(nullptr, "[[contact]]") + ": materials '" + mats[m1].name +
                         "' and '" + mats[m2].name +
                         "' are in different velocity fields without a contact law (add a "
                         "[[contact]] table for them, or one without `materials` for every "
                         "other pair)");
    }
}

} // namespace

Contact read_contact(const Reader& r, const toml::table& root, const std::vector<Material>& mats,
                     int dim) {
  Contact c;
  const auto tables = r.tables(root, "contact", false);
  if (tables.empty())
    return c; // single material mode
  if (mats.size() > size_t(kMaxMaterials))
    r.fail(nullptr, "[[contact]]",
           std::to_string(mats.size()) + " materials, more than the " +
               std::to_string(kMaxMaterials) + " a model takes");
  c.material_field = material_fields(r, tables, mats);
  const size_t fields = size_t(c.fields());
  std::vector<std::vector<std::string>> pair_key(fields, std::vector<std::string>(fields));
  for (size_t k = 0; k < tables.size(); ++k) {
    const toml::table& t = *tables[k];
    const std::string key = "contact." + std::to_string(k) + ".";
    if (single_field(r, t, key))
      continue;
    const auto m = table_materials(r, t, key, mats);
    ContactPair p = read_law(r, t, key, dim, m[0] >= 0);
    if (m[0] < 0) {
      if (c.has_fallback)
        r.fail(t.get("law"), key + "law", "a second [[contact]] table without `materials`");
      c.has_fallback = true;
      c.fallback = p;
      continue;
    }
    int a = c.material_field[size_t(m[0])], b = c.material_field[size_t(m[1])];
    if (a == b)
      r.fail(t.get("materials"), key + "materials",
             "'" + mats[size_t(m[0])].name + "' and '" + mats[size_t(m[1])].name +
                 "' share a velocity field (single-field): they cannot have a contact law");
    if (a > b) { // stored from the lower field; a specified normal turns with it
      std::swap(a, b);
      p.direction = -p.direction;
    }
    std::string& seen = pair_key[size_t(a)][size_t(b)];
    if (!seen.empty())
      r.fail(t.get("materials"), key + "materials",
             "these velocity fields already have a law in " + seen);
    seen = key.substr(0, key.size() - 1);
    p.first = a;
    p.second = b;
    c.pairs.push_back(p);
  }
  if (!c.has_fallback)
    check_every_pair(r, c, mats, pair_key);
  return c;
}

} // namespace smpm::detail
