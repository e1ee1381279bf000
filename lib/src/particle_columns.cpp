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

bool has_column(const Particles& P, const ParticleColumn& c) {
  if (c.vector)
    return (P.*c.vector).size() == P.size();
  const Field& f = P.*c.field;
  return f.rows() == P.size() && f.cols() == column_width(c, P.dim);
}

Eigen::Map<Field> column_values(Particles& P, const ParticleColumn& c) {
  SMPM_VERIFY(has_column(P, c), "column_values: the particles have no " + std::string(c.name));
  if (c.vector)
    return {(P.*c.vector).data(), P.size(), 1};
  return {(P.*c.field).data(), P.size(), column_width(c, P.dim)};
}

Eigen::Map<const Field> column_values(const Particles& P, const ParticleColumn& c) {
  SMPM_VERIFY(has_column(P, c), "column_values: the particles have no " + std::string(c.name));
  if (c.vector)
    return {(P.*c.vector).data(), P.size(), 1};
  return {(P.*c.field).data(), P.size(), column_width(c, P.dim)};
}

void set_column(Particles& P, const ParticleColumn& c, const Eigen::Ref<const Field>& values) {
  const Index w = column_width(c, P.dim);
  SMPM_VERIFY(values.cols() == w, "set_column: " + std::string(c.name) + " takes " +
                                      std::to_string(w) + " values per particle");
  if (c.vector)
    P.*c.vector = values.col(0);
  else
    P.*c.field = values;
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
  else
    (P.*c.field).resize(0, 0);
}

} // namespace smpm
