// SPDX-License-Identifier: BSD-3-Clause
// The [[material]] tables: each material's model, density and the constants of its model
// (elastic, Mie–Grüneisen, rigid), with its heat and J2 plasticity properties.
#include "reader.hpp"

#include <cmath>
#include <optional>
#include <set>

namespace smpm::detail {

namespace {

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

// J2 plasticity (plasticity.hpp): yield_stress and hardening, for hyperelastic and
// mie-gruneisen only.
void read_plastic_properties(const Reader& r, const toml::table& t, const std::string& key,
                             Material& m) {
  m.yield_stress = r.number(t, "yield_stress", key + "yield_stress", 0.0);
  m.hardening = r.number(t, "hardening", key + "hardening", 0.0);
  for (const char* k : {"yield_stress", "hardening"})
    if (t.get(k) && m.model != MaterialModel::Hyperelastic &&
        m.model != MaterialModel::MieGruneisen)
      r.fail(t.get(k), key + k, "only the hyperelastic and mie-gruneisen models take it");
  if (!(m.yield_stress >= 0))
    r.fail(t.get("yield_stress"), key + "yield_stress", "must be non-negative (0: elastic)");
  if (!(m.hardening >= 0))
    r.fail(t.get("hardening"), key + "hardening", "must be non-negative");
  if (t.get("hardening") && !(m.yield_stress > 0))
    r.fail(t.get("hardening"), key + "hardening", "needs a yield_stress");
}

// E > 0 and −1 < ν < ½ of the elastic models, with a finite wave speed.
void read_elastic_constants(const Reader& r, const toml::table& t, const std::string& key,
                            Material& m) {
  for (const char* k : {"bulk", "shear", "gruneisen", "s1", "viscosity"})
    if (t.get(k))
      r.fail(t.get(k), key + k, "only model = \"mie-gruneisen\" takes it");
  m.youngs = r.positive(t, "youngs", key + "youngs", std::nullopt);
  m.poisson = r.number(t, "poisson", key + "poisson", 0.0);
  if (!(m.poisson > -1 && m.poisson < 0.5))
    r.fail(t.get("poisson"), key + "poisson", "must lie in (-1, 0.5)");
  if (!std::isfinite(m.wave_speed(1)) || !std::isfinite(m.wave_speed(3)))
    r.fail(t.get("youngs"), key + "youngs",
           "gives an infinite wave speed (the modulus over the density overflows)");
}

// One [[material]] table: its name (not among `names`, which receives it), model, density,
// heat and plasticity properties and the constants of its model.
Material read_material(const Reader& r, const toml::table& t, std::set<std::string>& names) {
  Material m;
  m.name = r.string(t, "name", "material.name", std::nullopt);
  if (!names.insert(m.name).second)
    r.fail(t.get("name"), "material.name", "duplicate material name");
  const std::string key = "material." + m.name + ".";
  const std::string model = r.string(t, "model", key + "model", "linear");
  try {
    m.model = material_model_from_string(model);
  } catch (const InputError& e) {
    r.fail(t.get("model"), key + "model", e.what());
  }
  m.density = r.positive(t, "density", key + "density", std::nullopt);
  read_heat_properties(r, t, key, m);
  read_plastic_properties(r, t, key, m);
  if (m.model == MaterialModel::Rigid) { // rigid.hpp: density, and velocity (read_rigid)
    for (const char* k : {"youngs", "poisson", "bulk", "shear", "gruneisen", "s1", "viscosity"})
      if (t.get(k))
        r.fail(t.get(k), key + k, "a rigid material does not take it");
    return m;
  }
  if (m.model == MaterialModel::MieGruneisen) {
    read_mie_gruneisen(r, t, key, m);
    if (!std::isfinite(m.wave_speed(3)))
      r.fail(t.get("bulk"), key + "bulk",
             "gives an infinite wave speed (the modulus over the density overflows)");
    return m;
  }
  read_elastic_constants(r, t, key, m);
  return m;
}

} // namespace

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
    mats.push_back(read_material(r, *t, names));
  }
  return mats;
}

} // namespace smpm::detail
