// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Text-level helpers of the input reader: the schema of valid keys, key suggestions, the
// non-ASCII check that keeps toml++ 3.3 away from undefined behaviour, and --set overrides.

#include "sparsempm/input.hpp"

#include <toml++/toml.h>

#include <map>
#include <string>
#include <vector>

namespace smpm::detail {

/// The keys of [time], [step], [output] and the loads: the second half of input_keys().
std::vector<InputKey> run_input_keys();
/// Valid keys of every table of the input schema ("" is the top level).
const std::map<std::string, std::vector<std::string>>& schema();
/// " (did you mean 'x'?)" for the nearest valid key, or the list of valid keys.
std::string suggest(const std::string& key, const std::vector<std::string>& valid,
                    const std::string& what = "valid keys");
/// Throws InputError naming the line of a non-ASCII character outside the places where its
/// role is unambiguous (see toml_text.cpp).
void check_non_ascii(const std::string& text, const std::string& source);
/// The earlier vocabulary, accepted for one release: the table [scheme] is [step] and its key
/// `update` is `scheme`. Renames them in `root` (InputError naming the line when both spellings
/// are present) and returns a note for each rename.
std::vector<std::string> apply_aliases(toml::table& root, const std::string& source);
/// An override's section.key in the current vocabulary ("scheme.x" is "step.x", "step.update"
/// is "step.scheme").
std::string current_key_path(const std::string& path);
/// Applies one "section.key=value" override (value as a TOML value, else a string; arrays of
/// tables addressed by name or index). Throws InputError naming the override; control
/// characters (a newline that would later change the stored input) are refused. Returns a note
/// when the override used an earlier name (current_key_path), else an empty string.
std::string apply_override(toml::table& root, const std::string& spec);

} // namespace smpm::detail
