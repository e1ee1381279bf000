#include "sparsempm/threads.hpp"

#include "sparsempm/errors.hpp"

#include <omp.h>

#include <atomic>
#include <cstdlib>
#include <string>

namespace smpm {

namespace {
constexpr int kMaxThreads = 4096;
std::atomic<Index> g_threshold{1024};
} // namespace

int threads() {
  return omp_get_max_threads();
}

void set_threads(int count) {
  if (count < 1 || count > kMaxThreads)
    throw InputError("the number of threads must lie in [1, " + std::to_string(kMaxThreads) +
                     "], got " + std::to_string(count));
  omp_set_num_threads(count);
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
