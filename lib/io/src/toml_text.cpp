// SPDX-License-Identifier: BSD-3-Clause
#include "toml_text.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/input.hpp"

#include <algorithm>
#include <optional>
#include <regex>
#include <sstream>

namespace smpm::detail {

// Valid keys of every table of the schema ("" is the top level): the keys of input_keys(), the
// one list of them, which the input reference prints.
const std::map<std::string, std::vector<std::string>>& schema() {
  static const std::map<std::string, std::vector<std::string>> keys = [] {
    std::map<std::string, std::vector<std::string>> by_table;
    for (const InputKey& k : input_keys())
      by_table[k.table].push_back(k.key);
    return by_table;
  }();
  return keys;
}

// toml++ 3.3 reaches undefined behaviour (an unreachable branch in
// is_non_ascii_horizontal_whitespace) when a non-ASCII character stands where it tests for
// whitespace: after a bare value, between tokens, after a backslash in a string (found by
// tests/fuzz). Non-ASCII text is therefore accepted only where its role is unambiguous, and
// rejected with its line everywhere else:
//   - in a comment line (first non-blank character '#'),
//   - in a trailing comment ' # ...' after an ASCII part without quotes,
//   - in the string of a line  key = "text"  or  key = 'text'  (no backslash, no inner quote),
// and nowhere in a file with multi-line strings.
void check_non_ascii(const std::string& text, const std::string& source) {
  static const std::regex string_line(
      R"re(^[ \t]*[A-Za-z0-9_.-]+[ \t]*=[ \t]*("[^"\\]*"|'[^']*')[ \t]*(#.*)?$)re");
  const bool multi_line_strings =
      text.find("\"\"\"") != std::string::npos || text.find("'''") != std::string::npos;
  auto ascii = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(),
                       [](char c) { return static_cast<unsigned char>(c) < 0x80; });
  };
  std::istringstream in(text);
  long number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (ascii(line))
      continue;
    const size_t first = line.find_first_not_of(" \t");
    bool allowed = false;
    if (!multi_line_strings) {
      if (first != std::string::npos && line[first] == '#') {
        allowed = true; // a comment line
      } else if (std::regex_match(line, string_line)) {
        allowed = true; // key = "text" [# comment]
      } else {
        const size_t hash = line.find('#');
        const std::string code = line.substr(0, hash);
        allowed = hash != std::string::npos && hash > 0 &&
                  (line[hash - 1] == ' ' || line[hash - 1] == '\t') &&
                  code.find_first_of("\"'") == std::string::npos && ascii(code);
      }
    }
    if (!allowed)
      throw InputError(source + ":" + std::to_string(number) +
                       (multi_line_strings
                            ? ": non-ASCII characters cannot be used in a file with multi-line "
                              "strings"
                            : ": non-ASCII characters are accepted only in comments and in "
                              "simple key = \"text\" strings"));
  }
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string suggest(const std::string& key, const std::vector<std::string>& valid,
                    const std::string& what) {
  std::string best;
  size_t dist = 1000;
  for (const auto& v : valid)
    if (const size_t e = edit_distance(key, v); e < dist) {
      dist = e;
      best = v;
    }
  if (dist <= std::max<size_t>(2, key.size() / 3))
    return " (did you mean '" + best + "'?)";
  std::string list;
  for (const auto& v : valid)
    list += (list.empty() ? "" : ", ") + v;
  return " (" + what + ": " + list + ")";
}

namespace {
// Parses a --set value as a TOML value, or keeps it as a string.
void assign(toml::table& t, const std::string& key, const std::string& value) {
  check_non_ascii("v = " + value, "--set " + key);
  try {
    toml::table v = toml::parse("v = " + value, std::string_view("--set"));
    toml::node* n = v.get("v");
    if (n->is_integer())
      t.insert_or_assign(key, *n->value<int64_t>());
    else if (n->is_floating_point())
      t.insert_or_assign(key, *n->value<double>());
    else if (n->is_boolean())
      t.insert_or_assign(key, *n->value<bool>());
    else if (n->is_string())
      t.insert_or_assign(key, *n->value<std::string>());
    else if (n->is_array())
      t.insert_or_assign(key, *n->as_array());
    else if (n->is_table())
      t.insert_or_assign(key, *n->as_table());
    else
      t.insert_or_assign(key, value);
  } catch (const toml::parse_error&) {
    t.insert_or_assign(key, value);
  }
}

} // namespace

std::string current_key_path(const std::string& path) {
  std::string p = path.rfind("scheme.", 0) == 0 ? "step." + path.substr(7) : path;
  return p == "step.update" ? "step.scheme" : p;
}

std::vector<std::string> apply_aliases(toml::table& root, const std::string& source) {
  std::vector<std::string> notes;
  // Moves root[from] (or table[from]) to `to`, refusing both spellings at once.
  auto rename = [&](toml::table& t, const char* from, const char* to, const std::string& old_name,
                    const std::string& new_name) {
    toml::node* n = t.get(from);
    if (!n)
      return;
    if (t.get(to)) {
      const auto line = n->source().begin.line;
      throw InputError(source + ":" + std::to_string(line) + ": " + old_name +
                       " is the earlier name of " + new_name + ": give one of them");
    }
    // A move keeps the source lines of the node and of everything in it (a copy would not).
    std::move(*n).visit([&](auto&& v) { t.insert_or_assign(to, std::move(v)); });
    t.erase(from);
    notes.push_back(source + ": " + old_name + " is now " + new_name +
                    " (the earlier name is accepted in this release only)");
  };
  rename(root, "scheme", "step", "[scheme]", "[step]");
  if (toml::table* step = root.get_as<toml::table>("step")) {
    rename(*step, "update", "scheme", "step.update", "step.scheme");
    // step.xpic_contact_term = true | false: the closed form with or without contact 2020
    // Eq. (37)'s term, now step.xpic_contact = "term" | "none".
    if (const toml::node* n = step->get("xpic_contact_term")) {
      const auto line = std::to_string(n->source().begin.line);
      if (step->get("xpic_contact"))
        throw InputError(source + ":" + line + ": step.xpic_contact_term is the earlier name " +
                         "of step.xpic_contact: give one of them");
      const std::optional<bool> on = n->value<bool>();
      if (!on)
        throw InputError(source + ":" + line + ": step.xpic_contact_term: expected true or " +
                         "false (it is now step.xpic_contact = \"term\" | \"none\")");
      step->insert_or_assign("xpic_contact", *on ? "term" : "none");
      step->erase("xpic_contact_term");
      notes.push_back(source + ": step.xpic_contact_term = " + (*on ? "true" : "false") +
                      " is now step.xpic_contact = \"" + (*on ? "term" : "none") +
                      "\" (the earlier name is accepted in this release only)");
    }
  }
  return notes;
}

namespace {

// The entry of an array of tables an override names ("material.bar.youngs", "bc.0.wall.depth"):
// the table by name or index, or its inline table; `section` receives the schema section.
toml::table* listed_target(toml::node* sec, const std::vector<std::string>& parts,
                           const std::string& spec, std::string& section,
                           const std::string& prefix = "") {
  if (parts.size() != 3 && parts.size() != 4)
    throw InputError("--set " + clip(spec) + ": [[" + parts[0] + "]] entries are addressed as " +
                     parts[0] + ".<name or index>.key=value (or .table.key=value)");
  toml::table* target = nullptr;
  if (toml::array* arr = sec ? sec->as_array() : nullptr)
    for (size_t k = 0; k < arr->size() && !target; ++k) {
      toml::table* t = (*arr)[k].as_table();
      const auto name = t ? t->get("name") : nullptr;
      if (t && ((name && name->value<std::string>() == parts[1]) || std::to_string(k) == parts[1]))
        target = t;
    }
  if (!target)
    throw InputError("--set " + clip(spec) + ": no [[" + parts[0] + "]] named or numbered '" +
                     parts[1] + "'");
  if (parts.size() == 3)
    return target;
  section = prefix + parts[0] + "." + parts[2]; // a key of an inline table of the entry
  toml::node* sub = target->get(parts[2]);
  if (!schema().count(section) || !sub || !sub->as_table())
    throw InputError("--set " + clip(spec) + ": [[" + parts[0] + "]] " + parts[1] +
                     " has no table '" + parts[2] + "'");
  return sub->as_table();
}

// The table of a plain section an override names ("time.end"), made when absent.
toml::table* section_target(toml::table& root, toml::node* sec,
                            const std::vector<std::string>& parts, const std::string& spec) {
  if (parts.size() != 2)
    throw InputError("--set " + clip(spec) + ": expected " + parts[0] + ".key=value");
  if (!sec)
    sec = &root.insert_or_assign(parts[0], toml::table{}).first->second;
  toml::table* target = sec->as_table();
  if (!target)
    throw InputError("--set " + clip(spec) + ": '" + parts[0] + "' is not a table");
  return target;
}

} // namespace

std::string apply_override(toml::table& root, const std::string& spec) {
  for (const char c : spec)
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f)
      throw InputError("--set " + clip(spec) +
                       ": contains a control character (a newline?); values are one line");
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set " + clip(spec) + ": expected section.key=value");
  const std::string given = spec.substr(0, eq), value = spec.substr(eq + 1);
  if (current_key_path(given) == "step.xpic_contact_term") { // its earlier name and values
    if (value != "true" && value != "false")
      throw InputError("--set " + clip(spec) + ": expected true or false (it is now " +
                       "step.xpic_contact = \"term\" | \"none\")");
    const std::string now = value == "true" ? "\"term\"" : "\"none\"";
    apply_override(root, "step.xpic_contact=" + now);
    return "--set " + given + "=" + value + " is now --set step.xpic_contact=" + now +
           " (the earlier name is accepted in this release only)";
  }
  const std::string path = current_key_path(given);
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');)
    parts.push_back(part);
  const auto& top = schema().at("");
  // [[loads.traction]] and [[loads.body_force]] entries: loads.traction.<index>.key=value.
  const bool listed_load = parts.size() >= 3 && parts[0] == "loads" &&
                           (parts[1] == "traction" || parts[1] == "body_force");
  if (!listed_load && (parts.size() < 2 || parts.size() > 4 ||
                       std::find(top.begin(), top.end(), parts[0]) == top.end()))
    throw InputError("--set " + clip(spec) + ": expected section.key=value with a section of " +
                     "grid, material, body, bc, contact, time, step, output, loads" +
                     (parts.empty() ? "" : suggest(parts[0], top)));
  toml::table* target = nullptr;
  std::string section = parts[0]; // the schema section of the key set
  if (listed_load) {
    toml::node* loads = root.get("loads");
    toml::table* lt = loads ? loads->as_table() : nullptr;
    const std::vector<std::string> sub(parts.begin() + 1, parts.end());
    section = "loads." + sub[0];
    target = listed_target(lt ? lt->get(sub[0]) : nullptr, sub, spec, section, "loads.");
  } else {
    toml::node* sec = root.get(parts[0]);
    const bool listed =
        parts[0] == "material" || parts[0] == "body" || parts[0] == "bc" || parts[0] == "contact";
    target =
        listed ? listed_target(sec, parts, spec, section) : section_target(root, sec, parts, spec);
  }
  const std::string& key = parts.back();
  const auto& valid = schema().at(section);
  if (std::find(valid.begin(), valid.end(), key) == valid.end())
    throw InputError("--set " + clip(spec) + ": unknown key '" + section + "." + key + "'" +
                     suggest(key, valid));
  assign(*target, key, value);
  return path == given ? std::string()
                       : "--set " + given + " is now --set " + path +
                             " (the earlier name is accepted in this release only)";
}

} // namespace smpm::detail
