// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/threads.hpp"

#include "sparsempm/errors.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif

#include <atomic>
#include <cstdlib>
#include <string>

namespace smpm {

namespace {
constexpr int kMaxThreads = 4096;
std::atomic<Index> g_threshold{1024};
} // namespace

int threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1; // built without OpenMP (the clang fuzz target): every kernel is serial
#endif
}

void set_threads(int count) {
  if (count < 1 || count > kMaxThreads)
    throw InputError("the number of threads must lie in [1, " + std::to_string(kMaxThreads) +
                     "], got " + std::to_string(count));
#if defined(_OPENMP)
  omp_set_num_threads(count);
#endif
}

int threads_from_environment() {
  const char* value = std::getenv("SMPM_THREADS");
  if (!value)
    return threads();
  const std::string text(value);
  const bool digits = !text.empty() && text.size() <= 4 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  const int count = digits ? std::stoi(text) : 0;
  if (count < 1 || count > kMaxThreads)
    throw InputError("SMPM_THREADS='" + clip(text) + "': expected a positive integer (at most " +
                     std::to_string(kMaxThreads) + "), the number of threads");
  set_threads(count);
  return count;
}

Index parallel_threshold() {
  return g_threshold.load(std::memory_order_relaxed);
}

void set_parallel_threshold(Index rows) {
  SMPM_VERIFY(rows >= 0, "set_parallel_threshold: rows must be non-negative");
  g_threshold.store(rows, std::memory_order_relaxed);
}

} // namespace smpm
