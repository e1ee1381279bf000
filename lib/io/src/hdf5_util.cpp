// SPDX-License-Identifier: BSD-3-Clause
#include "hdf5_util.hpp"

#include <stdexcept>

namespace smpm::h5 {

void check(long status, const std::string& what) {
  if (status < 0)
    throw Error("HDF5: " + what);
}

void quiet_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Id create_group(hid_t parent, const std::string& name) {
  const hid_t g = H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check(g, "cannot create group " + name);
  return Id(g, H5Gclose);
}

Id open_group(hid_t parent, const std::string& name) {
  const hid_t g = H5Gopen2(parent, name.c_str(), H5P_DEFAULT);
  check(g, "cannot open group " + name);
  return Id(g, H5Gclose);
}

bool exists(hid_t parent, const std::string& path) {
  return H5Lexists(parent, path.c_str(), H5P_DEFAULT) > 0;
}

namespace {
void write_array(hid_t group, const std::string& name, hid_t type, const void* data, hsize_t rows,
                 hsize_t cols) {
  const hsize_t dims[2] = {rows, cols};
  Id space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose);
  check(space.get(), "dataspace for " + name);
  Id set(H5Dcreate2(group, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
         H5Dclose);
  check(set.get(), "cannot create dataset " + name);
  if (rows * (cols ? cols : 1) > 0)
    check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "cannot write dataset " + name);
}

std::vector<hsize_t> dims_of(hid_t set) {
  Id space(H5Dget_space(set), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  check(rank, "dataspace rank");
  std::vector<hsize_t> dims(static_cast<size_t>(rank), 0);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}
} // namespace

void write_doubles(hid_t group, const std::string& name, const double* data, hsize_t rows,
                   hsize_t cols) {
  write_array(group, name, H5T_NATIVE_DOUBLE, data, rows, cols);
}

void write_ints(hid_t group, const std::string& name, const int* data, hsize_t n, hsize_t cols) {
  write_array(group, name, H5T_NATIVE_INT, data, n, cols);
}

hsize_t rows_of(hid_t group, const std::string& name) {
  Id set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  check(set.get(), "cannot open dataset " + name);
  return dims_of(set.get())[0];
}

Field read_doubles(hid_t group, const std::string& name) {
  Id set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  check(set.get(), "cannot open dataset " + name);
  const auto dims = dims_of(set.get());
  Field out(static_cast<Index>(dims[0]), dims.size() > 1 ? static_cast<Index>(dims[1]) : 1);
  if (out.size())
    check(H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
          "cannot read dataset " + name);
  return out;
}

std::vector<int> read_ints(hid_t group, const std::string& name) {
  Id set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  check(set.get(), "cannot open dataset " + name);
  std::vector<int> out(size_t(dims_of(set.get())[0]));
  if (!out.empty())
    check(H5Dread(set.get(), H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
          "cannot read dataset " + name);
  return out;
}

namespace {
void scalar_attribute(hid_t obj, const std::string& name, hid_t type, const void* value) {
  if (H5Aexists(obj, name.c_str()) > 0)
    H5Adelete(obj, name.c_str());
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id attr(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(attr.get(), "cannot create attribute " + name);
  check(H5Awrite(attr.get(), type, value), "cannot write attribute " + name);
}
Id string_type() {
  Id t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}
} // namespace

void set_attribute(hid_t obj, const std::string& name, double value) {
  scalar_attribute(obj, name, H5T_NATIVE_DOUBLE, &value);
}
void set_attribute(hid_t obj, const std::string& name, long value) {
  scalar_attribute(obj, name, H5T_NATIVE_LONG, &value);
}
void set_attribute(hid_t obj, const std::string& name, const std::string& value) {
  const Id t = string_type();
  const char* s = value.c_str();
  scalar_attribute(obj, name, t.get(), &s);
}
void set_attribute(hid_t obj, const std::string& name, const std::vector<std::string>& value) {
  if (H5Aexists(obj, name.c_str()) > 0)
    H5Adelete(obj, name.c_str());
  const Id t = string_type();
  const hsize_t n = value.size();
  Id space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Id attr(H5Acreate2(obj, name.c_str(), t.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(attr.get(), "cannot create attribute " + name);
  std::vector<const char*> ptrs;
  for (const auto& s : value)
    ptrs.push_back(s.c_str());
  if (n)
    check(H5Awrite(attr.get(), t.get(), ptrs.data()), "cannot write attribute " + name);
}

bool has_attribute(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

double get_double_attribute(hid_t obj, const std::string& name) {
  Id attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  check(attr.get(), "missing attribute " + name);
  double v = 0;
  check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), "cannot read attribute " + name);
  return v;
}
long get_long_attribute(hid_t obj, const std::string& name) {
  Id attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  check(attr.get(), "missing attribute " + name);
  long v = 0;
  check(H5Aread(attr.get(), H5T_NATIVE_LONG, &v), "cannot read attribute " + name);
  return v;
}
std::string get_string_attribute(hid_t obj, const std::string& name) {
  Id attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  check(attr.get(), "missing attribute " + name);
  const Id t = string_type();
  char* s = nullptr;
  check(H5Aread(attr.get(), t.get(), &s), "cannot read attribute " + name);
  std::string out = s ? s : "";
  if (s)
    H5free_memory(s);
  return out;
}
std::vector<std::string> get_strings_attribute(hid_t obj, const std::string& name) {
  Id attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  check(attr.get(), "missing attribute " + name);
  Id space(H5Aget_space(attr.get()), H5Sclose);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<char*> ptrs(n, nullptr);
  const Id t = string_type();
  if (n)
    check(H5Aread(attr.get(), t.get(), ptrs.data()), "cannot read attribute " + name);
  std::vector<std::string> out;
  for (char* s : ptrs) {
    out.emplace_back(s ? s : "");
    if (s)
      H5free_memory(s);
  }
  return out;
}

void create_series(hid_t group, const std::string& name, hsize_t cols, hsize_t rows) {
  const hsize_t dims[2] = {0, cols}, maxdims[2] = {H5S_UNLIMITED, cols};
  const hsize_t chunk[2] = {rows, cols ? cols : 1};
  Id space(H5Screate_simple(cols ? 2 : 1, dims, maxdims), H5Sclose);
  Id plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(plist.get(), cols ? 2 : 1, chunk);
  Id set(H5Dcreate2(group, name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, plist.get(),
                    H5P_DEFAULT),
         H5Dclose);
  check(set.get(), "cannot create series " + name);
}

void append_series(hid_t group, const std::string& name, const double* rows, hsize_t count,
                   hsize_t cols) {
  if (count == 0)
    return;
  Id set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  check(set.get(), "cannot open series " + name);
  const hsize_t old = dims_of(set.get())[0];
  const hsize_t size[2] = {old + count, cols};
  check(H5Dset_extent(set.get(), size), "cannot extend series " + name);
  Id file_space(H5Dget_space(set.get()), H5Sclose);
  const hsize_t start[2] = {old, 0}, extent[2] = {count, cols};
  H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, extent, nullptr);
  Id mem_space(H5Screate_simple(cols ? 2 : 1, extent, nullptr), H5Sclose);
  check(
      H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT, rows),
      "cannot write series " + name);
}

void truncate_series(hid_t group, const std::string& name, hsize_t rows) {
  Id set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  check(set.get(), "cannot open series " + name);
  auto dims = dims_of(set.get());
  dims[0] = rows;
  check(H5Dset_extent(set.get(), dims.data()), "cannot resize series " + name);
}

} // namespace smpm::h5
