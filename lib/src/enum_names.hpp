// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The one idiom of the library's enum names (internal): a table of (value, name, description)
// next to each to_string, read both ways. The names are those of the input files; a parse
// failure lists every name of the table, with its description when it has one.

#include "sparsempm/errors.hpp"

#include <array>
#include <string>
#include <string_view>

namespace smpm::detail {

/// One enum value, its name in the input files and an optional description for messages.
template <class E>
struct EnumName {
  E value;
  std::string_view name;
  std::string_view description = {};
};

template <class E, size_t N>
using EnumNames = std::array<EnumName<E>, N>;

/// The name of `value` in `table` ("?" for a value the table lacks).
template <class E, size_t N>
constexpr std::string_view enum_name(E value, const EnumNames<E, N>& table) {
  for (const EnumName<E>& e : table)
    if (e.value == value)
      return e.name;
  return "?";
}

/// The value named `name`; throws InputError "unknown <what> '<name>' (expected a | b (…) | …)".
template <class E, size_t N>
E parse_enum(std::string_view name, const EnumNames<E, N>& table, std::string_view what) {
  for (const EnumName<E>& e : table)
    if (e.name == name)
      return e.value;
  std::string expected;
  for (const EnumName<E>& e : table) {
    expected += (expected.empty() ? "" : " | ") + std::string(e.name);
    if (!e.description.empty())
      expected += " (" + std::string(e.description) + ")";
  }
  throw InputError("unknown " + std::string(what) + " '" + clip(name) + "' (expected " + expected +
                   ")");
}

} // namespace smpm::detail
