// SPDX-License-Identifier: BSD-3-Clause
// The input keys as a TOML document (smpm info --keys), written by toml++.
#include "sparsempm/input.hpp"

#include <toml++/toml.h>

#include <ostream>

namespace smpm {

void write_input_keys(std::ostream& out) {
  toml::array keys;
  for (const InputKey& k : input_keys())
    keys.push_back(toml::table{{"table", k.table},
                               {"key", k.key},
                               {"type", k.type},
                               {"fallback", k.fallback},
                               {"literal", k.literal},
                               {"values", k.values},
                               {"unit", k.unit},
                               {"description", k.description},
                               {"bad", k.bad}});
  out << toml::table{{"key", std::move(keys)}} << "\n";
}

} // namespace smpm
