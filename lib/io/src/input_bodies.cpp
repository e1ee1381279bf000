// SPDX-License-Identifier: BSD-3-Clause
// The [[body]] tables: the particles of each region (box, disk, ellipse, image) on the lattice of
// ppc per cell, with their material, velocities and temperatures. Conditions: input_conditions.cpp.
#include "expression.hpp"
#include "png_image.hpp"
#include "reader.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <memory>

namespace smpm::detail {

namespace {

// A body's particles and the region they fill: a point of a later body that lies in it is the
// earlier body's (NairnMPM's MPMReadHandler::MPMPts: a particle position an earlier body filled
// is not filled again).
struct Region {
  Particles particles;
  std::function<bool(const double* x)> contains;
};

// The particles `keep` of a lattice `box`, of material `id`.
Particles subset(const Particles& box, const std::vector<Index>& keep, int id) {
  Particles P;
  P.resize(box.dim, Index(keep.size()));
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
  return subset(box, keep, id);
}

// The index of the body's material, by name.
int body_material(const Reader& r, const toml::table& t, const std::string& key,
                  const std::vector<Material>& mats) {
  const std::string mname = r.string(t, "material", key + "material", std::nullopt);
  std::vector<std::string> names;
  for (size_t k = 0; k < mats.size(); ++k) {
    if (mats[k].name == mname)
      return int(k);
    names.push_back(mats[k].name);
  }
  r.fail(t.get("material"), key + "material",
         "no such material" + suggest(mname, names, "materials"));
}

// The particles of a body's region: box | disk | ellipse, on the lattice of ppc per cell.
// Refuses a body whose bounding lattice [lo, hi] (ppc per cell) would hold more particles than
// this build accepts, before any is made.
void check_particle_count(const Reader& r, const toml::table& t, const std::string& key,
                          const Grid& g, const std::array<int, 3>& ppc,
                          const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  double estimate = 1;
  for (int a = 0; a < g.dim(); ++a)
    estimate *= (std::ceil((hi[a] - lo[a]) / g.cell_size(a)) + 1.0) * ppc[a];
  if (estimate > kMaxParticles)
    r.fail(t.get("ppc"), key + "ppc",
           "up to " + std::to_string(long(estimate)) + " particles, more than the " +
               std::to_string(long(kMaxParticles)) + " this build accepts");
}

// The file of an image body: a path relative to the input file's directory; a stored input (a
// restart) tries its input file's first.
std::filesystem::path image_path(const Reader& r, const toml::table& t, const std::string& key) {
  const std::string file = r.string(t, "image", key + "image", std::nullopt);
  std::filesystem::path path(file);
  if (!path.is_relative())
    return path;
  std::vector<std::filesystem::path> dirs(r.file_directories().begin(), r.file_directories().end());
  if (t.source().path && !t.source().path->empty())
    dirs.push_back(std::filesystem::path(*t.source().path).parent_path());
  std::error_code ec;
  const auto holds = std::find_if(dirs.begin(), dirs.end(), [&](const auto& dir) {
    return std::filesystem::exists(dir / path, ec);
  });
  if (holds != dirs.end())
    path = *holds / path;
  else if (!dirs.empty()) // named in the message
    path = dirs.back() / path;
  return path;
}

// The grey levels of an image body's pixels, levels = [lo, hi] (inclusive; default [0, 127]).
std::array<double, 3> image_levels(const Reader& r, const toml::table& t, const std::string& key) {
  std::array<double, 3> levels{0, 127, 0};
  if (t.get("levels")) {
    levels = r.vector(t, "levels", key + "levels", 2, true);
    if (!(levels[0] >= 0 && levels[1] <= 255 && levels[0] <= levels[1]))
      r.fail(t.get("levels"), key + "levels", "expected [lo, hi] with 0 <= lo <= hi <= 255");
  }
  return levels;
}

// The pixels of the image at `path`; check_size sees its size, from the file's header, before
// any pixel is read.
GreyImage read_image(const Reader& r, const toml::table& t, const std::string& key,
                     const std::filesystem::path& path,
                     const std::function<void(int width, int height)>& check_size) {
  if (!std::filesystem::is_regular_file(path))
    r.fail(t.get("image"), key + "image",
           "cannot read " + path.string() +
               (std::filesystem::exists(path) ? ": not a regular file (a directory, FIFO or device)"
                                              : ": no such file"));
  try {
    return read_grey_png(path.string(), check_size);
  } catch (const InputError&) {
    throw; // check_size's
  } catch (const std::runtime_error& e) {
    r.fail(t.get("image"), key + "image", "cannot read " + path.string() + ": " + e.what());
  }
}

// The lattice corners [cell_lo, cell_hi] of the grid cells that [lo, hi] covers.
void covering_cells(const Grid& g, const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                    std::array<double, 3>& cell_lo, std::array<double, 3>& cell_hi) {
  for (int a = 0; a < g.dim(); ++a) {
    const double h = g.cell_size(a);
    cell_lo[a] = g.origin(a) + h * std::floor((lo[a] - g.origin(a)) / h);
    cell_hi[a] = g.origin(a) + h * std::ceil((hi[a] - g.origin(a)) / h);
  }
}

// A bitmap body (NairnMPM's BMPRegion): region = "image", image = "file.png" (a path relative
// to the input file), pixel_size (length units per pixel, square pixels), origin (the image's
// lower-left corner; default the grid's origin) and levels = [lo, hi] (the grey levels 0–255 of
// the body's pixels, inclusive; default [0, 127], the dark half). The particles are those of
// the lattice of ppc per cell over the image whose point lies in a pixel of the body; each
// [[body]] reading the same image with other levels and material makes a multimaterial map.
// 2D only; pixel row 0 is the image's top row.
Region image_region(const Reader& r, const toml::table& t, const std::string& key, const Grid& g,
                    const std::array<int, 3>& ppc, double density, int id) {
  const int d = g.dim();
  if (d != 2)
    r.fail(t.get("region"), key + "region", "an image body needs a 2D grid");
  const std::filesystem::path path = image_path(r, t, key);
  const double s = r.positive(t, "pixel_size", key + "pixel_size", std::nullopt);
  const auto origin =
      r.vector(t, "origin", key + "origin", d, false, {g.origin(0), g.origin(1), 0});
  if (!g.contains(origin))
    r.fail(t.get("origin"), key + "origin", "the image's lower-left corner is outside the grid");
  const std::array<double, 3> levels = image_levels(r, t, key);
  const std::array<double, 3> lo{origin[0], origin[1], 0};
  std::array<double, 3> hi{0, 0, 0};
  // Its size, from the file's header, checked before any pixel is read: it must fit in the grid
  // from the origin, span the grid's lattice and hold at most kMaxImagePixels pixels.
  auto check_size = [&](int width, int height) {
    hi = {origin[0] + s * width, origin[1] + s * height, 0};
    const std::string size = std::to_string(width) + " x " + std::to_string(height) + " pixels";
    if (double(width) * double(height) > kMaxImagePixels)
      r.fail(t.get("image"), key + "image",
             path.string() + " claims " + size + ", more than the " +
                 std::to_string(long(kMaxImagePixels)) + " pixels an image body may have");
    for (int a = 0; a < d; ++a)
      if (!(hi[a] > lo[a]))
        r.fail(t.get("pixel_size"), key + "pixel_size",
               "the image (" + size + ") of pixel_size = " + number_text(s) +
                   " has no extent beside its origin");
    if (!g.contains(hi))
      r.fail(t.get("image"), key + "image",
             "the image (" + size + " of pixel_size = " + number_text(s) + " from the origin (" +
                 number_text(lo[0]) + ", " + number_text(lo[1]) + ")) reaches (" +
                 number_text(hi[0]) + ", " + number_text(hi[1]) + "), outside the grid");
  };
  GreyImage image = read_image(r, t, key, path, check_size);
  // The lattice over the cells the image covers.
  std::array<double, 3> cell_lo{0, 0, 0}, cell_hi{0, 0, 0};
  covering_cells(g, lo, hi, cell_lo, cell_hi);
  check_particle_count(r, t, key, g, ppc, cell_lo, cell_hi);
  Particles box = make_block(g, cell_lo, cell_hi, ppc, density, id);
  // A point is the body's where it lies in a pixel of its levels.
  auto shared = std::make_shared<const GreyImage>(std::move(image));
  auto contains = [shared, lo, hi, s, levels](const double* x) {
    const double u = (x[0] - lo[0]) / s, v = (hi[1] - x[1]) / s;
    if (!(u >= 0 && u < shared->width && v >= 0 && v < shared->height))
      return false;
    const int level = shared->at(int(u), int(v));
    return level >= levels[0] && level <= levels[1];
  };
  std::vector<Index> keep;
  for (Index p = 0; p < box.size(); ++p)
    if (contains(box.X.row(p).data()))
      keep.push_back(p);
  return {subset(box, keep, id), contains};
}

Region body_region(const Reader& r, const toml::table& t, const std::string& key, const Grid& g,
                   const std::array<int, 3>& ppc, double density, int id) {
  const int d = g.dim();
  const std::string region = r.string(t, "region", key + "region", "box");
  if (region == "image")
    return image_region(r, t, key, g, ppc, density, id);
  if (region == "box") {
    const auto lo = r.vector(t, "min", key + "min", d, true);
    const auto hi = r.vector(t, "max", key + "max", d, true);
    for (int a = 0; a < d; ++a)
      if (!(hi[a] > lo[a]))
        r.fail(t.get("max"), key + "max", "must exceed min on every axis");
    if (!g.contains(lo) || !g.contains(hi))
      r.fail(t.get("max"), key + "min/max", "particles outside the grid");
    check_particle_count(r, t, key, g, ppc, lo, hi);
    auto contains = [lo, hi, d](const double* x) {
      for (int a = 0; a < d; ++a)
        if (!(x[a] >= lo[a] && x[a] <= hi[a]))
          return false;
      return true;
    };
    return {make_block(g, lo, hi, ppc, density, id), contains};
  }
  if (region != "disk" && region != "ellipse")
    r.fail(t.get("region"), key + "region",
           "unknown region (expected box | disk | ellipse | image)");
  const auto c = r.vector(t, "center", key + "center", d, true);
  std::array<double, 3> semi{1, 1, 1};
  if (region == "disk") {
    const double rad = r.positive(t, "radius", key + "radius", std::nullopt);
    semi = {rad, rad, rad};
  } else {
    semi = r.vector(t, "semi_axes", key + "semi_axes", d, true);
    for (int a = 0; a < d; ++a)
      if (!(semi[a] > 0))
        r.fail(t.get("semi_axes"), key + "semi_axes", "must be positive");
  }
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  for (int a = 0; a < d; ++a) {
    lo[a] = c[a] - semi[a];
    hi[a] = c[a] + semi[a];
  }
  if (!g.contains(lo) || !g.contains(hi))
    r.fail(t.get("center"), key + "center", "particles outside the grid");
  check_particle_count(r, t, key, g, ppc, lo, hi);
  auto contains = [c, semi, d](const double* x) {
    double r2 = 0;
    for (int a = 0; a < d; ++a) {
      const double u = (x[a] - c[a]) / semi[a];
      r2 += u * u;
    }
    return r2 <= 1;
  };
  return {lattice_in(g, c, semi, ppc, density, id), contains};
}

// Initial velocity: numbers or expressions of the initial position X, Y, Z.
void body_velocity(const Reader& r, const toml::table& t, const std::string& key, Particles& P) {
  const toml::node* vn = t.get("velocity");
  if (!vn)
    return;
  const int d = P.dim;
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
    const Expression expr(*e.value<std::string>(), {"X", "Y", "Z"}, r.where(vn, key + "velocity"));
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

// Heat transport: temperature (a number or an expression of X, Y, Z; default the material's
// reference temperature) and heat_source (power per unit mass, a number; default none).
void body_heat(const Reader& r, const toml::table& t, const std::string& key, const Material& mat,
               Particles& P) {
  P.temperature.setConstant(P.size(), mat.reference_temperature);
  if (const toml::node* n = t.get("temperature")) {
    if (auto num = n->value<double>(); num && !n->is_string()) {
      P.temperature.setConstant(*num);
    } else if (n->is_string()) {
      const Expression expr(*n->value<std::string>(), {"X", "Y", "Z"},
                            r.where(n, key + "temperature"));
      for (Index p = 0; p < P.size(); ++p) {
        double x[3] = {0, 0, 0};
        for (int b = 0; b < P.dim; ++b)
          x[b] = P.X(p, b);
        P.temperature[p] = expr(x);
      }
    } else {
      r.fail(n, key + "temperature", "expected a number or an expression of X, Y, Z");
    }
    for (Index p = 0; p < P.size(); ++p)
      if (!(P.temperature[p] > 0) || !std::isfinite(P.temperature[p]))
        r.fail(n, key + "temperature",
               "is " + number_text(P.temperature[p]) + " at particle " + std::to_string(p) +
                   " (temperatures are absolute: positive and finite)");
  }
  if (t.get("heat_source"))
    P.heat_source.setConstant(P.size(),
                              r.number(t, "heat_source", key + "heat_source", std::nullopt));
}

} // namespace

Particles read_bodies(const Reader& r, const toml::table& root, const Grid& g,
                      const std::vector<Material>& mats, std::vector<BodyRange>* ranges) {
  const int d = g.dim();
  Particles all;
  all.resize(d, 0);
  int index = 0;
  std::vector<std::function<bool(const double*)>> claimed; // the regions of the bodies before
  for (const toml::table* t : r.tables(root, "body", true)) {
    r.check_keys(*t, "body");
    const std::string key = "body." + std::to_string(index++) + ".";
    const int id = body_material(r, *t, key, mats);
    const auto ppc = r.counts(*t, "ppc", key + "ppc", d);
    Region region = body_region(r, *t, key, g, ppc, mats[size_t(id)].density, id);
    if (region.particles.size() == 0)
      r.fail(t->get("region"), key + "region", "holds no particle");
    // Overlapping bodies: a point belongs to the first body whose region holds it (NairnMPM's
    // rule), so that no place has the mass of two bodies.
    std::vector<Index> keep;
    for (Index p = 0; p < region.particles.size(); ++p) {
      const double* x = region.particles.X.row(p).data();
      if (std::none_of(claimed.begin(), claimed.end(), [&](const auto& in) { return in(x); }))
        keep.push_back(p);
    }
    Particles P = Index(keep.size()) == region.particles.size()
                      ? std::move(region.particles)
                      : subset(region.particles, keep, id);
    if (P.size() == 0)
      r.fail(t->get("region"), key + "region",
             "holds no particle that an earlier [[body]] does not already fill (a point belongs "
             "to the first body whose region holds it)");
    claimed.push_back(std::move(region.contains));
    if (mats[size_t(id)].model == MaterialModel::Rigid && t->get("velocity"))
      r.fail(t->get("velocity"), key + "velocity",
             "a rigid body moves with its material's velocity (material." + mats[size_t(id)].name +
                 ".velocity)");
    body_velocity(r, *t, key, P);
    body_heat(r, *t, key, mats[size_t(id)], P);
    const std::string name = t->get("name") ? r.string(*t, "name", key + "name", "") : "";
    if (ranges) {
      for (const BodyRange& b : *ranges)
        if (!name.empty() && b.name == name)
          r.fail(t->get("name"), key + "name", "another body has this name");
      ranges->push_back({name, all.size(), P.size()});
    }
    all.append(P);
  }
  return all;
}

} // namespace smpm::detail
