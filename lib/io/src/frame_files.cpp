// SPDX-License-Identifier: BSD-3-Clause
#include "frame_files.hpp"

#include "hdf5_util.hpp"
#include "sparsempm/run_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace smpm::detail {

namespace fs = std::filesystem;

namespace {
constexpr const char* kTemporary = ".tmp";

// A frame file's name: six or more digits and ".h5".
bool is_frame_name(const std::string& name) {
  const size_t dot = name.size() >= 3 ? name.size() - 3 : 0;
  return name.size() >= 9 && name.compare(dot, 3, ".h5") == 0 &&
         name.find_first_not_of("0123456789") == dot;
}

// fsync of a path opened read-only: its data (a file) or its entries (a directory).
bool sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0)
    return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}
} // namespace

std::string frames_directory(const std::string& index_path) {
  fs::path p(index_path);
  p.replace_extension(".frames");
  return p.string();
}

std::string frame_file(const std::string& dir, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.h5", frame);
  return (fs::path(dir) / name).string();
}

std::vector<int> frame_files_in(const std::string& dir) {
  std::vector<int> frames;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (is_frame_name(name) && name.size() <= 12) // at most 9 digits: an int
      frames.push_back(std::stoi(name.substr(0, name.size() - 3)));
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

void write_temporary(const std::string& temporary, const std::function<void(hid_t)>& fill,
                     bool in_memory) {
  h5::quiet_errors();
  std::error_code ec;
  fs::remove(temporary, ec); // a temporary left by a killed writer
  errno = 0;
  // Built in memory and written at the close in one piece (HDF5's core driver): a frame's
  // hundred small metadata writes become one.
  const h5::Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (in_memory)
    h5::check(H5Pset_fapl_core(fapl.get(), 64 * 1024, true), "core file driver");
  h5::Id file(H5Fcreate(temporary.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl.get()), H5Fclose);
  if (!file)
    throw std::runtime_error("cannot create " + temporary + " (" +
                             (errno ? create_failure(errno) : std::string("HDF5")) + ")");
  try {
    fill(file.get());
    h5::check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush");
    if (H5Fclose(file.release()) < 0)
      throw std::runtime_error("cannot close " + temporary + " (" + std::strerror(errno) + ")");
  } catch (...) {
    file = h5::Id();
    fs::remove(temporary, ec);
    throw;
  }
}

void commit_file(const std::string& temporary, const std::string& path) {
  // The data reach the disk before the name: after a power loss the name holds the whole file
  // or the name does not exist.
  std::error_code ec;
  if (!sync_path(temporary, O_RDONLY)) {
    const int why = errno;
    fs::remove(temporary, ec);
    throw std::runtime_error("cannot sync " + temporary + " (" + std::strerror(why) + ")");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int why = errno;
    fs::remove(temporary, ec);
    throw std::runtime_error("cannot rename " + temporary + " to " + path + " (" +
                             std::strerror(why) + ")");
  }
}

void write_file_atomically(const std::string& path, const std::string& temporary,
                           const std::function<void(hid_t)>& fill, bool in_memory) {
  write_temporary(temporary, fill, in_memory);
  commit_file(temporary, path);
}

void sync_file(const std::string& path) {
  sync_path(path, O_RDONLY);
}

void sync_directory(const std::string& dir) {
  sync_path(dir.empty() ? std::string(".") : dir, O_RDONLY | O_DIRECTORY);
}

void remove_temporaries(const std::string& dir) {
  std::error_code ec;
  std::vector<fs::path> found;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().ends_with(kTemporary))
      found.push_back(it->path());
  for (const fs::path& p : found)
    fs::remove(p, ec);
}

bool holds_only_frames(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec)))
    return false;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!fs::is_regular_file(it->symlink_status(ec)) ||
        !(is_frame_name(name) || name.ends_with(kTemporary)))
      return false;
  }
  return !ec;
}

} // namespace smpm::detail
