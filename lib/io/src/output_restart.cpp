// SPDX-License-Identifier: BSD-3-Clause
// Continuing a stored run (OutputFile::reopen): the frames of the restart file, in either
// layout, become the frame files of the run's partial twin, up to the last frame that can be
// continued; the index is written anew with the series up to that frame.

#include "sparsempm/output.hpp"

#include "frame_files.hpp"
#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/errors.hpp"

#include <filesystem>
#include <limits>

namespace smpm {

using namespace detail;
namespace fs = std::filesystem;

namespace detail {
void make_frames_directory(const std::string& dir); // output.cpp
std::string copying_frames_directory(const std::string& dir);
} // namespace detail

namespace {

// Whether frame `frame` of the run opens whole: the objects a restart reads (a file of an
// earlier version cut short may hold links to objects that never reached the disk). A value
// out of range is the frame's content, refused by the caller with its message.
bool opens_whole(RunReader& source, int frame, Model probe) {
  try {
    load_frame_from(source.frame(frame), frame, probe);
  } catch (const h5::Error&) {
    return false;
  } catch (const std::runtime_error&) {
  }
  return true;
}

// The frame a restart continues: the last one that opens whole.
int restart_frame(RunReader& source, const std::string& path, const Model& model) {
  const std::vector<int>& frames = source.frames();
  for (auto it = frames.rbegin(); it != frames.rend(); ++it)
    if (opens_whole(source, *it, model))
      return *it;
  throw InputError(path + ": no complete frame to restart from");
}

// A frame of a file of one piece as a frame file of its own (its series rows stay in the
// index).
void copy_frame(hid_t from, int frame, const std::string& file) {
  const std::string name = frame_name(frame);
  write_file_atomically(file, file + ".tmp", [&](hid_t f) {
    for (const char* group : {"particles", "grid", "state", "matrices"}) {
      const std::string path = std::string(group) + "/" + name;
      if (!h5::exists(from, group) || !h5::exists(from, path))
        continue;
      if (!h5::exists(f, group))
        h5::create_group(f, group);
      h5::check(H5Ocopy(from, path.c_str(), f, path.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                "cannot copy " + path);
    }
    // The vertex lists of its particles, nodes with mass and contact nodes (the sidecars').
    std::vector<long> counts{long(h5::rows_of(from, "particles/" + name + "/X"))};
    for (const char* set : {"nodes", "contact_nodes"})
      if (h5::exists(from, "grid/" + name) && h5::exists(from, "grid/" + name + "/" + set))
        counts.push_back(long(h5::rows_of(from, "grid/" + name + "/" + set)));
    for (const long n : counts) {
      const std::string vertices = "vertices/" + std::to_string(n);
      if (n == 0 || !h5::exists(from, "vertices") || !h5::exists(from, vertices) ||
          (h5::exists(f, "vertices") && h5::exists(f, vertices)))
        continue;
      if (!h5::exists(f, "vertices"))
        h5::create_group(f, "vertices");
      h5::check(H5Ocopy(from, vertices.c_str(), f, vertices.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                "cannot copy " + vertices);
    }
  });
}

// The frame a restart continues (restart_frame), its state loaded into cfg.model and checked in
// the restart file before anything is written: its content, its time within the run's, its run
// state.
int load_restart_frame(RunReader& source, const std::string& restart_from, RunConfig& cfg) {
  if (source.frames().empty())
    throw InputError(restart_from + ": no complete frame to restart from");
  const int last = restart_frame(source, restart_from, cfg.model);
  try { // the state of the last frame, checked in the restart file before anything is written
    load_frame_from(source.frame(last), last, cfg.model);
  } catch (const std::runtime_error& e) {
    throw InputError(restart_from + ": frame " + std::to_string(last) + ": " + e.what());
  }
  const double end = cfg.time.end;
  if (cfg.model.time > end + 1e-12 * std::abs(end))
    throw InputError(restart_from + ": frame " + std::to_string(last) +
                     ": its time t = " + number_text(cfg.model.time) +
                     " is past the run's end time.end = " + number_text(end) + " (a damaged file)");
  (void)read_run_state(restart_from, last); // its state, refused by the file's name if damaged
  return last;
}

// The series up to the frame's step (a stopped run's later rows, and those of frames after it,
// are dropped), every series of the run (a file of an earlier version lacks some: NaN in its
// rows), in the order of `columns` (name, width); read before any file is written. `rows`: the
// number of rows kept.
std::vector<Field> restart_series(RunReader& source, int last, const Model& model,
                                  const std::vector<std::pair<std::string, size_t>>& columns,
                                  Index& rows) {
  const Field steps = source.series("step", last);
  rows = 0;
  while (rows < steps.rows() && steps(rows, 0) <= double(model.step))
    ++rows;
  std::vector<Field> base;
  for (const auto& [name, width] : columns) {
    Field values = source.has_series(name) ? source.series(name, last) : Field();
    if (values.rows() < rows || values.cols() != Index(std::max<size_t>(width, 1)))
      values = Field::Constant(rows, Index(std::max<size_t>(width, 1)),
                               std::numeric_limits<double>::quiet_NaN());
    base.push_back(values.topRows(rows));
  }
  return base;
}

} // namespace

OutputFile OutputFile::reopen(const std::string& path, const std::string& restart_from,
                              RunConfig& cfg, int& next_frame) {
  RunReader source(restart_from);
  const int last = load_restart_frame(source, restart_from, cfg);
  OutputFile out;
  out.path_ = path;
  out.dir_ = frames_directory(path);
  out.start(cfg);
  // The run's description as stored (cfg.text would append the overrides a second time).
  const hid_t index = source.index();
  out.input_ = h5::get_string_attribute(index, "input");
  out.overrides_ = h5::get_strings_attribute(index, "overrides");
  if (h5::has_attribute(index, "source"))
    out.source_ = h5::get_string_attribute(index, "source");
  Index rows = 0;
  const std::vector<Field> base =
      restart_series(source, last, cfg.model, out.layout_.columns(), rows);
  std::error_code ec;
  const bool in_place = source.split() && fs::equivalent(source.frames_directory(), out.dir_, ec);
  try {
    out.restore_frames(source, last, in_place);
    // The frame files' names reach the disk before the index that names them (which, for a
    // file of one piece continued in place, replaces the only other copy of its frames).
    sync_directory(out.dir_);
    sync_directory(fs::path(path).parent_path().string());
    out.write_restart_index(path, base, rows);
  } catch (...) {
    // Nothing half made stays: a copy's frames go; a run continued in place keeps its files.
    for (const std::string& dir : {out.dir_, copying_frames_directory(out.dir_)})
      if (!in_place && holds_only_frames(dir))
        fs::remove_all(dir, ec);
    out.frames_.clear(); // the destructor names nothing
    throw;
  }
  out.indexed_frame_ = last;
  out.indexed_rows_ = long(rows);
  out.write_sidecars(path, true);
  sync_directory(fs::path(path).parent_path().string());
  next_frame = last + 1;
  return out;
}

// The index of a restarted run: its frames, and `rows` rows of the series `base`.
void OutputFile::write_restart_index(const std::string& path, const std::vector<Field>& base,
                                     Index rows) {
  OutputFile& out = *this;
  write_file_atomically(path, (fs::path(out.dir_) / "index.h5.tmp").string(), [&](hid_t f) {
    out.write_index(f, false); // the frames, with empty series
    h5::Id series = h5::open_group(f, "series");
    const auto columns = out.layout_.columns();
    for (size_t c = 0; c < columns.size(); ++c)
      h5::append_series(series.get(), columns[c].first, base[c].data(), hsize_t(rows),
                        hsize_t(columns[c].second));
    h5::set_attribute(f, "frame_rows", long(rows));
  });
}

void OutputFile::restore_frames(RunReader& source, int last, bool in_place) {
  // A copy is made under another name and given the frames directory's name whole: a kill while
  // it copies leaves no frames directory without its index.
  const std::string into = in_place ? dir_ : copying_frames_directory(dir_);
  if (in_place) {
    // A run continued in place: its frames after the restart frame (that could not be read) go.
    remove_temporaries(dir_);
    for (int f : frame_files_in(dir_))
      if (f > last)
        fs::remove(frame_file(dir_, f));
  } else {
    make_frames_directory(into);
  }
  for (int f : source.frames()) {
    if (f > last)
      break;
    const std::string file = frame_file(into, f);
    if (!in_place && source.split()) {
      const std::string tmp = file + ".tmp";
      fs::copy_file(source.frame_path(f), tmp, fs::copy_options::overwrite_existing);
      sync_file(tmp);
      fs::rename(tmp, file);
    } else if (!in_place) {
      try {
        copy_frame(source.frame(f), f, file);
      } catch (const h5::Error&) {
        continue; // a frame of an earlier version's file cut short: not a frame
      }
    }
    const h5::Id h(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    h5::check(h.get(), "cannot open " + file);
    frames_.push_back(record_of(h.get(), f));
  }
  if (!in_place) {
    sync_directory(into);
    std::error_code ec;
    if (holds_only_frames(dir_)) // a stale one of this path (check_run_output saw no other)
      fs::remove_all(dir_, ec);
    fs::rename(into, dir_);
  }
}

} // namespace smpm
