// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file interrupt.hpp
/// Ctrl-C in a long computation that runs with the GIL released (advance, the stability
/// searches): Python's own handler only sets a flag that no Python code reads until the
/// computation returns. While a SigintScope lives on Python's main thread, SIGINT sets the
/// library's interrupt flag instead (errors.hpp: checked between steps and between evaluations
/// of ρ(T)), and the Interrupted that follows becomes what Python's handler raises
/// (KeyboardInterrupt by default).

#include <sparsempm/errors.hpp>

#include <pybind11/pybind11.h>

#include <atomic>
#include <csignal>

namespace smpm::python {

class SigintScope {
public:
  /// With the GIL held. Takes SIGINT over only on the main thread and while Python handles it
  /// (not when SIGINT is ignored or left to the system's default).
  SigintScope();
  /// With the GIL held: gives SIGINT back to Python; a SIGINT that arrived after the
  /// computation's last check is passed on to Python, so it is not lost.
  ~SigintScope();
  SigintScope(const SigintScope&) = delete;
  SigintScope& operator=(const SigintScope&) = delete;

  /// The flag for the library (null when the scope did not take SIGINT over).
  const std::atomic<int>* flag() const;
  /// After Interrupted, with the GIL held: gives SIGINT back to Python, runs its handler and
  /// throws what it raises (KeyboardInterrupt when it raises nothing).
  [[noreturn]] void raise();

private:
  void restore();
  bool active_ = false;
  struct sigaction previous_ {};
};

/// f(flag) with the GIL released and Ctrl-C stopping it (SigintScope).
template <class F>
auto interruptible(F&& f) {
  SigintScope scope;
  try {
    pybind11::gil_scoped_release release;
    return f(scope.flag());
  } catch (const Interrupted&) {
    scope.raise();
  }
}

} // namespace smpm::python
