// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/particle_columns.hpp"

#include "sparsempm/errors.hpp"

namespace smpm {

Index column_width(const ParticleColumn& c, int d) {
  switch (c.width) {
  case ColumnWidth::One:
    return 1;
  case ColumnWidth::Tensor:
    return Index(d) * d;
  case ColumnWidth::Nine:
    return 9;
  }
  return 1;
}

namespace {
// The Field of a column that is not a member (Particles::columns); null when P has none.
const Field* stored(const Particles& P, const ParticleColumn& c) {
  const auto it = P.columns.find(c.name);
  return it == P.columns.end() ? nullptr : &it->second;
}
} // namespace

bool has_column(const Particles& P, const ParticleColumn& c) {
  if (c.vector)
    return (P.*c.vector).size() == P.size();
  const Field* f = c.field ? &(P.*c.field) : stored(P, c);
  return f && f->rows() == P.size() && f->cols() == column_width(c, P.dim);
}

Eigen::Map<Field> column_values(Particles& P, const ParticleColumn& c) {
  SMPM_VERIFY(has_column(P, c), "column_values: the particles have no " + std::string(c.name));
  if (c.vector)
    return {(P.*c.vector).data(), P.size(), 1};
  Field& f = c.field ? P.*c.field : P.columns.find(c.name)->second;
  return {f.data(), P.size(), column_width(c, P.dim)};
}

Eigen::Map<const Field> column_values(const Particles& P, const ParticleColumn& c) {
  SMPM_VERIFY(has_column(P, c), "column_values: the particles have no " + std::string(c.name));
  if (c.vector)
    return {(P.*c.vector).data(), P.size(), 1};
  const Field& f = c.field ? P.*c.field : *stored(P, c);
  return {f.data(), P.size(), column_width(c, P.dim)};
}

void set_column(Particles& P, const ParticleColumn& c, const Eigen::Ref<const Field>& values) {
  const Index w = column_width(c, P.dim);
  SMPM_VERIFY(values.cols() == w, "set_column: " + std::string(c.name) + " takes " +
                                      std::to_string(w) + " values per particle");
  if (c.vector)
    P.*c.vector = values.col(0);
  else if (c.field)
    P.*c.field = values;
  else
    P.columns.insert_or_assign(std::string(c.name), Field(values));
}

std::pair<Index, Index> stored_shape(const Particles& P, const ParticleColumn& c) {
  if (c.vector)
    return {(P.*c.vector).size(), 1};
  const Field* f = c.field ? &(P.*c.field) : stored(P, c);
  return f ? std::pair{f->rows(), f->cols()} : std::pair<Index, Index>{0, 0};
}

void store_column(Particles& P, const ParticleColumn& c, Field values) {
  if (c.vector)
    P.*c.vector = values.col(0);
  else if (c.field)
    P.*c.field = std::move(values);
  else
    P.columns.insert_or_assign(std::string(c.name), std::move(values));
}

std::string range_message(const ParticleColumn& c) {
  const std::string why = c.range_reason.empty() ? "it must be" : std::string(c.range_reason) + ":";
  switch (c.range) {
  case ColumnRange::Positive:
    return " (" + why + " positive and finite)";
  case ColumnRange::NonNegative:
    return " (" + why + " non-negative and finite)";
  case ColumnRange::Finite:
    break;
  }
  return " (" + why + " finite)";
}

void clear_column(Particles& P, const ParticleColumn& c) {
  if (c.vector)
    (P.*c.vector).resize(0);
  else if (c.field)
    (P.*c.field).resize(0, 0);
  else if (const auto it = P.columns.find(c.name); it != P.columns.end())
    P.columns.erase(it);
}

} // namespace smpm
