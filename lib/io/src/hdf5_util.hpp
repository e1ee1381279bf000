// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small RAII helpers over the HDF5 C API (internal to sparsempm_io).

#include "sparsempm/types.hpp"

#include <hdf5.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace smpm::h5 {

/// Owns an hid_t and closes it with the matching H5*close.
class Id {
public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Id() { reset(); }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  Id(Id&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Id& operator=(Id&& o) noexcept {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = -1;
    return *this;
  }
  void reset() {
    if (id_ >= 0 && close_)
      close_(id_);
    id_ = -1;
  }
  hid_t get() const { return id_; }
  /// Gives up the identifier without closing it.
  hid_t release() {
    const hid_t id = id_;
    id_ = -1;
    return id;
  }
  explicit operator bool() const { return id_ >= 0; }

private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

/// An HDF5 call that failed: an object that cannot be created, opened, read or written.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Throws Error "HDF5: <what>" when status < 0.
void check(long status, const std::string& what);

/// Turns off HDF5's automatic printing of its error stack for the calling thread. The library
/// reports a failed HDF5 call as its own one-line error (Error, or an InputError naming the
/// file), and some calls are expected to fail (H5Fis_hdf5 of a file that is not HDF5, H5Fopen of
/// a file another run holds locked): HDF5's default handler would print its error stack on stderr
/// for each (14 lines for an H5Fopen of a missing file). Every function that makes the first HDF5
/// call of an operation (writing a file, opening a run, looking at an existing file) calls this
/// first. HDF5's thread-safe build keeps the setting per thread (H5E_DEFAULT is the calling
/// thread's error stack), so it is set on each call, not once per process.
void quiet_errors();

Id create_group(hid_t parent, const std::string& name);
Id open_group(hid_t parent, const std::string& name);
bool exists(hid_t parent, const std::string& path);

/// A row-major rows × cols array of doubles (cols = 0: 1D of length rows).
void write_doubles(hid_t group, const std::string& name, const double* data, hsize_t rows,
                   hsize_t cols);
void write_ints(hid_t group, const std::string& name, const int* data, hsize_t n, hsize_t cols = 0);
/// The first dimension of a dataset (its rows).
hsize_t rows_of(hid_t group, const std::string& name);
/// Reads a 1D or 2D double dataset into a row-major field (1D → rows × 1).
Field read_doubles(hid_t group, const std::string& name);
std::vector<int> read_ints(hid_t group, const std::string& name);

void set_attribute(hid_t obj, const std::string& name, double value);
void set_attribute(hid_t obj, const std::string& name, long value);
void set_attribute(hid_t obj, const std::string& name, const std::string& value);
void set_attribute(hid_t obj, const std::string& name, const std::vector<std::string>& value);
double get_double_attribute(hid_t obj, const std::string& name);
long get_long_attribute(hid_t obj, const std::string& name);
std::string get_string_attribute(hid_t obj, const std::string& name);
std::vector<std::string> get_strings_attribute(hid_t obj, const std::string& name);
bool has_attribute(hid_t obj, const std::string& name);

/// Rows per chunk of a series.
inline constexpr hsize_t kSeriesChunk = 1024;
/// An extendible 1D (cols = 0) or 2D double dataset in chunks of `chunk` rows; appends rows.
void create_series(hid_t group, const std::string& name, hsize_t cols,
                   hsize_t chunk = kSeriesChunk);
void append_series(hid_t group, const std::string& name, const double* rows, hsize_t count,
                   hsize_t cols);
void truncate_series(hid_t group, const std::string& name, hsize_t rows);

} // namespace smpm::h5
