// SPDX-License-Identifier: BSD-3-Clause
// A completed run assembled into one file (OutputFile::finish): every frame's objects copied
// from its frame file to the same paths, the series whole, written under a temporary name and
// renamed over the target; then the run's partial files are removed.

#include "sparsempm/output.hpp"

#include "frame_files.hpp"
#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/version.hpp"

#include <filesystem>
#include <limits>

namespace smpm {

using namespace detail;
namespace fs = std::filesystem;

namespace detail {
std::string removed_frames_directory(const std::string& dir); // output.cpp
}

namespace {

// The largest run (its frame files' bytes) assembled in memory.
constexpr double kAssembleInMemory = 256.0 * 1024 * 1024;

// Copies `path` of `from` to the same path of `to` (its parent group made when missing).
void copy_object(hid_t from, hid_t to, const std::string& group, const std::string& name) {
  const std::string path = group + "/" + name;
  if (!h5::exists(from, group) || !h5::exists(from, path))
    return;
  if (!h5::exists(to, group))
    h5::create_group(to, group);
  if (group == "vertices" && h5::exists(to, path))
    return; // one list per size
  h5::check(H5Ocopy(from, path.c_str(), to, path.c_str(), H5P_DEFAULT, H5P_DEFAULT),
            "cannot copy " + path);
}

// Every object of the run `r` into the file `f`, with the series of `layout` (NaN where the
// run lacks one: a restart from a file of an earlier version).
void assemble(hid_t f, RunReader& r, const SeriesLayout& layout) {
  for (const char* group : {"particles", "grid", "state"})
    h5::create_group(f, group);
  for (const int frame : r.frames()) {
    const hid_t from = r.frame(frame);
    const std::string name = frame_name(frame);
    for (const char* group : {"particles", "grid", "state", "matrices"})
      copy_object(from, f, group, name);
    if (h5::exists(from, "vertices")) {
      const h5::Id v = h5::open_group(from, "vertices");
      H5G_info_t info;
      h5::check(H5Gget_info(v.get(), &info), "vertex lists");
      for (hsize_t k = 0; k < info.nlinks; ++k) {
        char n[32] = {};
        if (H5Lget_name_by_idx(v.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, n, sizeof n,
                               H5P_DEFAULT) >= 0)
          copy_object(from, f, "vertices", n);
      }
    }
  }
  create_series_group(f, layout);
  const h5::Id series = h5::open_group(f, "series");
  const Index rows = r.series("step").rows();
  for (const auto& [name, width] : layout.columns()) {
    const Index cols = Index(std::max<size_t>(width, 1));
    Field values = r.has_series(name) ? r.series(name) : Field();
    if (values.rows() != rows || values.cols() != cols)
      values = Field::Constant(rows, cols, std::numeric_limits<double>::quiet_NaN());
    h5::append_series(series.get(), name, values.data(), hsize_t(rows), hsize_t(width));
  }
}

} // namespace

void OutputFile::finish(const std::string& target) {
  // The index keeps its status until the assembled file has its name: a kill before leaves a
  // restart point, whose restart continues no step and assembles again.
  settle();
  if (!pending_.empty())
    publish(true, true); // the rows after the last frame, for the assembly
  std::error_code ec;
  const bool in_place = fs::equivalent(path_, target, ec);
  {
    // Built in memory when the frames are small (their files' sum under kAssembleInMemory): one
    // write instead of a write per object of every frame.
    double bytes = 0;
    for (const int frame : frame_files_in(dir_))
      bytes += double(fs::file_size(frame_file(dir_, frame), ec));
    RunReader r(path_);
    write_file_atomically(
        target, (fs::path(dir_) / "assembled.h5.tmp").string(),
        [&](hid_t f) {
          h5::set_attribute(f, "input", input_);
          h5::set_attribute(f, "overrides", overrides_);
          h5::set_attribute(f, "source", source_);
          h5::set_attribute(f, "units", units_);
          h5::set_attribute(f, "version", std::string(kVersion));
          h5::set_attribute(f, "status", std::string("completed"));
          assemble(f, r, layout_);
        },
        bytes < kAssembleInMemory);
  }
  sync_directory(fs::path(target).parent_path().string());
  // The target's sidecars, each replaced whole, and the partial run's files removed.
  write_sidecars(target, false);
  // The partial run's sidecars go first (they only view its frames); the frames leave their
  // name in one rename (a kill while they are removed one by one must not leave a partial run
  // of some of them); then the index and the frames go.
  if (!in_place)
    for (const std::string& xmf : xdmf_paths(path_))
      fs::remove(xmf, ec);
  const std::string removed = removed_frames_directory(dir_);
  if (holds_only_frames(dir_)) {
    fs::remove_all(removed, ec);
    fs::rename(dir_, removed, ec);
  }
  if (!in_place)
    fs::remove(path_, ec);
  if (holds_only_frames(removed))
    fs::remove_all(removed, ec);
  path_ = target;
  status_ = "completed";
}

} // namespace smpm
