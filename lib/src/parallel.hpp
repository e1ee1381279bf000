// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The OpenMP loops of the library (every parallel region is one of these). Their results do not
// depend on the number of threads: each index is computed by one thread, sums run in a fixed
// order, and the exception a serial loop would throw first is rethrown after the region.

#include "sparsempm/threads.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <type_traits>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

#if defined(__SANITIZE_THREAD__) && defined(_OPENMP)
#include <sanitizer/tsan_interface.h>
extern "C" void AnnotateIgnoreWritesBegin(const char* file, int line);
extern "C" void AnnotateIgnoreWritesEnd(const char* file, int line);
#endif

namespace smpm::detail {

// libgomp is not instrumented for ThreadSanitizer, which therefore does not see the fork and
// join of a parallel region (what ARCHER adds through OMPT). These annotations tell it: the
// calling thread releases before the region and acquires after it, every thread of the region
// acquires at its start and releases at its end, and the calling thread's writes of the
// region's arguments (which libgomp hands to the other threads) are not recorded. What
// ThreadSanitizer reports are then races between the threads of a region.
inline char region_sync;
inline void region_fork() {
#if defined(__SANITIZE_THREAD__) && defined(_OPENMP)
  __tsan_release(&region_sync);
  AnnotateIgnoreWritesBegin(__FILE__, __LINE__);
#endif
}
inline void region_enter() {
#if defined(__SANITIZE_THREAD__) && defined(_OPENMP)
  if (omp_get_thread_num() == 0)
    AnnotateIgnoreWritesEnd(__FILE__, __LINE__);
  __tsan_acquire(&region_sync);
#endif
}
inline void region_leave() {
#if defined(__SANITIZE_THREAD__) && defined(_OPENMP)
  __tsan_release(&region_sync);
#endif
}
inline void region_join() {
#if defined(__SANITIZE_THREAD__) && defined(_OPENMP)
  __tsan_acquire(&region_sync);
#endif
}

/// Calls body(i) for every i in [0, n), spread over the threads when `rows` (the particles or
/// nodes the loop covers; n when negative) reaches parallel_threshold(). No exception leaves the
/// region: each thread records the first index that threw, and the exception of the smallest one is
/// rethrown after the region (the one a serial loop stops at; indices after a recorded failure may
/// be skipped).
template <class Body>
void parallel_for(Index n, Body&& body, Index rows = -1) {
  std::atomic<Index> first_failure{n};
  std::exception_ptr failure;
  std::mutex lock;
  const bool many = n > 1 && (rows < 0 ? n : rows) >= parallel_threshold() && threads() > 1;
  auto guarded = [&](Index i) {
    if (i > first_failure.load(std::memory_order_relaxed))
      return;
    try {
      body(i);
    } catch (...) {
      std::lock_guard<std::mutex> guard(lock);
      if (i < first_failure.load(std::memory_order_relaxed)) {
        first_failure.store(i, std::memory_order_relaxed);
        failure = std::current_exception();
      }
    }
  };
  if (!many) {
    for (Index i = 0; i < n && !failure; ++i)
      guarded(i);
  } else {
    region_fork();
#pragma omp parallel
    {
      region_enter();
      // nowait: the barrier that ends the region is the one barrier needed (one barrier less:
      // 1.4 of the 4.4 µs a two-thread region costs on the machine of docs/performance.md's
      // figures).
#pragma omp for schedule(static) nowait
      for (Index i = 0; i < n; ++i)
        guarded(i);
      region_leave();
    }
    region_join();
  }
  if (failure)
    std::rethrow_exception(failure);
}

/// Calls body(begin, end) for consecutive ranges that cover [0, n): one range per thread, run in
/// parallel, when `rows` (the particles or nodes the work covers) reaches parallel_threshold()
/// and there are several threads; else body(0, n) on the calling thread. `cumulative` (n + 1
/// nondecreasing counts, or null) balances the ranges by its increments, say the entries of each
/// node, instead of by indices. What a range computes must not depend on where the ranges split
/// (the node sums of scatter_to_nodes in kernels.hpp, the rows of m~ in consistent_mass.cpp).
template <class Body>
void parallel_ranges(Index n, Index rows, const int* cumulative, Body&& body) {
  const Index parts = n > 1 && rows >= parallel_threshold() ? std::min<Index>(threads(), n) : 1;
  if (parts == 1) {
    body(Index(0), n);
    return;
  }
  auto split = [&](Index t) -> Index {
    if (t == parts)
      return n;
    if (!cumulative)
      return t * n / parts;
    const double target = double(cumulative[n] - cumulative[0]) * double(t) / double(parts);
    return Index(std::lower_bound(cumulative, cumulative + n + 1, cumulative[0] + target,
                                  [](int c, double v) { return double(c) < v; }) -
                 cumulative);
  };
  parallel_for(
      parts, [&](Index t) { body(split(t), split(t + 1)); }, rows);
}

/// fn(first, count) for the ranges of parallel_ranges(n, n, nullptr, …): element-wise work on
/// the rows of a node or particle field, with Eigen's segment or middleRows.
template <class Fn>
void parallel_segments(Index n, Fn&& fn) {
  parallel_ranges(n, n, nullptr, [&](Index r0, Index r1) { fn(r0, r1 - r0); });
}

/// Rows per block of the ordered reductions: a fixed size, so the order of the additions is
/// the same for any number of threads.
inline constexpr Index kReductionBlock = 512;

/// out[c] = combine over the blocks of [0, n) of the k values block(begin, end, acc) adds into
/// acc (c < k) for the indices [begin, end) of a block, with combine(a, b) the reduction (a + b
/// for sums, max for maxima), or combine(c, a, b) when it differs between the values: blocks
/// of kReductionBlock indices in order, each from `init`, then the blocks in order. Bit for bit
/// the same for any number of threads.
template <class Block, class Combine>
void ordered_reduce_blocks(Index n, int k, double init, double* out, Block&& block,
                           Combine&& combine) {
  const Index blocks = (n + kReductionBlock - 1) / kReductionBlock;
  std::vector<double> partial(size_t(blocks * k), init);
  parallel_for(
      blocks,
      [&](Index b) {
        block(b * kReductionBlock, std::min(n, (b + 1) * kReductionBlock), partial.data() + b * k);
      },
      n);
  for (int c = 0; c < k; ++c) {
    out[c] = init;
    for (Index b = 0; b < blocks; ++b) {
      if constexpr (std::is_invocable_v<Combine, int, double, double>)
        out[c] = combine(c, out[c], partial[size_t(b * k + c)]);
      else
        out[c] = combine(out[c], partial[size_t(b * k + c)]);
    }
  }
}

/// An exclusive prefix sum over [0, n) in blocks of kReductionBlock indices: starts[b] =
/// Σ count(i) over the indices before block b (blocks + 1 entries, the last the total), the
/// blocks' totals computed in parallel. for_prefix_blocks then visits the blocks in parallel.
template <class Count>
void prefix_block_starts(Index n, std::vector<Index>& starts, Count&& count) {
  const Index blocks = (n + kReductionBlock - 1) / kReductionBlock;
  starts.assign(size_t(blocks + 1), 0);
  parallel_for(
      blocks,
      [&](Index b) {
        Index total = 0;
        for (Index i = b * kReductionBlock; i < std::min(n, (b + 1) * kReductionBlock); ++i)
          total += count(i);
        starts[size_t(b + 1)] = total;
      },
      n);
  for (Index b = 0; b < blocks; ++b)
    starts[size_t(b + 1)] += starts[size_t(b)];
}

/// body(begin, end, start) for each block of prefix_block_starts, in parallel: start is the sum
/// of the counts before index begin.
template <class Body>
void for_prefix_blocks(Index n, const std::vector<Index>& starts, Body&& body) {
  parallel_for(
      Index(starts.size()) - 1,
      [&](Index b) {
        body(b * kReductionBlock, std::min(n, (b + 1) * kReductionBlock), starts[size_t(b)]);
      },
      n);
}

/// ordered_reduce_blocks with term(i, acc) adding index i's values into acc.
template <class Term, class Combine>
void ordered_reduce(Index n, int k, double init, double* out, Term&& term, Combine&& combine) {
  ordered_reduce_blocks(
      n, k, init, out,
      [&](Index begin, Index end, double* acc) {
        for (Index i = begin; i < end; ++i)
          term(i, acc);
      },
      combine);
}

/// Σ_i term(i) for i in [0, n) in the fixed order of ordered_reduce.
template <class Term>
double ordered_sum(Index n, Term&& term) {
  double sum;
  ordered_reduce(
      n, 1, 0.0, &sum, [&](Index i, double* acc) { acc[0] += term(i); },
      [](double a, double b) { return a + b; });
  return sum;
}

} // namespace smpm::detail
