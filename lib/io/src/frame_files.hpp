// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The frame files of a run being written (internal to sparsempm_io; docs/guide/file-safety.md).
//
// A run in progress is an index file ("run.partial.h5") beside a directory of frame files
// ("run.partial.frames/000012.h5"). Each file is written whole under a temporary name, closed,
// synced and only then renamed into place, so that at any instant (a SIGKILL, a power loss) a
// name holds a complete file or nothing: HDF5 updates its metadata in place, and a file whose
// flush is cut short cannot be opened. The directory is the record of the completed frames;
// the index, replaced the same way, names the run (input, status) and links the frames for
// h5py. A completed run is assembled into one file of the same layout (output_assemble.cpp).

#include <functional>
#include <hdf5.h>
#include <string>
#include <vector>

namespace smpm::detail {

/// The directory of a run file's frame files: "dir/run.partial.h5" → "dir/run.partial.frames".
std::string frames_directory(const std::string& index_path);
/// The file of frame `frame` in `dir`: "dir/000012.h5".
std::string frame_file(const std::string& dir, int frame);
/// The frames whose files are in `dir`, ascending (a frame file is complete once named).
std::vector<int> frame_files_in(const std::string& dir);

/// Creates the HDF5 file `path` whole or not at all: `fill` writes it as `temporary` (a name
/// no reader takes for a run's file), which is then closed, synced to the disk and renamed to
/// `path`. `in_memory`: the file is built in memory and written at its close in one piece
/// (HDF5's core driver; for files that fit in memory). A failure throws std::runtime_error and
/// leaves `path` as it was.
void write_file_atomically(const std::string& path, const std::string& temporary,
                           const std::function<void(hid_t)>& fill, bool in_memory = true);
/// The first half of write_file_atomically: `fill` writes the HDF5 file `temporary`, which is
/// closed. Throws std::runtime_error (and removes it) on failure.
void write_temporary(const std::string& temporary, const std::function<void(hid_t)>& fill,
                     bool in_memory = true);
/// The second half: `temporary` is synced to the disk and renamed to `path`. Touches no HDF5
/// object, so it may run on another thread while HDF5 is used. Throws std::runtime_error.
void commit_file(const std::string& temporary, const std::string& path);
/// Flushes a file's data to the disk; best effort.
void sync_file(const std::string& path);
/// Flushes a directory's entries to the disk (the renames into it); best effort.
void sync_directory(const std::string& dir);
/// Removes what a writer killed in `dir` leaves: temporary files.
void remove_temporaries(const std::string& dir);
/// Whether `dir` holds only frame files and temporaries of a run: a rerun may remove it.
bool holds_only_frames(const std::string& dir);

} // namespace smpm::detail
