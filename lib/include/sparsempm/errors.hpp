// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file errors.hpp
/// The two kinds of failure a user can act on: bad input and numerical failure.

#include <atomic>
#include <stdexcept>
#include <string>
#include <string_view>

namespace smpm {

/// Thrown for input a user must correct (bad parameters, an inconsistent set-up).
/// The message names the offending key or argument and its value.
class InputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// An InputError about one option of the library's option structs (StepOptions, FmpmOptions,
/// ExactOptions): key() names it as the input files and Python do ("order", "blend_alpha",
/// "periodic_cx", ...) and reason() says what is wrong with its value, so that an input reader
/// can point at the line that set it. what() is "<key> = <value>: <reason>".
class OptionError : public InputError {
public:
  /// The error of option `key` set to `value` (as text), `reason` saying what is wrong.
  OptionError(std::string key, const std::string& value, std::string reason);
  /// The option's name as input files and Python spell it ("order", "blend_alpha", ...).
  const std::string& key() const { return key_; }
  /// What is wrong with the value (the message without "<key> = <value>: ").
  const std::string& reason() const { return reason_; }

private:
  std::string key_, reason_;
};

/// Thrown when a computation fails numerically (NaN, det F ≤ 0, a particle leaving
/// the grid). The message names the particle or node; `step` is the time step
/// number when known (−1 otherwise).
class NumericalError : public std::runtime_error {
public:
  /// The failure `what` at time step `step` (−1: not known).
  explicit NumericalError(const std::string& what, long step = -1);
  /// The time step number at which it happened, −1 when not known.
  long step() const { return step_; }

private:
  long step_;
};

/// Thrown by the collective calls of a step across processes (NodeSums) on every process but
/// the one whose step failed (NodeSums::fail): every process stops at the same step, and only
/// the one that failed holds the message naming the particle or node.
class FailedElsewhere : public NumericalError {
public:
  using NumericalError::NumericalError;
};

/// `text` as quoted in a one-line message: control characters written as `\n`, `\t` or `\xNN`
/// and at most `max` characters, followed by the full length when cut.
std::string clip(std::string_view text, size_t max = 80);

/// A number as a message shows it (ostream's default format: 6 significant digits).
std::string number_text(double value);

/// Prefixes a NumericalError's message with the step and time at which it happened.
NumericalError at_step(const NumericalError& e, long step, double time);

/// Thrown when a signal asked a long computation to stop at its next safe point: a run between
/// steps (RunOptions, AdvanceOptions), the stability searches between evaluations of ρ(T). Their
/// `interrupt` flag is an atomic a signal handler sets to the signal's number (0: none).
class Interrupted : public std::runtime_error {
public:
  /// Stopped by the signal number `signal`; `what` says by which signal and where.
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  /// The number of the signal that asked to stop (SIGINT, SIGTERM).
  int signal() const { return signal_; }

private:
  int signal_;
};

/// "SIGINT", "SIGTERM" or "a signal".
const char* signal_name(int signal);

/// Throws Interrupted ("interrupted by SIGINT <where>") when `flag` is set; `where` is called
/// only then (it says where the computation stopped).
template <class Where>
void check_interrupt(const std::atomic<int>* flag, Where&& where) {
  if (!flag)
    return;
  if (const int s = flag->load(std::memory_order_relaxed); s != 0)
    throw Interrupted(s, std::string("interrupted by ") + signal_name(s) + " " + where());
}

/// Thrown when the library is called wrongly by a program (mismatched sizes, a missing
/// solver): a defect of the calling code, not of the user's input. Always checked.
class UsageError : public std::logic_error {
public:
  using std::logic_error::logic_error;
};

namespace detail {
/// What SMPM_VERIFY calls when its condition fails: throws UsageError with `message`, the
/// failed `condition` and its source location `file`:`line`.
[[noreturn]] void usage_failure(const char* condition, const std::string& message, const char* file,
                                int line);
} // namespace detail

} // namespace smpm

/// Always-on check of a library precondition (MFEM_VERIFY style): throws smpm::UsageError
/// naming the condition, the message and the source location when `cond` is false.
#define SMPM_VERIFY(cond, message)                                                                 \
  do {                                                                                             \
    if (!(cond))                                                                                   \
      ::smpm::detail::usage_failure(#cond, (message), __FILE__, __LINE__);                         \
  } while (false)
