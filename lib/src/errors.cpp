// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/errors.hpp"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <sstream>
#include <utility>

namespace smpm {

OptionError::OptionError(std::string key, const std::string& value, std::string reason)
    : InputError(key + " = " + value + ": " + reason), key_(std::move(key)),
      reason_(std::move(reason)) {}

NumericalError::NumericalError(const std::string& what, long step)
    : std::runtime_error(what), step_(step) {}

std::string clip(std::string_view text, size_t max) {
  std::string out;
  for (const char c : text.substr(0, max)) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n')
      out += "\\n";
    else if (c == '\t')
      out += "\\t";
    else if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      out += hex;
    } else
      out += c;
  }
  if (text.size() > max)
    out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

const char* signal_name(int s) {
  return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal";
}

std::string number_text(double value) {
  if (std::isnan(value))
    return "nan"; // not "-nan": the sign of a NaN means nothing to a reader
  std::ostringstream os;
  os << value;
  return os.str();
}

NumericalError at_step(const NumericalError& e, long step, double time) {
  std::ostringstream os;
  os << "step " << step << " (t = " << time << "): " << e.what();
  return NumericalError(os.str(), step);
}

namespace detail {
void usage_failure(const char* condition, const std::string& message, const char* file, int line) {
  std::ostringstream os;
  os << message << " (" << condition << " failed at " << file << ":" << line << ")";
  throw UsageError(os.str());
}
} // namespace detail

} // namespace smpm
