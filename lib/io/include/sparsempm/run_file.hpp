// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file run_file.hpp
/// Where a run writes, safely. A run claims its output path with a lock, writes a partial twin
/// of it ("run.h5" → "run.partial.h5", with its own ParaView sidecar) and moves the partial file
/// over the path only when it completes: a run that fails, is interrupted or killed leaves the
/// partial file (readable by `smpm info` and `--restart`) and never touches a result already
/// at the path.

#include <string>
#include <vector>

namespace smpm {

/// The partial twin of an output path: "dir/run.h5" → "dir/run.partial.h5" ("run" →
/// "run.partial"); a partial path is its own twin.
std::string partial_path(const std::string& path);
/// The output path a partial twin stands for (identity for a path that is not partial).
std::string final_path(const std::string& path);
/// Whether `path` names a partial twin.
bool is_partial_path(const std::string& path);

/// Throws InputError (one line naming the option, the path and the reason) unless `path` may
/// receive a run's output: not a directory, not the input file, not an .xmf name, not an
/// existing file other than a sparsempm run, not a lock file's name, with a partial file that
/// is not a damaged file or a restart point (a run with a complete frame that did not complete
/// or whose file was not yet assembled, whatever its status; replaced only when `discard`), a
/// frames directory that is a run's, and a sidecar that is neither the input nor an XDMF file of
/// another run. `option` names the option in messages ("-o"); `restart` is the run file a
/// restart continues (its own partial file is the one it continues into). `locked`: the caller
/// holds the output's OutputLock (its own lock is not another run's).
void check_run_output(const std::string& path, const std::string& input, const std::string& option,
                      const std::string& restart = {}, bool discard = false, bool locked = false);
/// Throws InputError unless `path` may receive a table (CSV) of `smpm stability` or `smpm
/// spectrum`: not a directory, none of `inputs` (the input file first, then run files read), not an
/// existing HDF5 file or XDMF sidecar, not a lock file or a path a run holds, in a writable
/// directory that exists.
void check_table_output(const std::string& path, const std::vector<std::string>& inputs,
                        const std::string& option);

/// Writes the table `text` to `path` whole or not at all: through the temporary file
/// "<path>.tmp", unlinked and created anew (O_EXCL | O_NOFOLLOW: a file or link left there by a
/// killed command is never written through), with check_table_output done again just before
/// the move (a run may have claimed the path meanwhile). A failed write or move throws
/// std::runtime_error naming the option and the path, and removes the temporary file.
void write_table_file(const std::string& path, const std::string& text,
                      const std::vector<std::string>& inputs, const std::string& option);

/// Whether a live run holds `path` locked: its HDF5 file (as opposed to a damaged file, which
/// HDF5 cannot open either) or its lock file "<output>.lock" (as opposed to a stale one).
bool held_by_writer(const std::string& path);

/// Why creating a file failed, for a message: strerror(err) with what to look at (ENOSPC: the
/// disk or its table of inodes is full; EACCES, EPERM, EROFS: the directory is not writable).
std::string create_failure(int err);

/// Largest run file read (any size HDF5 holds; the check is that it is a regular file).
inline constexpr long long kMaxRunFileBytes = 1LL << 50;

/// Throws InputError unless `path` is a regular file of at most `max_bytes` (inputs and run
/// files: no directories, FIFOs or devices).
void check_regular_file(const std::string& path, long long max_bytes, const std::string& what);

/// An exclusive claim on an output path for the life of a run: "<path>.lock" held with
/// flock(LOCK_EX | LOCK_NB). A second claim on the same path, by this or another process,
/// fails at once with InputError before anything is written. The lock file is removed when
/// the claim ends; one left by a killed run holds no lock and is taken over.
class OutputLock {
public:
  /// Claims `path`: creates "<path>.lock" and locks it. Throws InputError when another claim
  /// holds it, or when "<path>.lock" is a link or a non-empty file (left untouched).
  explicit OutputLock(const std::string& path);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

private:
  std::string lock_path_;
  int fd_ = -1;
};

} // namespace smpm
