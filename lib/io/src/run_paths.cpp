// SPDX-License-Identifier: BSD-3-Clause
// The paths and locks of a run's files (run_file.hpp): a partial twin's name, a live run's lock,
// the claim on an output path, the message of a failed create, the check of an input file.
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace smpm {

namespace fs = std::filesystem;

namespace {
constexpr const char* kPartial = ".partial";
} // namespace

// Whether a live run holds `path` with flock(LOCK_EX): its HDF5 file (HDF5 locks a file it
// writes) or its lock file (OutputLock). A shared claim fails while that run lives; a stale
// lock file left by a killed run is not held.
bool held_by_writer(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

bool is_partial_path(const std::string& path) {
  return fs::path(path).stem().string().ends_with(kPartial) ||
         fs::path(path).filename().string().ends_with(kPartial);
}

std::string partial_path(const std::string& path) {
  if (is_partial_path(path))
    return path;
  fs::path p(path);
  const std::string ext = p.extension().string();
  p.replace_filename(p.stem().string() + kPartial + ext);
  return p.string();
}

std::string final_path(const std::string& path) {
  if (!is_partial_path(path))
    return path;
  fs::path p(path);
  const std::string ext = p.extension().string(), stem = p.stem().string();
  const std::string name = p.filename().string();
  if (name.ends_with(kPartial)) // "run.partial": no extension
    p.replace_filename(name.substr(0, name.size() - std::strlen(kPartial)));
  else
    p.replace_filename(stem.substr(0, stem.size() - std::strlen(kPartial)) + ext);
  return p.string();
}

void check_regular_file(const std::string& path, long long max_bytes, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st))
    throw InputError(path + ": cannot open the " + what + " (no such file)");
  if (!fs::is_regular_file(st))
    throw InputError(path + ": the " + what + " must be a regular file, not " +
                     (fs::is_directory(st) ? "a directory" : "a device, FIFO or socket"));
  const auto size = fs::file_size(path, ec);
  if (!ec && (long long)(size) > max_bytes)
    throw InputError(path + ": the " + what + " is " + std::to_string(size) +
                     " bytes, more than the " + std::to_string(max_bytes) + " accepted");
}

std::string create_failure(int err) {
  const std::string text = std::strerror(err);
  if (err == ENOSPC || err == EDQUOT)
    return text + ": the disk, its table of inodes or the quota is full";
  if (err == EACCES || err == EPERM || err == EROFS)
    return text + ": is the directory writable?";
  return text;
}

OutputLock::OutputLock(const std::string& path) : lock_path_(path + ".lock") {
  // Lock the file at the path, then check that the path still names it: a run that finished
  // meanwhile unlinks its lock file before releasing it.
  for (int attempt = 0; attempt < 100; ++attempt) {
    // Not through a link; and a lock file is empty: anything else at its name is somebody's
    // file, which the claim would remove when it ends.
    fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0 && errno == ELOOP)
      throw InputError(path + ": " + lock_path_ + " is a link, not a lock file; not touched");
    if (fd_ < 0)
      throw InputError(path + ": cannot create the lock file " + lock_path_ + " (" +
                       create_failure(errno) + ")");
    struct stat own {};
    if (::fstat(fd_, &own) != 0 || !S_ISREG(own.st_mode) || own.st_size != 0 || own.st_nlink != 1) {
      ::close(fd_);
      fd_ = -1;
      throw InputError(path + ": " + lock_path_ +
                       " exists and is not an empty lock file; not touched (move it away)");
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
      throw InputError(path + ": another run is writing this file (" + lock_path_ +
                       " is locked); wait for it or choose another -o");
    }
    struct stat held {
    }, named{};
    if (::fstat(fd_, &held) == 0 && ::stat(lock_path_.c_str(), &named) == 0 &&
        held.st_ino == named.st_ino && held.st_dev == named.st_dev)
      return;
    ::close(fd_);
    fd_ = -1;
  }
  throw InputError(path + ": could not take the lock " + lock_path_);
}

OutputLock::~OutputLock() {
  if (fd_ < 0)
    return;
  ::unlink(lock_path_.c_str()); // while still locked: no other run holds this inode
  ::flock(fd_, LOCK_UN);
  ::close(fd_);
}

} // namespace smpm
