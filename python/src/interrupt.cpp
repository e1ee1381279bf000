// SPDX-License-Identifier: BSD-3-Clause
#include "interrupt.hpp"

namespace smpm::python {

namespace py = pybind11;

namespace {

std::atomic<int> g_sigint{0};
int g_depth = 0; // scopes alive (changed with the GIL held)

extern "C" void on_sigint(int s) {
  g_sigint.store(s);
}

// Whether Python handles SIGINT on this thread: the main thread, with a Python handler (not
// SIG_IGN or SIG_DFL) for it.
bool python_handles_sigint() {
  const py::module_ threading = py::module_::import("threading");
  if (!threading.attr("current_thread")().is(threading.attr("main_thread")()))
    return false;
  const py::module_ signal = py::module_::import("signal");
  const py::object handler = signal.attr("getsignal")(SIGINT);
  return !handler.is_none() && !handler.equal(signal.attr("SIG_IGN")) &&
         !handler.equal(signal.attr("SIG_DFL"));
}

} // namespace

SigintScope::SigintScope() {
  if (!python_handles_sigint())
    return;
  if (g_depth == 0) // cleared before our handler can set it
    g_sigint.store(0);
  struct sigaction ours {};
  ours.sa_handler = on_sigint;
  sigemptyset(&ours.sa_mask);
  if (::sigaction(SIGINT, &ours, &previous_) != 0)
    return;
  ++g_depth;
  active_ = true;
}

void SigintScope::restore() {
  if (!active_)
    return;
  ::sigaction(SIGINT, &previous_, nullptr);
  --g_depth;
  active_ = false;
}

SigintScope::~SigintScope() {
  if (!active_)
    return;
  restore(); // first: a SIGINT from now on is Python's own
  if (g_depth == 0 && g_sigint.exchange(0) != 0)
    PyErr_SetInterrupt(); // one that came after the last check: seen at Python's next check
}

const std::atomic<int>* SigintScope::flag() const {
  return active_ ? &g_sigint : nullptr;
}

void SigintScope::raise() {
  restore();
  g_sigint.store(0); // handed to Python: no enclosing scope passes it on again
  PyErr_SetInterrupt();
  if (PyErr_CheckSignals() != 0)
    throw py::error_already_set();
  PyErr_SetNone(PyExc_KeyboardInterrupt);
  throw py::error_already_set();
}

} // namespace smpm::python
