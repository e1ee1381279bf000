#pragma once
/// \file errors.hpp
/// The two kinds of failure a user can act on: bad input and numerical failure.

#include <stdexcept>
#include <string>

namespace smpm {

/// Thrown for input a user must correct (bad parameters, an inconsistent set-up).
/// The message names the offending key or argument and its value.
class InputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Thrown when a computation fails numerically (NaN, det F ≤ 0, a particle leaving
/// the grid). The message names the particle or node; `step` is the time step
/// number when known (−1 otherwise).
class NumericalError : public std::runtime_error {
public:
  explicit NumericalError(const std::string& what, long step = -1);
  long step() const { return step_; }

private:
  long step_;
};

/// Prefixes a NumericalError's message with the step and time at which it happened.
NumericalError at_step(const NumericalError& e, long step, double time);

} // namespace smpm
