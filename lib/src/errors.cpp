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

} // namespace smpm
