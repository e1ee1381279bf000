// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/output.hpp"

#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"
#include "sparsempm/stages.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/version.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/statvfs.h>
#include <thread>

namespace smpm {

using namespace detail;

namespace {

// HDF5 closes the files left open when the process exits. A file whose flush failed (a full
// disk) cannot be closed, and that late close crashes inside the library (seen with HDF5
// 1.10.8: a segfault after the run had reported the failure). The files of a run are closed
// explicitly; the exit-time pass is turned off before HDF5 is first used.
const int kNoExitClose = (H5dont_atexit(), 0);

} // namespace

namespace detail {

std::string frame_name(int frame) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%06d", frame);
  return buf;
}

// File access with the metadata cache never evicting: metadata reaches the disk only at
// H5Fflush, so the file on disk is always the state of the last flush.
h5::Id access_plist() {
  h5::Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5AC_cache_config_t cfg;
  cfg.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  H5Pget_mdc_config(fapl.get(), &cfg);
  cfg.evictions_enabled = false;
  cfg.incr_mode = H5C_incr__off;
  cfg.flash_incr_mode = H5C_flash_incr__off;
  cfg.decr_mode = H5C_decr__off;
  cfg.set_initial_size = true;
  cfg.initial_size = 16 * 1024 * 1024;
  cfg.max_size = 64 * 1024 * 1024;
  cfg.min_size = 1024 * 1024;
  h5::check(H5Pset_mdc_config(fapl.get(), &cfg), "metadata cache configuration");
  return fapl;
}

// The per-material series (mass, momentum, centre of mass) and their widths.
const char* const kMaterialSeries[] = {"material_mass", "material_momentum", "material_centre"};
hsize_t material_width(int s, int materials, int dim) {
  return hsize_t(materials) * (s == 0 ? 1 : hsize_t(dim));
}
void create_material_series(hid_t series, int materials, int dim) {
  for (int s = 0; s < 3; ++s)
    h5::create_series(series, kMaterialSeries[s], material_width(s, materials, dim));
}

const char* const kSeries[] = {"step",
                               "t",
                               "kinetic",
                               "strain",
                               "total",
                               "velocity_change",
                               "velocity_change_sum",
                               "friction",
                               "viscous",
                               "fmpm_order",
                               "plastic"};

} // namespace detail

OutputFile::OutputFile(const std::string& path, const RunConfig& cfg)
    : path_(path), dim_(cfg.model.grid.dim()), materials_(int(cfg.model.materials.size())) {
  for (const Material& m : cfg.model.materials)
    material_names_.push_back(m.name);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const h5::Id fapl = access_plist();
  errno = 0;
  file_ = File(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  if (!file_.is_open()) // HDF5's file driver leaves the errno of its open()
    throw InputError(path + ": cannot create the file (" +
                     (errno ? create_failure(errno) : std::string("is the directory writable?")) +
                     ")");
  try {
    initialize(cfg);
  } catch (const std::exception& e) {
    file_.close();             // the destructor does not run for a throwing constructor
    std::remove(path.c_str()); // no frame yet: nothing to keep, and no file that looks valid
    throw std::runtime_error(path + ": cannot start the run file (" + e.what() +
                             "; is the disk full?)");
  }
}

void OutputFile::initialize(const RunConfig& cfg) {
  h5::set_attribute(file_.get(), "input", cfg.text);
  h5::set_attribute(file_.get(), "overrides", cfg.overrides);
  h5::set_attribute(file_.get(), "source", cfg.source);
  h5::set_attribute(file_.get(), "version", std::string(kVersion));
  h5::set_attribute(file_.get(), "status", std::string("running"));
  h5::create_group(file_.get(), "particles");
  h5::create_group(file_.get(), "grid");
  h5::create_group(file_.get(), "state");
  if (cfg.output.matrices)
    h5::create_group(file_.get(), "matrices");
  h5::Id series = h5::create_group(file_.get(), "series");
  for (const char* s : kSeries)
    h5::create_series(series.get(), s, 0);
  h5::create_series(series.get(), "momentum", hsize_t(dim_));
  create_material_series(series.get(), materials_, dim_);
  if (cfg.step.transport.update != TransportUpdate::Off)
    for (const char* s : kThermalSeries)
      h5::create_series(series.get(), s, 0);
  if (const std::vector<std::string> labels = reaction_labels(cfg.model); !labels.empty()) {
    h5::create_series(series.get(), "reaction", hsize_t(labels.size()));
    h5::set_attribute(series.get(), "reaction_conditions", labels);
  }
  h5::check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), "flush");
}

OutputFile::~OutputFile() = default;

OutputFile::File& OutputFile::File::operator=(File&& o) noexcept {
  if (this != &o) {
    close();
    id_ = o.id_;
    o.id_ = -1;
  }
  return *this;
}

long OutputFile::File::close() {
  const long status = id_ >= 0 ? H5Fclose(id_) : 0;
  id_ = -1;
  return status;
}

namespace {
// The groups that hold one group per frame.
constexpr const char* kFrameGroups[] = {"particles", "grid", "matrices", "state"};

// Renames the frame groups `from` to `to` (best effort when `to` is empty: deletes them).
void move_frame(hid_t file, const std::string& from, const std::string& to) {
  for (const char* group : kFrameGroups) {
    if (!h5::exists(file, group))
      continue;
    const h5::Id g = h5::open_group(file, group);
    if (H5Lexists(g.get(), from.c_str(), H5P_DEFAULT) <= 0)
      continue;
    if (to.empty())
      H5Ldelete(g.get(), from.c_str(), H5P_DEFAULT);
    else
      h5::check(H5Lmove(g.get(), from.c_str(), g.get(), to.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                "cannot name frame " + to);
  }
}

// Throws std::runtime_error unless the file system of `path` has room for `bytes` (an upper
// bound, frame_bytes) and 64 kB more: a
// write that fills the disk leaves HDF5 metadata pointing past the end of the file (links that
// cannot even be deleted), so a frame that might not fit is not begun.
void check_room(const std::string& path, double bytes) {
  struct statvfs fs {};
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (::statvfs(dir.empty() ? "." : dir.c_str(), &fs) != 0)
    return; // unknown: the write itself reports a full disk
  const double room = double(fs.f_bavail) * double(fs.f_frsize);
  if (room < bytes + 64 * 1024)
    throw std::runtime_error("no room for the frame: it needs about " +
                             std::to_string(long(bytes / 1024)) + " kB and the disk has " +
                             std::to_string(long(room / 1024)) + " kB free");
}
} // namespace

void OutputFile::write_frame(int frame, const Model& model, Shape shape, bool matrices,
                             const StepPreparation* prepared) {
  ensure_open();
  check_room(path_, frame_bytes(model, prepared, matrices, pending_.size(), series_written_));
  // The frame is written under a staging name that no reader takes for a frame, flushed, and
  // only then given its name: a frame whose write fails all the same (the disk filled by another
  // program) leaves no frame behind. A staged name left by such a failure (a dangling link,
  // which HDF5 cannot delete) is passed over.
  const std::string name = frame_name(frame);
  const hid_t f = file_.get();
  std::string staged = name + ".staged";
  for (int k = 1; h5::exists(f, "particles/" + staged); ++k)
    staged = name + ".staged" + std::to_string(k);
  try {
    write_particles(f, staged, model);
    write_grid(f, staged, model, shape, matrices, prepared);
    write_run_state(f, staged, state_);
    append_series_rows(f, pending_, dim_); // the rows accumulated since the last frame
    {
      h5::Id g = h5::open_group(f, "particles/" + staged);
      h5::set_attribute(g.get(), "complete", 1L); // the frame is whole
    }
    h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush");
    move_frame(f, staged, name);
    h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush");
  } catch (...) {
    move_frame(f, staged, ""); // no staged frame in what a later flush writes
    throw;
  }
  series_written_ += pending_.size();
  pending_.clear();
  frames_.push_back(record_of(file_.get(), frame));
  write_xdmf_frame(frames_.size() - 1);
  // The metadata cache, which never evicts (access_plist), keeps the metadata of every frame
  // since the file was opened, and each flush scans all of it (HDF5 1.10's
  // H5C_set_slist_enabled): frame n cost O(n), 10,000 frames of 4 particles slowed from 60 to
  // a few frames per second. Closing the file (clean: it was just flushed) and opening it again
  // every kFramesPerOpen frames empties the cache; the file is opened again when it is next
  // written (ensure_open), so that a failure to open it is the next write's, not this frame's.
  if (frames_.size() % kFramesPerOpen == 0)
    file_.close();
}

void OutputFile::ensure_open() {
  if (file_.is_open())
    return;
  const h5::Id fapl = access_plist();
  // A reader that opened the file while it was closed holds HDF5's lock for a moment.
  for (int attempt = 0; attempt < 200 && !file_.is_open(); ++attempt) {
    if (attempt > 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    file_ = File(H5Fopen(path_.c_str(), H5F_ACC_RDWR, fapl.get()));
  }
  if (!file_.is_open())
    throw std::runtime_error(path_ + ": cannot open the run file again (another program has "
                                     "held it open for 2 s)");
}

void OutputFile::set_status(const std::string& status) noexcept {
  try {
    ensure_open();
    if (!pending_.empty()) { // the series up to the last step, past the last frame
      append_series_rows(file_.get(), pending_, dim_);
      series_written_ += pending_.size();
      pending_.clear();
    }
  } catch (const std::exception&) {
  }
  try {
    h5::set_attribute(file_.get(), "status", status);
    H5Fflush(file_.get(), H5F_SCOPE_GLOBAL);
  } catch (const std::exception&) {
    // A full disk: the status stays "running"; the frames flushed before remain readable.
  }
}

void OutputFile::discard() noexcept {
  file_.close();
  std::error_code ec;
  std::filesystem::remove(path_, ec);
  for (const std::string& xmf : xdmf_paths(path_))
    std::filesystem::remove(xmf, ec);
}

void OutputFile::finish(const std::string& target) {
  ensure_open();
  h5::set_attribute(file_.get(), "status", std::string("completed"));
  h5::check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), "flush");
  h5::check(file_.close(), "close " + path_);
  std::error_code ec;
  const bool in_place = path_ == target || std::filesystem::equivalent(path_, target, ec);
  std::filesystem::rename(path_, target);
  // The target's sidecars, whole; a sidecar of an earlier run there that this run has not (the
  // contact nodes of a multimaterial run, replaced by a single-material one) is removed, and so
  // are the partial file's.
  for (const std::string& xmf : xdmf_paths(target))
    std::filesystem::remove(xmf, ec);
  write_xdmf_whole(target);
  if (!in_place)
    for (const std::string& xmf : xdmf_paths(path_))
      std::filesystem::remove(xmf, ec);
  path_ = target;
}

namespace {

// Drops every frame group but the complete frames (a killed or failed run's last frame, staged
// or dangling: a link whose object never reached the disk).
void drop_incomplete_frames(hid_t file, const std::vector<int>& frames) {
  std::vector<std::string> keep;
  for (int k : frames)
    keep.push_back(frame_name(k));
  for (const char* group : kFrameGroups) {
    if (!h5::exists(file, group))
      continue;
    h5::Id g = h5::open_group(file, group);
    H5G_info_t info;
    H5Gget_info(g.get(), &info);
    std::vector<std::string> names;
    for (hsize_t k = 0; k < info.nlinks; ++k) {
      char link[64] = {};
      if (H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, link, sizeof link,
                             H5P_DEFAULT) >= 0)
        names.emplace_back(link);
    }
    for (const std::string& n : names)
      if (std::find(keep.begin(), keep.end(), n) == keep.end())
        H5Ldelete(g.get(), n.c_str(), H5P_DEFAULT);
  }
}

// Truncates every series to the rows of steps up to `step` (the restart frame's); a series that
// a file of an earlier version lacks is made, NaN in those rows.
hsize_t keep_series_to(hid_t file, long step, int materials, int dim) {
  h5::Id series = h5::open_group(file, "series");
  const Field steps = h5::read_doubles(series.get(), "step");
  hsize_t keep = 0;
  while (keep < hsize_t(steps.rows()) && long(steps(Index(keep), 0)) <= step)
    ++keep;
  auto make_missing = [&](const char* name, hsize_t width) {
    if (h5::exists(series.get(), name))
      return;
    h5::create_series(series.get(), name, width);
    const std::vector<double> missing(keep * std::max<hsize_t>(width, 1),
                                      std::numeric_limits<double>::quiet_NaN());
    h5::append_series(series.get(), name, missing.data(), keep, width);
  };
  for (const char* s : kSeries) {
    make_missing(s, 0);
    h5::truncate_series(series.get(), s, keep);
  }
  h5::truncate_series(series.get(), "momentum", keep);
  for (int s = 0; s < 3; ++s) {
    make_missing(kMaterialSeries[s], material_width(s, materials, dim));
    h5::truncate_series(series.get(), kMaterialSeries[s], keep);
  }
  for (const char* s : kThermalSeries) // heat transport's, when the run has them
    if (h5::exists(series.get(), s))
      h5::truncate_series(series.get(), s, keep);
  if (h5::exists(series.get(), "reaction")) // the velocity conditions', when the run has them
    h5::truncate_series(series.get(), "reaction", keep);
  return keep;
}

} // namespace

OutputFile OutputFile::reopen(const std::string& path, RunConfig& cfg, int& next_frame) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const h5::Id fapl = access_plist();
  OutputFile out;
  out.path_ = path;
  out.dim_ = cfg.model.grid.dim();
  out.materials_ = int(cfg.model.materials.size());
  out.file_ = File(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()));
  if (!out.file_.is_open())
    throw InputError(path + ": cannot open the run file for restart");
  const hid_t f = out.file_.get();
  const std::vector<int> frames = complete_frames(f);
  if (frames.empty())
    throw InputError(path + ": no complete frame to restart from");
  const int last = frames.back();
  if (!h5::exists(f, "state")) // a file of an earlier version
    h5::create_group(f, "state");
  drop_incomplete_frames(f, frames);
  try { // the state of the last frame
    load_frame_from(f, last, cfg.model);
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": frame " + std::to_string(last) + ": " + e.what());
  }
  out.series_written_ = keep_series_to(f, cfg.model.step, out.materials_, out.dim_);
  h5::set_attribute(f, "status", std::string("running"));
  for (const Material& m : cfg.model.materials)
    out.material_names_.push_back(m.name);
  for (int k : frames)
    out.frames_.push_back(record_of(f, k));
  h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush");
  for (size_t k = 0; k < out.frames_.size(); ++k) // the sidecar of this file, from scratch
    out.write_xdmf_frame(k);
  next_frame = last + 1;
  return out;
}

} // namespace smpm
