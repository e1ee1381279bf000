// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Reading a run file in either of its layouts (internal to sparsempm_io): one HDF5 file that
// holds every frame (a completed run, or a run of an earlier version, complete or not), or the
// index of a run in progress with its directory of frame files (frame_files.hpp). Both put a
// frame's objects at the same paths (/particles/<frame>, /grid/<frame>, /state/<frame>,
// /matrices/<frame>), so a frame is read the same way from either.

#include "hdf5_util.hpp"

#include <limits>
#include <string>
#include <vector>

namespace smpm::detail {

/// Opens a run file read-only; InputError saying why not (not HDF5, locked by a writer, or
/// damaged).
hid_t open_for_reading(const std::string& path);
/// The complete frames of a file that holds its frames itself, ascending.
std::vector<int> complete_frames(hid_t file);

/// A run file opened for reading.
class RunReader {
public:
  /// Opens `path` (open_for_reading) and lists its complete frames.
  explicit RunReader(const std::string& path);

  /// The file of the run's attributes (input, overrides, source, version, status).
  hid_t index() const { return index_.get(); }
  /// Whether the frames are in frame files (a run in progress, killed or stopped).
  bool split() const { return !dir_.empty(); }
  /// The directory of the frame files ("" when the file holds its frames).
  const std::string& frames_directory() const { return dir_; }
  /// The complete frames, ascending.
  const std::vector<int>& frames() const { return frames_; }
  /// The file that holds the objects of frame `frame` (the index itself when not split). Valid
  /// until the next call; throws std::runtime_error when it cannot be opened.
  hid_t frame(int frame);
  /// The path of the file that holds frame `frame`.
  std::string frame_path(int frame) const;

  /// Whether the run has the series `name`.
  bool has_series(const std::string& name);
  /// Every row of the series `name` from t = 0 (rows × width; one column for a scalar): the
  /// rows of the complete frames and, after the last, those a stopped run recorded (up to a
  /// frame file that cannot be read, if any). With
  /// `up_to`, the rows of the frames up to that one (at least; the caller cuts by step).
  Field series(const std::string& name, int up_to = std::numeric_limits<int>::max());
  /// The names of the series, in alphabetical order.
  std::vector<std::string> series_names();
  /// The conditions of the reaction series' columns (empty without it).
  std::vector<std::string> reaction_conditions();

private:
  // The group "series" of the index.
  hid_t series_group();
  std::string path_, dir_;
  h5::Id index_;
  std::vector<int> frames_;
  long index_last_ = -1;   // the last frame whose series rows the index holds
  hsize_t frame_rows_ = 0; // those rows (the rows after them: a stopped run's last steps)
  int open_frame_ = -1;
  h5::Id frame_file_, series_;
};

} // namespace smpm::detail
