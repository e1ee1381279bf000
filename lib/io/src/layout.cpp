// SPDX-License-Identifier: BSD-3-Clause
// The layout of a run file, stated once (output.hpp: run_file_layout), and the walk of a file
// against it (smpm info).

#include "sparsempm/output.hpp"
#include "sparsempm/particle_columns.hpp"
#include "sparsempm/step_part.hpp"

#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"

#include <algorithm>
#include <array>
#include <regex>
#include <stdexcept>

namespace smpm {

using namespace detail;

namespace {
// The columns the parts of the step add to the particles (particle_columns), as layout entries.
std::vector<LayoutEntry> column_entries() {
  // path, shape, meaning and needs of each column in frames, as strings (a program's part's
  // string_views need not end in a null)
  static const std::vector<std::array<std::string, 4>> text = [] {
    std::vector<std::array<std::string, 4>> t;
    for (const ParticleColumn& c : particle_columns())
      if (c.in_frames)
        t.push_back({"/particles/<frame>/" + std::string(c.name), std::string(c.shape),
                     std::string(c.meaning), std::string(c.needs)});
    return t;
  }();
  std::vector<LayoutEntry> entries;
  for (const auto& [path, shape, meaning, needs] : text)
    entries.push_back({path.c_str(), shape.c_str(), meaning.c_str(), needs.c_str()});
  return entries;
}

// The file's attributes: its input, its version and the status of the run that writes it.
std::vector<LayoutEntry> file_entries() {
  return {
      {"/@input", "text", "the input file with the --set overrides appended", ""},
      {"/@overrides", "strings", "the --set overrides", ""},
      {"/@source", "text", "the input file's name", ""},
      {"/@units", "text",
       "the unit system of the input's numbers (output.units): none, SI or mm-ms-g", ""},
      {"/@version", "text", "the sparsempm version that wrote the file", ""},
      {"/@status", "text", "running | completed | failed: ... | interrupted: ...", ""},
      {"/@frame_files", "text", "the directory of the frame files, beside the index",
       "in progress"},
      {"/@last_frame", "scalar", "the last frame linked here (-1: none)", "in progress"},
      {"/@frame_rows", "scalar", "the series rows up to that frame (later: a stopped run's)",
       "in progress"},
  };
}

// A frame's particles, with the columns of the parts of the step after their material ids.
std::vector<LayoutEntry> particle_entries() {
  std::vector<LayoutEntry> entries = {
      {"/particles/<frame>/X", "N x d", "positions", ""},
      {"/particles/<frame>/V", "N x d", "velocities", ""},
      {"/particles/<frame>/stress", "N x d^2", "Cauchy stresses (row-major)", ""},
      {"/particles/<frame>/F", "N x d^2", "deformation gradients (row-major)", ""},
      {"/particles/<frame>/mass", "N", "masses", ""},
      {"/particles/<frame>/volume", "N", "current volumes J V0", ""},
      {"/particles/<frame>/volume0", "N", "initial volumes", ""},
      {"/particles/<frame>/half_length", "N x d", "initial half-lengths r0 of the domains", ""},
      {"/particles/<frame>/material", "N", "material ids (index of [[material]])", ""},
  };
  const std::vector<LayoutEntry> columns = column_entries();
  entries.insert(entries.end(), columns.begin(), columns.end());
  const std::vector<LayoutEntry> rest = {
      {"/particles/<frame>/J", "N", "det F, the volume ratio V/V0", ""},
      {"/particles/<frame>/xyz", "N x 3", "positions with y = z = 0, for ParaView", "1D"},
      {"/particles/<frame>@time", "scalar", "the frame's time t", ""},
      {"/particles/<frame>@step", "scalar", "the frame's step", ""},
      {"/particles/<frame>@complete", "scalar", "written last: the frame is whole", ""},
  };
  entries.insert(entries.end(), rest.begin(), rest.end());
  return entries;
}

// A frame's grid: the nodes with mass and their fields, and the contact nodes.
std::vector<LayoutEntry> grid_entries() {
  return {
      {"/grid/<frame>/nodes", "na", "grid index of each node with mass (a n_g + i: field a)", ""},
      {"/grid/<frame>/m", "na", "lumped masses m = S^T M", ""},
      {"/grid/<frame>/p", "na x d", "momenta p = S^T M V (before contact)", ""},
      {"/grid/<frame>/v", "na x d", "velocities m^-1 p", ""},
      {"/grid/<frame>/X", "na x d", "positions of the nodes", ""},
      {"/grid/<frame>/xyz", "na x 3", "positions with y = z = 0, for ParaView", "1D"},
      {"/grid/<frame>/field", "na", "velocity field a of each node", "contact"},
      {"/grid/<frame>@grid_nodes", "scalar", "n_g, the grid's nodes", ""},
      {"/grid/<frame>@velocity_fields", "scalar", "n_f, the velocity fields", ""},
      {"/grid/<frame>/contact_nodes", "nc", "grid index of each contact node", "contact"},
      {"/grid/<frame>/contact_fields", "2 nc", "its two fields (-1, -1: three or more)", "contact"},
      {"/grid/<frame>/contact_normal", "nc x d", "the normal from the first field", "contact"},
      {"/grid/<frame>/contact_separation", "nc",
       "the separation of the detection (-1: none, at a node of 3+ fields or of a rigid "
       "partner under 30% of its volume)",
       "contact"},
      {"/grid/<frame>/contact_approaching", "nc", "1 where the fields approach", "contact"},
      {"/grid/<frame>/contact_X", "nc x d", "positions of the contact nodes", "contact"},
      {"/grid/<frame>/contact_xyz", "nc x 3", "their positions with y = z = 0", "1D contact"},
  };
}

// The sidecars' vertex cells and the operators of a frame (output.matrices).
std::vector<LayoutEntry> matrix_entries() {
  return {
      {"/vertices/<n>", "n x 1", "0 ... n - 1: the sidecars' vertex cells of n points", ""},
      {"/matrices/<frame>/<matrix>/data", "nnz",
       "CSR values of S, G0, G1, G2, consistent_mass (and with heat transport "
       "consistent_capacity, conductivity)",
       "output.matrices"},
      {"/matrices/<frame>/<matrix>/indices", "nnz", "CSR column indices", "output.matrices"},
      {"/matrices/<frame>/<matrix>/indptr", "rows + 1", "CSR row offsets", "output.matrices"},
      {"/matrices/<frame>/<matrix>/shape", "2", "rows and columns", "output.matrices"},
  };
}

// The series: one row per step.
std::vector<LayoutEntry> series_entries() {
  return {
      {"/series/step", "steps", "step number, one row per step (row 0: t = 0)", ""},
      {"/series/t", "steps", "time", ""},
      {"/series/kinetic", "steps", "kinetic energy", ""},
      {"/series/strain", "steps", "strain (internal) energy", ""},
      {"/series/total", "steps", "kinetic + strain", ""},
      {"/series/momentum", "steps x d", "total momentum", ""},
      {"/series/velocity_change", "steps", "RMS of V(t) - V(0) (FMPM 2026 §3.1)", ""},
      {"/series/velocity_change_sum", "steps", "its running sum", ""},
      {"/series/fmpm_order", "steps", "order the FMPM loop reached (0: none)", ""},
      {"/series/reaction", "steps x n_bc",
       "force of each velocity condition along its direction (its reaction)", "[[bc]]"},
      {"/series@reaction_conditions", "n_bc", "the conditions of the reaction columns", "[[bc]]"},
      {"/series/material_mass", "steps x n_mat", "mass of each material", ""},
      {"/series/material_momentum", "steps x n_mat d", "momentum of each material", ""},
      {"/series/material_centre", "steps x n_mat d", "centre of mass of each material", ""},
  };
}

// The series the parts of the step add (PartSeries), after the run's own.
std::vector<LayoutEntry> part_series_entries() {
  struct Text {
    std::string path, meaning, needs;
  };
  static const std::vector<Text> text = [] {
    std::vector<Text> t;
    for (const StepPartEntry* entry : step_part_entries())
      for (const PartSeries& s : entry->series)
        t.push_back(
            {"/series/" + std::string(s.name), std::string(s.meaning), std::string(s.needs)});
    return t;
  }();
  std::vector<LayoutEntry> entries;
  for (const Text& s : text)
    entries.push_back({s.path.c_str(), "steps", s.meaning.c_str(), s.needs.c_str()});
  return entries;
}

// The state a restart takes from its frame.
std::vector<LayoutEntry> state_entries() {
  return {
      {"/state/<frame>@courant_budget", "scalar", "periodic FMPM's budget (restart)", ""},
      {"/state/<frame>@friction_work", "scalar", "friction work (restart)", ""},
      {"/state/<frame>@viscous_work", "scalar", "viscous work (restart)", ""},
      {"/state/<frame>@plastic_work", "scalar", "plastic work (restart)", ""},
      {"/state/<frame>@velocity_change_sum", "scalar", "velocity-change sum (restart)", ""},
  };
}
} // namespace

const std::vector<LayoutEntry>& run_file_layout() {
  static const std::vector<LayoutEntry> layout = [] {
    std::vector<LayoutEntry> entries;
    for (auto group : {file_entries, particle_entries, grid_entries, matrix_entries, series_entries,
                       part_series_entries, state_entries}) {
      const std::vector<LayoutEntry> part = group();
      entries.insert(entries.end(), part.begin(), part.end());
    }
    return entries;
  }();
  return layout;
}

std::string layout_pattern(const std::string& path) {
  static const std::regex frame("/[0-9]{6,}(/|@|$)"), matrix("/matrices/<frame>/[A-Za-z0-9_]+/"),
      vertices("^/vertices/[0-9]+$");
  if (std::regex_match(path, vertices))
    return "/vertices/<n>";
  std::string p = std::regex_replace(path, frame, "/<frame>$1");
  return std::regex_replace(p, matrix, "/matrices/<frame>/<matrix>/");
}

const LayoutEntry* layout_entry(const std::string& path) {
  const std::string pattern = layout_pattern(path);
  for (const LayoutEntry& e : run_file_layout())
    if (pattern == e.path)
      return &e;
  return nullptr;
}

namespace {

std::string shape_of(hid_t dataset) {
  const h5::Id space(H5Dget_space(dataset), H5Sclose);
  hsize_t dims[H5S_MAX_RANK] = {};
  const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  std::string s;
  for (int k = 0; k < rank; ++k)
    s += (k ? " x " : "") + std::to_string(dims[k]);
  return rank == 0 ? "scalar" : s;
}

struct Walk {
  std::vector<FileObject> out;
  std::string prefix; // the path of the group being visited
};

herr_t on_attribute(hid_t, const char* name, const H5A_info_t*, void* data) {
  auto& [w, object] = *static_cast<std::pair<Walk*, std::string>*>(data);
  const std::string path = object == "/" ? "/@" + std::string(name) : object + "@" + name;
  w->out.push_back({path, "", layout_entry(path)});
  return 0;
}

void attributes(Walk& w, hid_t obj, const std::string& path) {
  std::pair<Walk*, std::string> ctx{&w, path};
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, on_attribute, &ctx);
}

herr_t on_object(hid_t group, const char* name, const H5O_info_t* info, void* data) {
  Walk& w = *static_cast<Walk*>(data);
  const bool self = std::string(name) == ".";
  const std::string path = w.prefix + (self ? "" : "/" + std::string(name));
  const h5::Id obj(H5Oopen(group, name, H5P_DEFAULT), H5Oclose);
  if (!obj)
    return 0;
  if (info->type == H5O_TYPE_DATASET) {
    const h5::Id set(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    w.out.push_back({path, shape_of(set.get()), layout_entry(path)});
  }
  attributes(w, obj.get(), path);
  return 0;
}

// Every object in the group `path` of the file, recursively.
void visit(Walk& w, hid_t file, const std::string& path) {
  const h5::Id g(H5Gopen2(file, path.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g) // a frame whose write failed (a full disk): a dangling link
    return;
  w.prefix = path;
  H5Ovisit2(g.get(), H5_INDEX_NAME, H5_ITER_INC, on_object, &w, H5O_INFO_BASIC);
}

} // namespace

std::vector<FileObject> walk_run_file(const std::string& path) {
  check_regular_file(path, kMaxRunFileBytes, "run file");
  RunReader r(path);
  Walk w;
  attributes(w, r.index(), "/");
  if (h5::exists(r.index(), "series"))
    visit(w, r.index(), "/series");
  if (r.frames().empty())
    return w.out;
  // The objects of the last frame that opens (a killed run's newest frame file may be damaged),
  // from the file that holds them, and its particles' vertex list.
  int last = -1;
  hid_t file = -1;
  for (auto f = r.frames().rbegin(); f != r.frames().rend() && last < 0; ++f) {
    try {
      file = r.frame(*f);
      last = *f;
    } catch (const std::runtime_error&) { // the frame before it, then
    }
  }
  if (last < 0)
    return w.out;
  for (const char* group : {"grid", "matrices", "particles", "state"}) {
    const std::string g = std::string("/") + group + "/" + frame_name(last);
    if (h5::exists(file, group) && h5::exists(file, g.substr(1)))
      visit(w, file, g);
  }
  const std::string x = "particles/" + frame_name(last) + "/X";
  const std::string v = "/vertices/" + std::to_string(h5::rows_of(file, x));
  if (h5::exists(file, "vertices") && h5::exists(file, v.substr(1))) {
    const h5::Id set(H5Dopen2(file, v.c_str(), H5P_DEFAULT), H5Dclose);
    w.out.push_back({v, shape_of(set.get()), layout_entry(v)});
  }
  return w.out;
}

} // namespace smpm
