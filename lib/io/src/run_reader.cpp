// SPDX-License-Identifier: BSD-3-Clause
#include "run_reader.hpp"

#include "frame_files.hpp"
#include "output_format.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

namespace smpm::detail {

hid_t open_for_reading(const std::string& path) {
  h5::quiet_errors();
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  // A run of an earlier version held HDF5's lock on its file while it ran: such a file is read
  // without the lock, and a read that meets a flush in progress is tried again. (The lock's
  // setting must match that of a file this process already has open: hence the default first.)
  if (f < 0 && held_by_writer(path)) {
    const h5::Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    h5::check(H5Pset_file_locking(fapl.get(), false, true), "file access without locking");
    f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get());
    for (int attempt = 0; f < 0 && attempt < 20 && held_by_writer(path); ++attempt) {
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
      f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get());
    }
  }
  if (f >= 0)
    return f;
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError(path + ": not an HDF5 run file");
  if (held_by_writer(path))
    throw InputError(path + ": an HDF5 file that cannot be opened now (another process is "
                            "writing it and holds its lock); try again when that run ends");
  throw InputError(path + ": a damaged HDF5 file (cut short or overwritten); it cannot be "
                          "opened");
}

std::vector<int> complete_frames(hid_t file) {
  std::vector<int> frames;
  if (!h5::exists(file, "particles"))
    return frames;
  h5::Id parts = h5::open_group(file, "particles");
  H5G_info_t info;
  if (H5Gget_info(parts.get(), &info) < 0)
    return frames;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[64] = {};
    if (H5Lget_name_by_idx(parts.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name,
                           H5P_DEFAULT) < 0)
      continue;
    const std::string s(name);
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
      continue; // not a frame of ours
    // A frame whose write was cut short (by a kill or a full disk, in a file of an earlier
    // version) may hold dangling links: its particles without the mark written last, or a
    // grid or state group that cannot be opened. (A group that is missing is the frame's
    // content, judged when the frame is read.)
    const hid_t g = H5Gopen2(parts.get(), s.c_str(), H5P_DEFAULT);
    if (g < 0)
      continue;
    const h5::Id group(g, H5Gclose);
    bool whole = h5::has_attribute(g, "complete");
    for (const char* other : {"grid", "state"}) {
      const std::string link = std::string(other) + "/" + s;
      if (whole && h5::exists(file, other) && h5::exists(file, link))
        whole = h5::Id(H5Oopen(file, link.c_str(), H5P_DEFAULT), H5Oclose).get() >= 0;
    }
    if (whole)
      frames.push_back(std::stoi(s));
  }
  std::sort(frames.begin(), frames.end()); // numerically, past 999999 too
  return frames;
}

RunReader::RunReader(const std::string& path)
    : path_(path), index_(open_for_reading(path), H5Fclose) {
  if (!h5::has_attribute(index_.get(), "frame_files")) {
    frames_ = complete_frames(index_.get());
    return;
  }
  // A run in progress: its frames are the files of its directory, named beside the index.
  const std::string name = h5::get_string_attribute(index_.get(), "frame_files");
  dir_ = (std::filesystem::path(path).parent_path() / name).string();
  frames_ = frame_files_in(dir_);
  index_last_ = h5::get_long_attribute(index_.get(), "last_frame");
  frame_rows_ = hsize_t(h5::get_long_attribute(index_.get(), "frame_rows"));
}

std::string RunReader::frame_path(int frame) const {
  return split() ? frame_file(dir_, frame) : path_;
}

hid_t RunReader::frame(int frame) {
  if (!split())
    return index_.get();
  if (frame != open_frame_) {
    frame_file_ = h5::Id();
    open_frame_ = -1;
    const std::string file = frame_file(dir_, frame);
    frame_file_ = h5::Id(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!frame_file_)
      throw h5::Error("cannot open the frame file " + file);
    open_frame_ = frame;
  }
  return frame_file_.get();
}

hid_t RunReader::series_group() {
  if (!series_)
    series_ = h5::open_group(index_.get(), "series");
  return series_.get();
}

bool RunReader::has_series(const std::string& name) {
  return h5::exists(index_.get(), "series") && h5::exists(series_group(), name);
}

Field RunReader::series(const std::string& name, int up_to) {
  Field rows = h5::read_doubles(series_group(), name);
  if (!split() || frames_.empty() || frames_.back() <= index_last_)
    return rows; // the index has every row: the frames' and the stopped run's last steps
  // The index was last written at frame index_last_: the later frames' rows are in their files.
  std::vector<Field> parts{rows.topRows(Index(std::min<hsize_t>(frame_rows_, rows.rows())))};
  Index total = parts[0].rows();
  for (int f : frames_) {
    if (f <= index_last_)
      continue;
    if (f > up_to)
      break;
    Field rows_of_frame;
    try {
      const hid_t file = frame(f);
      if (!h5::exists(file, "series/" + name))
        continue;
      h5::Id g = h5::open_group(file, "series");
      rows_of_frame = h5::read_doubles(g.get(), name);
    } catch (const h5::Error&) {
      break; // a frame file that cannot be read (damaged): the rows end before it
    }
    parts.push_back(std::move(rows_of_frame));
    if (parts.back().cols() != rows.cols())
      throw std::runtime_error("the series " + name + " of frame " + std::to_string(f) + " has " +
                               std::to_string(parts.back().cols()) + " columns, not " +
                               std::to_string(rows.cols()));
    total += parts.back().rows();
  }
  Field out(total, rows.cols());
  Index at = 0;
  for (const Field& p : parts) {
    out.middleRows(at, p.rows()) = p;
    at += p.rows();
  }
  return out;
}

std::vector<std::string> RunReader::series_names() {
  std::vector<std::string> names;
  const hid_t g = series_group();
  H5G_info_t info;
  if (H5Gget_info(g, &info) < 0)
    return names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[128] = {};
    if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) >=
        0)
      names.emplace_back(name);
  }
  return names;
}

std::vector<std::string> RunReader::reaction_conditions() {
  const hid_t g = series_group();
  return h5::has_attribute(g, "reaction_conditions")
             ? h5::get_strings_attribute(g, "reaction_conditions")
             : std::vector<std::string>{};
}

} // namespace smpm::detail
