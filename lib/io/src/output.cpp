// SPDX-License-Identifier: BSD-3-Clause
// Writing a run in progress (output.hpp, OutputFile): one frame file per frame, the index and
// the sidecars replaced whole, each through a temporary name (frame_files.hpp).

#include "sparsempm/output.hpp"
#include "sparsempm/particle_columns.hpp"

#include "frame_files.hpp"
#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"
#include "sparsempm/version.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <sys/statvfs.h>

namespace smpm {

using namespace detail;
namespace fs = std::filesystem;

namespace {

// HDF5 closes the files left open when the process exits. A file whose flush failed (a full
// disk) cannot be closed, and that late close crashes inside the library (seen with HDF5
// 1.10.8: a segfault after the run had reported the failure). The files of a run are closed
// explicitly; the exit-time pass is turned off before HDF5 is first used.
const int kNoExitClose = (H5dont_atexit(), 0);

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Throws std::runtime_error unless the file system of `path` has room for `bytes` (an upper
// bound, frame_bytes) and 64 kB more: a frame that might not fit is not begun.
void check_room(const std::string& path, double bytes) {
  struct statvfs fs {};
  const fs::path dir = fs::path(path).parent_path();
  if (::statvfs(dir.empty() ? "." : dir.c_str(), &fs) != 0)
    return; // unknown: the write itself reports a full disk
  const double room = double(fs.f_bavail) * double(fs.f_frsize);
  if (room < bytes + 64 * 1024)
    throw std::runtime_error("no room for the frame: it needs about " +
                             std::to_string(long(bytes / 1024)) + " kB and the disk has " +
                             std::to_string(long(room / 1024)) + " kB free");
}

// The largest frame (frame_bytes) built in memory before it is written.
constexpr double kFrameInMemory = 64.0 * 1024 * 1024;

// The groups that hold one group per frame.
constexpr const char* kFrameGroups[] = {"particles", "grid", "state", "matrices"};

} // namespace

namespace detail {
std::string frame_name(int frame) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%06d", frame);
  return buf;
}

std::string removed_frames_directory(const std::string& dir) {
  return dir + ".removed";
}
std::string copying_frames_directory(const std::string& dir) {
  return dir + ".copying";
}

// A frames directory made anew: one left by an earlier run of this path (it holds only frame
// files and temporaries) is removed; anything else at its name is not touched.
void make_frames_directory(const std::string& dir) {
  std::error_code ec;
  // A completed run's, killed while removed, and a restart's copy, killed while it copied.
  for (const std::string& other : {removed_frames_directory(dir), copying_frames_directory(dir)})
    if (holds_only_frames(other))
      fs::remove_all(other, ec);
  if (fs::exists(fs::symlink_status(dir, ec))) {
    if (!holds_only_frames(dir))
      throw InputError(dir + ": exists and is not the frames directory of a run; not touched "
                             "(move it away)");
    fs::remove_all(dir, ec);
  }
  if (!fs::create_directory(dir, ec) || ec)
    throw InputError(dir + ": cannot create the frames directory (" +
                     (ec ? create_failure(ec.value()) : std::string("it exists")) + ")");
}
} // namespace detail

OutputFile::OutputFile(const std::string& path, const RunConfig& cfg)
    : path_(path), dir_(frames_directory(path)) {
  start(cfg);
  make_frames_directory(dir_);
  try {
    publish(true); // the index before any frame: the run's input and status
  } catch (const std::exception& e) {
    discard(); // no frame yet: nothing to keep, and no file that looks valid
    throw std::runtime_error(path + ": cannot start the run file (" + e.what() +
                             "; is the disk full?)");
  }
}

void OutputFile::start(const RunConfig& cfg) {
  input_ = cfg.text;
  overrides_ = cfg.overrides;
  source_ = cfg.source;
  units_ = cfg.output.units;
  layout_ = SeriesLayout(cfg);
  dim_ = cfg.model.grid.dim();
  for (const Material& m : cfg.model.materials)
    material_names_.push_back(m.name);
}

OutputFile::~OutputFile() {
  // The frames written since the index was, named in it (a run that neither finished nor
  // stopped: a test's or a program's own writer).
  try {
    settle();
    if (!frames_.empty() && indexed_frame_ != frames_.back().frame && status_ != "completed")
      publish(true);
  } catch (const std::exception&) {
  }
}

void OutputFile::write_frame(int frame, const Model& model, Shape shape, bool matrices,
                             const StepPreparation* prepared) {
  size_t columns = 0; // of the series
  for (const auto& column : layout_.columns())
    columns += std::max<size_t>(column.second, 1);
  // Room for the frame and for writing the index and sidecars again after it (which a stop
  // then does: the index always names the frames a full disk leaves).
  const double series_bytes =
      8.0 * double(columns) * double(unindexed_.size() + pending_.size() + kIndexSeriesChunk);
  const double bytes = frame_bytes(model, prepared, matrices, pending_.size(), columns);
  check_room(path_, bytes + 1.25 * published_bytes_ + series_bytes);
  settle(); // the frame before named (its failure is this write's)
  publish(false);
  const std::string name = frame_name(frame), file = frame_file(dir_, frame);
  FrameRecord record;
  // Frames of up to kFrameInMemory bytes are built in memory and written in one piece.
  write_temporary(
      file + ".tmp",
      [&](hid_t f) {
        for (const char* g : {"particles", "grid", "state"})
          h5::create_group(f, g);
        write_particles(f, name, model);
        write_grid(f, name, model, shape, matrices, prepared);
        write_run_state(f, name, state_);
        write_series_rows(f, layout_, pending_); // the rows since the frame before
        h5::Id g = h5::open_group(f, "particles/" + name);
        h5::set_attribute(g.get(), "complete", 1L); // the mark of a whole frame (earlier layouts)
        record = record_of(f, frame);
      },
      bytes < kFrameInMemory);
  // Synced and named on another thread while the run goes on (no HDF5 call there); the next
  // frame, a stop or the end waits for it (settle).
  committing_ =
      std::async(std::launch::async, [tmp = file + ".tmp", file] { commit_file(tmp, file); });
  committing_record_ = record;
  committing_rows_ = std::move(pending_);
  pending_.clear();
  if (indexed_frame_ < 0) { // the first frame is named in the index at once
    settle();
    publish(false);
  }
}

void OutputFile::settle() {
  if (!committing_.valid())
    return;
  committing_.get(); // rethrows the commit's failure
  frames_.push_back(committing_record_);
  unindexed_.insert(unindexed_.end(), committing_rows_.begin(), committing_rows_.end());
  committing_rows_.clear();
}

void OutputFile::publish(bool force, bool tail) {
  const double begin = seconds_now();
  // The index and sidecars cost at most a fifth of the run's time (the first frame is named
  // at once).
  if (!force && indexed_frame_ >= 0 && begin - published_at_ < 4 * publish_cost_)
    return;
  write_file_atomically(path_, (fs::path(dir_) / "index.h5.tmp").string(),
                        [&](hid_t f) { write_index(f, tail); });
  indexed_frame_ = frames_.empty() ? -1 : frames_.back().frame;
  indexed_rows_ += long(unindexed_.size());
  unindexed_.clear();
  write_sidecars(path_, true);
  sync_directory(dir_);
  sync_directory(fs::path(path_).parent_path().string());
  published_at_ = seconds_now();
  publish_cost_ = published_at_ - begin;
  std::error_code ec;
  published_bytes_ = double(fs::file_size(path_, ec));
  for (const std::string& xmf : xdmf_paths(path_))
    if (fs::exists(xmf, ec))
      published_bytes_ += double(fs::file_size(xmf, ec));
}

void OutputFile::write_index(long f, bool tail) {
  h5::set_attribute(f, "input", input_);
  h5::set_attribute(f, "overrides", overrides_);
  h5::set_attribute(f, "source", source_);
  h5::set_attribute(f, "units", units_);
  h5::set_attribute(f, "version", std::string(kVersion));
  h5::set_attribute(f, "status", status_);
  const std::string dir_name = fs::path(dir_).filename().string();
  h5::set_attribute(f, "frame_files", dir_name);
  h5::set_attribute(f, "last_frame", long(frames_.empty() ? -1 : frames_.back().frame));
  h5::set_attribute(f, "frame_rows", indexed_rows_ + long(unindexed_.size()));
  // Each frame's groups as links into its file (h5py follows them; readers of sparsempm list
  // the directory, which may hold frames written after this index).
  std::map<Index, int> vertices; // a vertex list's size → the first frame file that has it
  for (const char* group : kFrameGroups) {
    h5::Id g = h5::create_group(f, group);
    for (const FrameRecord& r : frames_) {
      if (group == kFrameGroups[3] && !r.has_matrices)
        continue;
      const std::string name = frame_name(r.frame),
                        target = (fs::path(dir_name) / (name + ".h5")).string();
      h5::check(H5Lcreate_external(target.c_str(), ("/" + std::string(group) + "/" + name).c_str(),
                                   g.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                "cannot link frame " + name);
      for (const Index n : {r.particles, r.nodes, r.contact})
        if (n > 0)
          vertices.emplace(n, r.frame);
    }
  }
  h5::Id v = h5::create_group(f, "vertices");
  for (const auto& [n, frame] : vertices) {
    const std::string target = (fs::path(dir_name) / (frame_name(frame) + ".h5")).string();
    h5::check(H5Lcreate_external(target.c_str(), ("/vertices/" + std::to_string(n)).c_str(),
                                 v.get(), std::to_string(n).c_str(), H5P_DEFAULT, H5P_DEFAULT),
              "cannot link the vertex list " + std::to_string(n));
  }
  // The series: those of the index written before (its frames' rows), the rows of the frames
  // since, and with `tail` the rows since the last frame (a stopped run's last steps).
  if (indexed_rows_ > 0 || indexed_frame_ >= 0) {
    const h5::Id old(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    h5::check(old.get(), "cannot open the index " + path_);
    h5::check(H5Ocopy(old.get(), "series", f, "series", H5P_DEFAULT, H5P_DEFAULT),
              "cannot copy the series");
    h5::Id series = h5::open_group(f, "series");
    for (const auto& [name, width] : layout_.columns())
      h5::truncate_series(series.get(), name, hsize_t(indexed_rows_));
  } else {
    create_series_group(f, layout_, kIndexSeriesChunk);
  }
  append_series_rows(f, layout_, unindexed_);
  if (tail)
    append_series_rows(f, layout_, pending_);
}

void OutputFile::set_status(const std::string& status) noexcept {
  status_ = status;
  try {
    settle();
  } catch (const std::exception&) {
    // The last frame could not be named (a full disk): its rows stay in the series, before
    // those since.
    pending_.insert(pending_.begin(), committing_rows_.begin(), committing_rows_.end());
    committing_rows_.clear();
  }
  try {
    publish(true, true); // with the rows since the last frame
    return;
  } catch (const std::exception&) {
  }
  // A full disk: the rows since the last frame (no restart needs them) are left out.
  try {
    publish(true, false);
  } catch (const std::exception&) {
    // Still no room: the index keeps its status "running"; the frames stay readable.
  }
}

void OutputFile::discard() noexcept {
  try {
    settle();
  } catch (const std::exception&) {
  }
  frames_.clear(); // nothing left to name
  std::error_code ec;
  fs::remove(path_, ec);
  for (const std::string& xmf : xdmf_paths(path_))
    fs::remove(xmf, ec);
  if (holds_only_frames(dir_))
    fs::remove_all(dir_, ec);
}

OutputFile::FrameRecord OutputFile::record_of(long file, int frame) {
  const std::string name = frame_name(frame);
  FrameRecord r;
  r.frame = frame;
  h5::Id parts = h5::open_group(hid_t(file), "particles");
  h5::Id pg = h5::open_group(parts.get(), name);
  r.time = h5::get_double_attribute(pg.get(), "time");
  r.particles = Index(h5::rows_of(pg.get(), "X"));
  r.has_J = h5::exists(pg.get(), "J");
  for (const ParticleColumn& c : particle_columns())
    if (c.in_frames && h5::exists(pg.get(), std::string(c.name)))
      r.columns.emplace_back(c.name);
  r.has_matrices =
      h5::exists(hid_t(file), "matrices") && h5::exists(hid_t(file), "matrices/" + name);
  if (!h5::exists(hid_t(file), "grid") || !h5::exists(hid_t(file), "grid/" + name))
    return r;
  h5::Id gg = h5::open_group(hid_t(file), "grid/" + name);
  r.fields = int(h5::get_long_attribute(gg.get(), "velocity_fields"));
  if (h5::exists(gg.get(), "X")) // files of earlier versions have no node positions
    r.nodes = Index(h5::rows_of(gg.get(), "nodes"));
  if (h5::exists(gg.get(), "contact_X"))
    r.contact = Index(h5::rows_of(gg.get(), "contact_nodes"));
  return r;
}

} // namespace smpm
