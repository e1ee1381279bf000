// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file threads.hpp
/// The number of OpenMP threads the kernels of a step use. Results do not depend on it, bit for
/// bit: sums over the particles of a node add their terms in particle order, reductions are summed
/// in blocks of a fixed size (see DESIGN.md, "Threads"). On a machine shared with other busy
/// processes, OMP_WAIT_POLICY=passive keeps waiting threads from spinning.

#include "sparsempm/types.hpp"

namespace smpm {

/// Threads of the parallel regions started by the calling thread (OpenMP's nthreads-var:
/// OMP_NUM_THREADS or the number of cores unless set_threads was called).
int threads();

/// Uses `count` ≥ 1 threads in the parallel regions the calling thread starts from now on.
/// Throws InputError for count < 1.
void set_threads(int count);

/// Applies the environment variable SMPM_THREADS when it is set (it takes precedence over
/// OMP_NUM_THREADS) and returns threads(). Throws InputError naming the variable and its value
/// unless it is a positive integer.
int threads_from_environment();

/// Lets the calling thread run on the CPUs of every OpenMP place again when thread binding is on
/// (OMP_PROC_BIND other than false, OMP_PLACES or GOMP_CPU_AFFINITY). libgomp binds the initial
/// thread to the first place when it loads; a program that then replaces itself (exec) starts
/// with that place's CPUs alone, and its libgomp sees one CPU: one thread by default, every
/// thread on that place when a count is given. Call it before such an exec (and restore the
/// thread's CPUs if the exec fails). Returns true when nothing was bound or the calling thread's
/// CPUs were set (Linux), false when they could not be.
bool unbind_initial_thread() noexcept;

/// Rows (particles, nodes) below which a kernel runs on the calling thread alone, since starting
/// the threads costs more than the work (default 1024). 0 runs every kernel on all threads,
/// which tests use to exercise the parallel paths on small problems.
Index parallel_threshold();
/// Sets parallel_threshold() to `rows` for the whole process (UsageError for rows < 0).
void set_parallel_threshold(Index rows);

} // namespace smpm
