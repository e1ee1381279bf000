// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The checks of the stability and spectrum options, before any work: the library's limits
// (validate of step_options.hpp) in the words of the command line, "--option value: reason";
// and the cells of their tables.

#include <sparsempm/errors.hpp>
#include <sparsempm/step_options.hpp>

#include <charconv>
#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace smpm::app {

/// Most entries of a list option.
inline constexpr size_t kMaxList = 1000;
/// The largest FMPM order and blending period the commands take (each order is a spectral
/// search over k passes; the library's own cap, kMaxFmpmOrder, is higher).
inline constexpr int kMaxListedOrder = 10000;

/// Whether all of `text` is a finite number (std::from_chars; an optional leading '+'), and
/// that number in `v`.
template <class T>
bool parse_all(const std::string& text, T& v) {
  const char* first = text.data() + (text.rfind('+', 0) == 0 ? 1 : 0);
  const char* last = text.data() + text.size();
  if (first != text.data() && first != last && *first == '-') // "+-5"
    return false;
  const auto [end, ec] = std::from_chars(first, last, v);
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(v))
      return false;
  return ec == std::errc() && end == last && first != last;
}
/// `text` as the value of `option`, or InputError "<option> <text>: expected <expected>".
template <class T = double>
T parse_value(const std::string& option, const std::string& text, const std::string& expected) {
  T v{};
  if (!parse_all(text, v))
    throw InputError(option + " " + clip(text) + ": expected " + expected);
  return v;
}

/// A value as a table cell shows it: `precision` significant digits, NaN empty.
inline std::string cell(double v, int precision = 4) {
  if (std::isnan(v))
    return "";
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

/// A value as a message shows it (a table cell leaves NaN empty).
inline std::string shown(double v) {
  if (std::isnan(v))
    return "nan";
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

/// Applies `set` to default FMPM options and validates them as the library does: an option the
/// library refuses is refused as "<flag> <value>: <reason>".
template <class Set>
void check_fmpm_option(const std::string& flag, const std::string& value, Set&& set) {
  StepOptions o;
  set(o.fmpm, o);
  try {
    validate(o);
  } catch (const OptionError& e) {
    throw InputError(flag + " " + value + ": " + e.reason());
  }
}

inline void check_int(const std::string& option, int value, int lo, int hi) {
  if (value < lo || value > hi)
    throw InputError(option + " " + std::to_string(value) + ": must lie in [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]");
}
inline void check_fraction(const std::string& option, double value) {
  if (!(value >= 0 && value <= 1))
    throw InputError(option + " " + shown(value) + ": must lie in [0, 1]");
}
template <class T>
void check_list(const std::string& option, const std::vector<T>& values) {
  if (values.empty() || values.size() > kMaxList)
    throw InputError(option + ": give 1 to " + std::to_string(kMaxList) + " values");
}

/// --order, --blend-alpha and --blend-every, each value by the library's limits (orders and
/// periods up to kMaxListedOrder).
inline void check_fmpm_lists(const std::vector<int>& orders, const std::vector<double>& alphas,
                             const std::vector<int>& every) {
  check_list("--order", orders);
  for (int k : orders)
    check_int("--order", k, 1, kMaxListedOrder);
  check_list("--blend-alpha", alphas);
  for (double a : alphas)
    check_fmpm_option("--blend-alpha", shown(a), [a](FmpmOptions& f, auto&) { f.blend_alpha = a; });
  check_list("--blend-every", every);
  for (int m : every)
    check_int("--blend-every", m, 1, kMaxListedOrder);
}

} // namespace smpm::app
