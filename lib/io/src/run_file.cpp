// SPDX-License-Identifier: BSD-3-Clause
// The checks of a path before a run or a table is written there (run_file.hpp): what an existing
// file, partial twin, frames directory or sidecar at that path is; and a table written whole.
#include "sparsempm/run_file.hpp"

#include "frame_files.hpp"
#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/output.hpp"

#include <hdf5.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace smpm {

namespace fs = std::filesystem;

namespace {

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec))
    return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// What an existing file is: a sparsempm run (with its status and whether it holds a complete
// frame), an HDF5 file a live run holds locked, a damaged HDF5 file, or something else.
enum class FileKind { Run, Locked, Damaged, Other };
struct ExistingFile {
  FileKind kind = FileKind::Other;
  std::string status;
  size_t frames = 0; // its complete frames
};
ExistingFile existing_file(const std::string& path) {
  h5::quiet_errors();
  if (H5Fis_hdf5(path.c_str()) <= 0)
    return {};
  if (held_by_writer(path))
    return ExistingFile{FileKind::Locked, {}, 0};
  try {
    detail::RunReader r(path);
    const hid_t f = r.index();
    if (H5Aexists(f, "version") <= 0 || H5Aexists(f, "status") <= 0 || H5Aexists(f, "input") <= 0)
      return {};
    return ExistingFile{FileKind::Run, h5::get_string_attribute(f, "status"), r.frames().size()};
  } catch (const std::exception&) {
    return ExistingFile{FileKind::Damaged, {}, 0};
  }
}

// The first 4 kB of a file (where an XDMF sidecar names itself and its data file).
std::string file_head(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  return head;
}

// Whether a file starts with the HDF5 signature or holds an XDMF sidecar: files of runs, which a
// table never replaces.
bool is_hdf5_or_sidecar(const std::string& path) {
  h5::quiet_errors();
  return H5Fis_hdf5(path.c_str()) > 0 || file_head(path).find("<Xdmf") != std::string::npos;
}

// Whether an existing .xmf names `h5_name` as its data file (a sidecar of that run).
// A sidecar names its data file in its first element (xdmf_header); one of an earlier version
// in its first DataItem.
bool is_sidecar_of(const std::string& xmf, const std::string& h5_name) {
  const std::string head = file_head(xmf), name = detail::xml_escaped(h5_name);
  return head.find("<Xdmf") != std::string::npos &&
         (head.find("<Information Name=\"data\" Value=\"" + name + "\"/>") != std::string::npos ||
          head.find(">" + name + ":/particles/") != std::string::npos);
}
} // namespace

namespace {

// The names an output path may not have: empty, a directory, no extension, a lock file's, a
// sidecar's, a partial file's.
void check_output_name(const std::string& path, const std::string& option) {
  const std::string who = option + " " + path + ": ";
  if (path.empty())
    throw InputError(option + ": the output path is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError(who + "is a directory; give a file name such as run.h5");
  const fs::path extension = fs::path(path).extension();
  if (extension.empty())
    throw InputError(who + "has no extension; give a name such as run.h5 (its partial file and "
                           "sidecars are named from it)");
  if (extension == ".lock")
    throw InputError(who + "is the name of a run's lock file; give a name such as run.h5");
  if (extension == ".xmf")
    throw InputError(who + "is the name of a ParaView sidecar; give the .h5 name");
  if (is_partial_path(path))
    throw InputError(who + "names a partial file; give the result's name " + final_path(path) +
                     " (a run writes " + path + " itself and moves it there when it completes)");
}

// The output path or its partial twin `p` as a file found there: never the input, a
// directory, a locked or damaged file, another program's file, or a killed run's restart point.
void check_existing_output(const std::string& path, const std::string& p, const std::string& input,
                           const std::string& option, const std::string& restart, bool discard) {
  const std::string who = option + " " + path + ": ";
  std::error_code ec;
  if (!input.empty() && same_file(p, input))
    throw InputError(who + (p == path ? "is" : "its partial file " + p + " is") +
                     " the input file; not overwritten");
  if (fs::is_directory(p, ec))
    throw InputError(who + "its partial file " + p + " is a directory");
  if (!fs::exists(p, ec))
    return;
  const ExistingFile e = existing_file(p);
  if (e.kind == FileKind::Locked)
    throw InputError(path + ": another run is writing this file (" + p +
                     " is locked); wait for it or choose another -o");
  const std::string found = p == path ? "exists" : "its partial file " + p + " exists";
  if (e.kind == FileKind::Damaged)
    throw InputError(who + found +
                     " and is a damaged HDF5 file (it cannot be opened); not overwritten (move "
                     "it away)");
  if (e.kind == FileKind::Other)
    throw InputError(who + found + " and is not a sparsempm run file; not overwritten");
  // A run that did not complete (killed, interrupted, failed, or whose restart failed): its
  // partial file is the point to restart from, replaced only when asked.
  if (p != path && e.frames > 0 && e.status != "completed" && !discard &&
      !(!restart.empty() && same_file(p, restart)))
    throw InputError(who + "its partial file " + p + " holds " + std::to_string(e.frames) +
                     " frame" + (e.frames == 1 ? "" : "s") + " of a run that " +
                     (e.status == "running"                 ? "was stopped"
                      : e.status.starts_with("interrupted") ? "was interrupted"
                                                            : "failed") +
                     "; continue it with --restart " + p +
                     ", or start again with --discard-partial (its frames are then lost)");
}

// The frames directory of the partial twin `p`: a run's (or absent), and not holding frames
// that no index names.
void check_frames_directory(const std::string& path, const std::string& p,
                            const std::string& option, bool discard) {
  const std::string dir = detail::frames_directory(p);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec)))
    return;
  const std::string who = option + " " + path + ": ";
  if (!detail::holds_only_frames(dir))
    throw InputError(who + "its frames directory " + dir +
                     " exists and is not the frames directory of a run; not touched (move it "
                     "away)");
  if (!fs::exists(p, ec) && !detail::frame_files_in(dir).empty() && !discard)
    throw InputError(who + "its frames directory " + dir + " holds frames whose index " + p +
                     " is missing (no run can continue them); not touched: move it away or "
                     "start again with --discard-partial");
}

} // namespace

void check_run_output(const std::string& path, const std::string& input, const std::string& option,
                      const std::string& restart, bool discard, bool locked) {
  check_output_name(path, option);
  // A live run on this path (also where HDF5's own file locks are off) is named as such
  // before its files are judged.
  if (!locked && held_by_writer(path + ".lock"))
    throw InputError(path + ": another run is writing this file (" + path +
                     ".lock is locked); wait for it or choose another -o");
  for (const std::string& p : {path, partial_path(path)})
    check_existing_output(path, p, input, option, restart, discard);
  check_frames_directory(path, partial_path(path), option, discard);
  const std::string who = option + " " + path + ": ";
  std::error_code ec;
  for (const std::string& p : {path, partial_path(path)})
    for (const std::string& xmf : xdmf_paths(p)) {
      if (!input.empty() && same_file(xmf, input))
        throw InputError(who + "its ParaView sidecar " + xmf + " would overwrite the input file");
      if (fs::exists(xmf, ec) && !is_sidecar_of(xmf, fs::path(p).filename().string()))
        throw InputError(who + "its ParaView sidecar " + xmf +
                         " exists and belongs to no run of this file; not overwritten");
    }
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw InputError(who + "the directory " + dir.string() +
                     (fs::exists(dir, ec) ? " is a file" : " does not exist"));
}

void check_table_output(const std::string& path, const std::vector<std::string>& inputs,
                        const std::string& option) {
  const std::string who = option + " " + path + ": ";
  std::error_code ec;
  if (path.empty())
    throw InputError(option + ": the output path is empty");
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st))
    throw InputError(who + "is a directory; give a file name such as table.csv");
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(who + "is not a regular file (a device, FIFO or socket)");
  for (size_t k = 0; k < inputs.size(); ++k)
    if (!inputs[k].empty() && same_file(path, inputs[k]))
      throw InputError(who +
                       (k == 0 ? std::string("is the input file")
                               : "is " + inputs[k] + ", a run file this command reads") +
                       "; not overwritten");
  if (is_partial_path(path))
    throw InputError(who + "names a run's partial file; give a name such as table.csv");
  if (fs::path(path).extension() == ".lock")
    throw InputError(who + "is the name of a run's lock file; give a name such as table.csv");
  if (fs::exists(st) && is_hdf5_or_sidecar(path))
    throw InputError(who + "exists and is a run file or its sidecar; not overwritten");
  if (held_by_writer(path + ".lock"))
    throw InputError(who + "a run is writing this path (it holds " + path +
                     ".lock); not overwritten");
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw InputError(who + (fs::exists(dir, ec)
                                ? "the directory " + dir.string() + " is a file"
                                : "the directory " + dir.string() + " does not exist"));
  // The table is written through a temporary file in its directory: found here, before the
  // work, rather than after it.
  const std::string in_dir = dir.empty() ? std::string(".") : dir.string();
  if (::access(in_dir.c_str(), W_OK) != 0)
    throw InputError(who + "cannot write in the directory " + in_dir + " (" + std::strerror(errno) +
                     ")");
}

void write_table_file(const std::string& path, const std::string& text,
                      const std::vector<std::string>& inputs, const std::string& option) {
  const std::string tmp = path + ".tmp";
  ::unlink(tmp.c_str());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  int why = fd < 0 ? errno : 0;
  for (size_t done = 0; !why && done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0)
      why = n < 0 ? errno : EIO;
    else
      done += size_t(n);
  }
  if (fd >= 0 && ::close(fd) != 0 && !why)
    why = errno;
  if (!why) {
    try {
      check_table_output(path, inputs, option);
    } catch (const InputError&) {
      ::unlink(tmp.c_str());
      throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      why = errno;
  }
  if (why) {
    if (fd >= 0)
      ::unlink(tmp.c_str());
    throw std::runtime_error(option + " " + path + ": cannot write the table (" +
                             std::strerror(why) + ")");
  }
}

} // namespace smpm
