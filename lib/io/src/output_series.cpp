// SPDX-License-Identifier: BSD-3-Clause
// The series of a run file (/series: one row per step, output.hpp's SeriesRow): their names
// and widths, and their rows as written into the run's files.

#include "output_format.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/step_part.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace smpm::detail {

const char* const kSeries[] = {
    "step",      "t", "kinetic", "strain", "total", "velocity_change", "velocity_change_sum",
    "fmpm_order"};
const char* const kMaterialSeries[] = {"material_mass", "material_momentum", "material_centre"};

SeriesLayout::SeriesLayout(const RunConfig& cfg)
    : dim(cfg.model.grid.dim()), materials(int(cfg.model.materials.size())),
      reactions(reaction_labels(cfg.model)) {
  const std::vector<std::pair<std::string, size_t>> own = columns(); // the run's own series
  for (const StepPartEntry* entry : series_parts(cfg.step))
    for (const PartSeries& s : entry->series) {
      if (std::any_of(own.begin(), own.end(), [&](const auto& c) { return c.first == s.name; }))
        throw UsageError("the series " + std::string(s.name) +
                         " of a part of the step is one of the run's own");
      parts.emplace_back(s.name);
    }
}

std::vector<std::pair<std::string, size_t>> SeriesLayout::columns() const {
  std::vector<std::pair<std::string, size_t>> out;
  for (const char* s : kSeries)
    out.emplace_back(s, 0);
  out.emplace_back("momentum", size_t(dim));
  for (int s = 0; s < 3; ++s) // per material: mass; momentum and centre (d each)
    out.emplace_back(kMaterialSeries[s], size_t(materials) * (s == 0 ? 1 : size_t(dim)));
  if (!reactions.empty())
    out.emplace_back("reaction", reactions.size());
  for (const std::string& s : parts)
    out.emplace_back(s, 0);
  return out;
}

std::vector<Field> series_values(const SeriesLayout& layout, const std::vector<SeriesRow>& rows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Index k = Index(rows.size());
  const int d = layout.dim;
  std::vector<Field> out;
  for (const auto& [name, width] : layout.columns())
    out.emplace_back(Field::Constant(k, Index(std::max<size_t>(width, 1)), nan));
  for (Index r = 0; r < k; ++r) {
    const SeriesRow& row = rows[size_t(r)];
    const double scalars[] = {double(row.step),
                              row.t,
                              row.e.kinetic,
                              row.e.strain,
                              row.e.total,
                              row.velocity_change,
                              row.velocity_change_sum,
                              row.fmpm_order};
    size_t c = 0;
    for (const double v : scalars)
      out[c++](r, 0) = v;
    for (int a = 0; a < d; ++a)
      out[c](r, a) = row.e.momentum[a];
    ++c;
    // material_sums lays out (mass, momentum d, centre d) per material.
    const size_t per = size_t(1 + 2 * d);
    for (int s = 0; s < 3; ++s, ++c)
      for (int m = 0; m < layout.materials && row.materials.size() >= size_t(m + 1) * per; ++m)
        for (int a = 0; a < (s == 0 ? 1 : d); ++a)
          out[c](r, m * (s == 0 ? 1 : d) + a) = row.materials[size_t(m) * per +
                                                              (s == 0   ? 0
                                                               : s == 1 ? 1
                                                                        : 1 + size_t(d)) +
                                                              size_t(a)];
    if (!layout.reactions.empty()) {
      for (size_t j = 0; j < std::min(layout.reactions.size(), row.reactions.size()); ++j)
        out[c](r, Index(j)) = row.reactions[j];
      ++c;
    }
    for (size_t s = 0; s < std::min(layout.parts.size(), row.parts.size()); ++s)
      out[c + s](r, 0) = row.parts[s];
  }
  return out;
}

namespace {
void label_reactions(hid_t series, const SeriesLayout& layout) {
  if (!layout.reactions.empty())
    h5::set_attribute(series, "reaction_conditions", layout.reactions);
}
} // namespace

void create_series_group(hid_t file, const SeriesLayout& layout, hsize_t chunk) {
  h5::Id series = h5::create_group(file, "series");
  for (const auto& [name, width] : layout.columns())
    h5::create_series(series.get(), name, hsize_t(width), chunk);
  label_reactions(series.get(), layout);
}

void append_series_rows(hid_t file, const SeriesLayout& layout,
                        const std::vector<SeriesRow>& rows) {
  if (rows.empty())
    return;
  h5::Id series = h5::open_group(file, "series");
  const std::vector<Field> values = series_values(layout, rows);
  const auto columns = layout.columns();
  for (size_t c = 0; c < columns.size(); ++c)
    h5::append_series(series.get(), columns[c].first, values[c].data(), hsize_t(rows.size()),
                      hsize_t(columns[c].second));
}

void write_series_rows(hid_t file, const SeriesLayout& layout, const std::vector<SeriesRow>& rows) {
  h5::Id series = h5::create_group(file, "series");
  const std::vector<Field> values = series_values(layout, rows);
  const auto columns = layout.columns();
  for (size_t c = 0; c < columns.size(); ++c)
    h5::write_doubles(series.get(), columns[c].first, values[c].data(), hsize_t(rows.size()),
                      hsize_t(columns[c].second));
  label_reactions(series.get(), layout);
}

} // namespace smpm::detail
