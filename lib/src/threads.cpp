// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/threads.hpp"

#include "sparsempm/errors.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif
#if defined(__linux__)
#include <sched.h>
#endif

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <string>
#include <vector>

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

bool unbind_initial_thread() noexcept {
#if defined(_OPENMP)
  if (omp_get_proc_bind() == omp_proc_bind_false || omp_get_num_places() == 0)
    return true; // nothing was bound
#if defined(__linux__)
  try {
    // The CPUs of every place: libgomp built the places from the process's CPUs at load time
    // (GOMP_CPU_AFFINITY's from its list, as libgomp itself would use them), before it bound
    // this thread to the first place.
    std::vector<int> cpus;
    for (int place = 0; place < omp_get_num_places(); ++place) {
      std::vector<int> ids(size_t(omp_get_place_num_procs(place)));
      omp_get_place_proc_ids(place, ids.data());
      cpus.insert(cpus.end(), ids.begin(), ids.end());
    }
    int largest = -1;
    for (int id : cpus)
      largest = std::max(largest, id);
    if (largest < 0)
      return false;
    cpu_set_t* set = CPU_ALLOC(largest + 1);
    if (!set)
      return false;
    const size_t size = CPU_ALLOC_SIZE(largest + 1);
    CPU_ZERO_S(size, set);
    for (int id : cpus)
      if (id >= 0)
        CPU_SET_S(id, size, set);
    const bool done = sched_setaffinity(0, size, set) == 0;
    CPU_FREE(set);
    return done;
  } catch (...) { // out of memory
    return false;
  }
#else
  return false;
#endif
#else
  return true;
#endif
}

Index parallel_threshold() {
  return g_threshold.load(std::memory_order_relaxed);
}

void set_parallel_threshold(Index rows) {
  SMPM_VERIFY(rows >= 0, "set_parallel_threshold: rows must be non-negative");
  g_threshold.store(rows, std::memory_order_relaxed);
}

} // namespace smpm
