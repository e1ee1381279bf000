// SPDX-License-Identifier: BSD-3-Clause
#include "parts.hpp"

#include "sparsempm/errors.hpp"

#include <deque>
#include <iterator>
#include <string>

namespace smpm {

namespace {
// The parts a program added (register_step_part), after the library's own.
std::deque<StepPartEntry>& added_parts() {
  static std::deque<StepPartEntry> added;
  return added;
}

std::vector<ParticleColumn>& columns_of_parts() {
  static std::vector<ParticleColumn> columns = [] {
    std::vector<ParticleColumn> all;
    for (const parts::Entry* entry : parts::kList)
      all.insert(all.end(), entry->columns.begin(), entry->columns.end());
    return all;
  }();
  return columns;
}
} // namespace

std::vector<const StepPartEntry*> step_part_entries() {
  std::vector<const StepPartEntry*> entries(std::begin(parts::kList), std::end(parts::kList));
  for (const StepPartEntry& entry : added_parts())
    entries.push_back(&entry);
  return entries;
}

std::vector<std::unique_ptr<StepPart>> step_parts(const StepOptions& options) {
  std::vector<std::unique_ptr<StepPart>> list;
  for (const StepPartEntry* entry : step_part_entries())
    if (std::unique_ptr<StepPart> part = entry->make(options))
      list.push_back(std::move(part));
  return list;
}

std::vector<const PartSeries*> part_series(const StepOptions& options) {
  std::vector<const PartSeries*> series;
  for (const StepPartEntry* entry : step_part_entries())
    if (!entry->series.empty() && entry->make(options))
      for (const PartSeries& s : entry->series)
        series.push_back(&s);
  return series;
}

const std::vector<ParticleColumn>& particle_columns() {
  return columns_of_parts();
}

void register_step_part(const StepPartEntry& entry) {
  if (!entry.make)
    throw UsageError("register_step_part: the part has no maker");
  for (const PartSeries& s : entry.series) {
    if (!s.value)
      throw UsageError("register_step_part: series " + std::string(s.name) + " has no value");
    for (const StepPartEntry* other : step_part_entries())
      for (const PartSeries& o : other->series)
        if (o.name == s.name)
          throw UsageError("register_step_part: a part already has a series named " +
                           std::string(s.name));
  }
  std::vector<ParticleColumn>& columns = columns_of_parts();
  for (const ParticleColumn& c : entry.columns) {
    if (c.vector || c.field)
      throw UsageError("register_step_part: column " + std::string(c.name) +
                       " is a member of Particles; a program's part keeps its columns in "
                       "Particles::columns");
    for (const ParticleColumn& other : columns)
      if (other.name == c.name)
        throw UsageError("register_step_part: a part already has a column named " +
                         std::string(c.name));
  }
  columns.insert(columns.end(), entry.columns.begin(), entry.columns.end());
  added_parts().push_back(entry); // a deque: the entries step_part_entries gave stay valid
}

} // namespace smpm
