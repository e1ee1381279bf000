#include "sparsempm/errors.hpp"

#include <sstream>

namespace smpm {

NumericalError::NumericalError(const std::string& what, long step)
    : std::runtime_error(what), step_(step) {}

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
