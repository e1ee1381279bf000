// SPDX-License-Identifier: BSD-3-Clause
#include "parts.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <atomic>
#include <deque>
#include <iterator>
#include <string>

namespace smpm {

namespace {
// Set by the first read of the list: register_step_part refuses after it.
std::atomic<bool> sealed{false};

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

std::vector<const StepPartEntry*> entries_of_parts() {
  std::vector<const StepPartEntry*> entries(std::begin(parts::kList), std::end(parts::kList));
  for (const StepPartEntry& entry : added_parts())
    entries.push_back(&entry);
  return entries;
}

// Particles' own names, in frames (X ... material, J, xyz) and in Python (dim, volume, jacobian).
constexpr std::string_view kParticleNames[] = {
    "X",           "V",        "F", "stress", "mass", "volume0", "volume",
    "half_length", "material", "J", "xyz",    "dim",  "jacobian"};
} // namespace

std::vector<const StepPartEntry*> step_part_entries() {
  sealed = true;
  return entries_of_parts();
}

std::vector<std::unique_ptr<StepPart>> step_parts(const StepOptions& options) {
  std::vector<std::unique_ptr<StepPart>> list;
  for (const StepPartEntry* entry : step_part_entries())
    if (std::unique_ptr<StepPart> part = entry->make(options))
      list.push_back(std::move(part));
  return list;
}

void check_distributed(const std::vector<std::unique_ptr<StepPart>>& parts, const Model& model,
                       std::string_view step) {
  for (const std::unique_ptr<StepPart>& part : parts)
    if (const std::string why = part->not_distributed(model); !why.empty())
      throw InputError(std::string(step) + " across processes does not take " + why + " yet");
}

std::vector<const StepPartEntry*> series_parts(const StepOptions& options) {
  std::vector<const StepPartEntry*> entries;
  for (const StepPartEntry* entry : step_part_entries())
    if (!entry->series.empty() && entry->make(options))
      entries.push_back(entry);
  return entries;
}

const std::vector<ParticleColumn>& particle_columns() {
  sealed = true;
  return columns_of_parts();
}

void register_step_part(const StepPartEntry& entry) {
  auto refuse = [](const std::string& why) { throw UsageError("register_step_part: " + why); };
  if (sealed)
    refuse("the list of parts was read already (register parts before any Stepper, run, layout "
           "or particle set is made)");
  if (!entry.make)
    refuse("the part has no maker");
  const std::vector<ParticleColumn>& columns = columns_of_parts();
  for (size_t k = 0; k < entry.columns.size(); ++k) {
    const ParticleColumn& c = entry.columns[k];
    const std::string name(c.name);
    if (c.vector || c.field)
      refuse("column " + name +
             " is a member of Particles; a program's part keeps its columns in "
             "Particles::columns");
    const auto same = [&](const ParticleColumn& o) { return o.name == c.name; };
    if (name.empty() || std::find(std::begin(kParticleNames), std::end(kParticleNames), c.name) !=
                            std::end(kParticleNames))
      refuse("a column may not be named '" + name + "' (the particles' own)");
    if (std::any_of(columns.begin(), columns.end(), same) ||
        std::any_of(entry.columns.begin(), entry.columns.begin() + std::ptrdiff_t(k), same))
      refuse("a part already has a column named " + name);
  }
  const std::vector<const StepPartEntry*> entries = entries_of_parts();
  if (!entry.series.empty() && !entry.series_values)
    refuse("the part has series but no series_values");
  for (size_t k = 0; k < entry.series.size(); ++k) {
    const PartSeries& s = entry.series[k];
    const std::string name(s.name);
    if (name.empty())
      refuse("a series has no name");
    const auto same = [&](const PartSeries& o) { return o.name == s.name; };
    bool taken = std::any_of(entry.series.begin(), entry.series.begin() + std::ptrdiff_t(k), same);
    for (const StepPartEntry* other : entries)
      taken = taken || std::any_of(other->series.begin(), other->series.end(), same);
    if (taken)
      refuse("a part already has a series named " + name);
  }
  columns_of_parts().insert(columns_of_parts().end(), entry.columns.begin(), entry.columns.end());
  added_parts().push_back(entry); // a deque: the entries step_part_entries gave stay valid
}

} // namespace smpm
