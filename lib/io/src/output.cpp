#include "sparsempm/output.hpp"

#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/run_file.hpp"
#include "sparsempm/stages.hpp"
#include "sparsempm/version.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

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

void write_csr(hid_t parent, const std::string& name, const SparseRowMatrix& A) {
  h5::Id g = h5::create_group(parent, name);
  h5::write_doubles(g.get(), "data", A.valuePtr(), hsize_t(A.nonZeros()), 0);
  h5::write_ints(g.get(), "indices", A.innerIndexPtr(), hsize_t(A.nonZeros()));
  h5::write_ints(g.get(), "indptr", A.outerIndexPtr(), hsize_t(A.rows() + 1));
  const int shape[2] = {int(A.rows()), int(A.cols())};
  h5::write_ints(g.get(), "shape", shape, 2);
}

const char* const kSeries[] = {
    "step",     "t",       "kinetic",   "strain", "total", "velocity_change", "velocity_change_sum",
    "friction", "viscous", "fmpm_order"};

} // namespace detail

std::string xdmf_path(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xmf");
  return p.string();
}

OutputFile::OutputFile(const std::string& path, const RunConfig& cfg)
    : path_(path), dim_(cfg.model.grid.dim()), materials_(int(cfg.model.materials.size())) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const h5::Id fapl = access_plist();
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (file_ < 0)
    throw InputError("output.file = \"" + path +
                     "\": cannot create the file (is the directory "
                     "writable?)");
  try {
    initialize(cfg);
  } catch (const std::exception& e) {
    H5Fclose(file_); // the destructor does not run for a throwing constructor
    file_ = -1;
    std::remove(path.c_str()); // no frame yet: nothing to keep, and no file that looks valid
    throw std::runtime_error(path + ": cannot start the run file (" + e.what() +
                             "; is the disk full?)");
  }
}

void OutputFile::initialize(const RunConfig& cfg) {
  h5::set_attribute(file_, "input", cfg.text);
  h5::set_attribute(file_, "overrides", cfg.overrides);
  h5::set_attribute(file_, "source", cfg.source);
  h5::set_attribute(file_, "version", std::string(kVersion));
  h5::set_attribute(file_, "status", std::string("running"));
  h5::create_group(file_, "particles");
  h5::create_group(file_, "grid");
  if (cfg.output.matrices)
    h5::create_group(file_, "matrices");
  h5::Id series = h5::create_group(file_, "series");
  for (const char* s : kSeries)
    h5::create_series(series.get(), s, 0);
  h5::create_series(series.get(), "momentum", hsize_t(dim_));
  create_material_series(series.get(), materials_, dim_);
  h5::check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flush");
}

OutputFile::~OutputFile() {
  if (file_ >= 0)
    H5Fclose(file_);
}

OutputFile::OutputFile(OutputFile&& o) noexcept
    : path_(std::move(o.path_)), file_(o.file_), dim_(o.dim_), frames_(std::move(o.frames_)),
      frame_particles_(std::move(o.frame_particles_)), pending_(std::move(o.pending_)) {
  o.file_ = -1;
}

namespace {
// /particles/<name>: the particle fields of a frame.
void write_particles(hid_t file, const std::string& name, const Model& model) {
  const Particles& P = model.particles;
  h5::Id parts = h5::open_group(file, "particles");
  h5::Id g = h5::create_group(parts.get(), name);
  const hsize_t N = hsize_t(P.size()), d = hsize_t(P.dim);
  h5::write_doubles(g.get(), "X", P.X.data(), N, d);
  h5::write_doubles(g.get(), "V", P.V.data(), N, d);
  h5::write_doubles(g.get(), "stress", P.stress.data(), N, d * d);
  h5::write_doubles(g.get(), "F", P.F.data(), N, d * d);
  h5::write_doubles(g.get(), "mass", P.mass.data(), N, 0);
  const Eigen::VectorXd vol = P.volume();
  h5::write_doubles(g.get(), "volume", vol.data(), N, 0);
  h5::write_doubles(g.get(), "volume0", P.volume0.data(), N, 0);
  h5::write_doubles(g.get(), "half_length", P.half_length.data(), N, d);
  h5::write_ints(g.get(), "material", P.material.data(), N);
  if (P.energy.size() == P.size()) // internal energy per unit mass (Mie–Grüneisen)
    h5::write_doubles(g.get(), "energy", P.energy.data(), N, 0);
  if (P.dim == 1) { // ParaView needs three coordinates
    Field xyz = Field::Zero(P.size(), 3);
    xyz.col(0) = P.X.col(0);
    h5::write_doubles(g.get(), "xyz", xyz.data(), N, 3);
  }
  h5::set_attribute(g.get(), "time", model.time);
  h5::set_attribute(g.get(), "step", model.step);
}

// /grid/<name> (m, p = SᵀMV, v = m⁻¹p) and, when asked, /matrices/<name> (S, G_a, m̃ in CSR),
// from the preparation of the step that starts at the frame (`prepared`, the Stepper's), or from
// the frame's own when there is none or when the matrices need the whole grid's numbering.
void write_grid(hid_t file, const std::string& name, const Model& model, Shape shape, bool matrices,
                const StepPreparation* prepared) {
  const Particles& P = model.particles;
  StepPreparation own;
  if (!prepared || (matrices && prepared->ops.node_range != NodeRange::Grid)) {
    // On the particles' window of the grid (storage and time follow the particles), or on the
    // whole grid when the matrices are written (their columns are the grid's nodes).
    own.ops.node_range = matrices ? NodeRange::Grid : NodeRange::Particles;
    prepare_step(model, shape, own);
    prepared = &own;
  }
  // Multimaterial: each velocity field's nodal fields (node i of field α is α n_g + i), the
  // extrapolation of contact 2020 Eq. (5) before contact.
  const Operators& ops = prepared->ops;
  const int fields = ops.fields;
  {
    // The nodes with mass only (active_nodes), with their indices in the grid (node α n_g + i
    // of field α): a frame of a few particles on a large grid stays small.
    Field p, v;
    map_momentum(particle_operators(ops), P.V, p);
    lumped_solve(ops.m_inv, p, v);
    Eigen::VectorXi nodes = active_nodes(ops);
    const Index na = nodes.size();
    Eigen::VectorXd m(na);
    Field pa(na, P.dim), va(na, P.dim);
    for (Index k = 0; k < na; ++k) {
      m[k] = ops.m[nodes[k]];
      pa.row(k) = p.row(nodes[k]);
      va.row(k) = v.row(nodes[k]);
      nodes[k] = int(ops.whole_node(nodes[k]));
    }
    h5::Id grid = h5::open_group(file, "grid");
    h5::Id g = h5::create_group(grid.get(), name);
    const hsize_t n = hsize_t(na), d = hsize_t(P.dim);
    h5::write_ints(g.get(), "nodes", nodes.data(), n);
    h5::write_doubles(g.get(), "m", m.data(), n, 0);
    h5::write_doubles(g.get(), "p", pa.data(), n, d);
    h5::write_doubles(g.get(), "v", va.data(), n, d);
    h5::set_attribute(g.get(), "grid_nodes", long(model.grid.num_nodes()));
    h5::set_attribute(g.get(), "velocity_fields", long(fields));
    if (fields > 1)
      detail::write_contact_nodes(g.get(), *prepared, p);
  }
  if (!matrices)
    return;
  if (!h5::exists(file, "matrices"))
    h5::create_group(file, "matrices");
  h5::Id mats = h5::open_group(file, "matrices");
  h5::Id g = h5::create_group(mats.get(), name);
  write_csr(g.get(), "S", ops.S);
  for (int a = 0; a < P.dim; ++a)
    write_csr(g.get(), "G" + std::to_string(a), ops.G[size_t(a)]);
  write_csr(g.get(), "consistent_mass", SparseRowMatrix(consistent_mass(ops)));
}

// Appends the buffered rows to /series.
void append_series_rows(hid_t file, const std::vector<SeriesRow>& rows, int dim) {
  h5::Id series = h5::open_group(file, "series");
  const size_t k = rows.size();
  std::vector<double> col(k), mom(k * size_t(dim));
  for (int s = 0; s < kNumSeries; ++s) {
    for (size_t r = 0; r < k; ++r) {
      const SeriesRow& row = rows[r];
      const double vals[kNumSeries] = {double(row.step),
                                       row.t,
                                       row.e.kinetic,
                                       row.e.strain,
                                       row.e.total,
                                       row.velocity_change,
                                       row.velocity_change_sum,
                                       row.friction,
                                       row.viscous,
                                       row.fmpm_order};
      col[r] = vals[s];
    }
    h5::append_series(series.get(), kSeries[s], col.data(), k, 0);
  }
  for (size_t r = 0; r < k; ++r)
    for (int a = 0; a < dim; ++a)
      mom[r * size_t(dim) + size_t(a)] = rows[r].e.momentum[a];
  h5::append_series(series.get(), "momentum", mom.data(), k, hsize_t(dim));
  // Per material: material_sums lays out (mass, momentum d, centre d) per material.
  if (k == 0 || rows[0].materials.empty())
    return;
  const size_t nm = rows[0].materials.size() / size_t(1 + 2 * dim);
  for (int s = 0; s < 3; ++s) {
    const size_t w = size_t(material_width(s, int(nm), dim)), per = w / nm;
    std::vector<double> data(k * w);
    for (size_t r = 0; r < k; ++r)
      for (size_t m = 0; m < nm; ++m)
        for (size_t a = 0; a < per; ++a)
          data[r * w + m * per + a] = rows[r].materials[m * size_t(1 + 2 * dim) +
                                                        (s == 0   ? 0
                                                         : s == 1 ? 1
                                                                  : 1 + size_t(dim)) +
                                                        a];
    h5::append_series(series.get(), kMaterialSeries[s], data.data(), k, hsize_t(w));
  }
}
} // namespace

void OutputFile::write_frame(int frame, const Model& model, Shape shape, bool matrices,
                             const StepPreparation* prepared) {
  const std::string name = frame_name(frame);
  write_particles(file_, name, model);
  write_grid(file_, name, model, shape, matrices, prepared);
  append_series_rows(file_, pending_, dim_); // the rows accumulated since the last frame
  pending_.clear();
  {
    h5::Id parts = h5::open_group(file_, "particles");
    h5::Id g = h5::open_group(parts.get(), name);
    h5::set_attribute(g.get(), "courant_budget", courant_budget_); // stepper state (restart)
    h5::set_attribute(g.get(), "complete", 1L); // written last: the frame is whole
  }
  h5::check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flush");
  frames_.emplace_back(frame, model.time);
  frame_particles_.push_back(model.particles.size());
  write_xdmf_frame(frames_.size() - 1);
}

void OutputFile::set_status(const std::string& status) noexcept {
  try {
    if (!pending_.empty()) { // the series up to the last step, past the last frame
      append_series_rows(file_, pending_, dim_);
      pending_.clear();
    }
  } catch (const std::exception&) {
  }
  try {
    h5::set_attribute(file_, "status", status);
    H5Fflush(file_, H5F_SCOPE_GLOBAL);
  } catch (const std::exception&) {
    // A full disk: the status stays "running"; the frames flushed before remain readable.
  }
}

void OutputFile::finish(const std::string& target) {
  h5::set_attribute(file_, "status", std::string("completed"));
  h5::check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flush");
  h5::check(H5Fclose(file_), "close " + path_);
  file_ = -1;
  const std::string partial_xmf = xdmf_path(path_);
  std::filesystem::rename(path_, target);
  write_xdmf_whole(target, xdmf_path(target));
  std::error_code ec;
  if (!std::filesystem::equivalent(partial_xmf, xdmf_path(target), ec))
    std::filesystem::remove(partial_xmf, ec);
  path_ = target;
}

namespace {
const char* kXdmfTrailer = "  </Grid>\n </Domain>\n</Xdmf>\n";

std::string xdmf_header() {
  return "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
         "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

// The <Grid> of one frame: particle positions and fields as HDF DataItems of `h5_name`.
std::string xdmf_frame(const std::string& h5_name, int frame, double time, Index N, int d) {
  const char* axes = "xyz";
  const std::string name = frame_name(frame), base = h5_name + ":/particles/" + name;
  std::ostringstream x;
  auto data = [&](const std::string& set, Index cols) {
    std::ostringstream s;
    s << "<DataItem Dimensions=\"" << N << (cols ? " " + std::to_string(cols) : "")
      << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << base << "/" << set
      << "</DataItem>";
    return s.str();
  };
  auto column = [&](const std::string& label, const std::string& set, Index cols, Index c) {
    x << "    <Attribute Name=\"" << label << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      << "     <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << N << " 1\">\n"
      << "      <DataItem Dimensions=\"3 2\" Format=\"XML\">0 " << c << " 1 1 " << N
      << " 1</DataItem>\n      " << data(set, cols) << "\n     </DataItem>\n    </Attribute>\n";
  };
  x << "   <Grid Name=\"frame " << name << "\" GridType=\"Uniform\">\n"
    << "    <Time Value=\"" << time << "\"/>\n"
    << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
    << "\" NodesPerElement=\"1\"/>\n"
    << "    <Geometry GeometryType=\"" << (d == 2 ? "XY" : "XYZ") << "\">\n     "
    << (d == 1 ? data("xyz", 3) : data("X", d)) << "\n    </Geometry>\n";
  for (int a = 0; a < d; ++a)
    column(std::string("v") + axes[a], "V", d, a);
  for (int a = 0; a < d; ++a)
    for (int b = a; b < d; ++b)
      column(std::string("stress_") + axes[a] + axes[b], "stress", d * d, a * d + b);
  for (const char* s : {"mass", "volume"})
    x << "    <Attribute Name=\"" << s << "\" AttributeType=\"Scalar\" Center=\"Node\">\n     "
      << data(s, 0) << "\n    </Attribute>\n";
  x << "    <Attribute Name=\"material\" AttributeType=\"Scalar\" Center=\"Node\">\n"
    << "     <DataItem Dimensions=\"" << N << "\" NumberType=\"Int\" Precision=\"4\" "
    << "Format=\"HDF\">" << base << "/material</DataItem>\n    </Attribute>\n";
  x << "   </Grid>\n";
  return x.str();
}
} // namespace

// Appends frame k to the sidecar in place: the new <Grid> replaces the closing tags, which are
// written again after it, so writing frame n costs the size of frame n.
void OutputFile::write_xdmf_frame(size_t k) {
  const std::string xmf = xdmf_path(path_);
  const std::string h5_name = std::filesystem::path(path_).filename().string();
  if (xmf_trailer_ < 0 || !std::filesystem::exists(xmf)) { // new, or removed meanwhile
    std::ofstream out(xmf, std::ios::binary | std::ios::trunc);
    std::string head = xdmf_header();
    for (size_t j = 0; j < k; ++j)
      head += xdmf_frame(h5_name, frames_[j].first, frames_[j].second, frame_particles_[j], dim_);
    out << head;
    if (!out.flush())
      throw std::runtime_error("cannot write the ParaView sidecar " + xmf);
    xmf_trailer_ = long(head.size());
  }
  const std::string block =
      xdmf_frame(h5_name, frames_[k].first, frames_[k].second, frame_particles_[k], dim_);
  std::fstream out(xmf, std::ios::binary | std::ios::in | std::ios::out);
  out.seekp(xmf_trailer_);
  out << block << kXdmfTrailer;
  if (!out.flush())
    throw std::runtime_error("cannot write the ParaView sidecar " + xmf);
  xmf_trailer_ += long(block.size());
}

// The whole sidecar of `h5_path` written to `xmf_path` (through a temporary file).
void OutputFile::write_xdmf_whole(const std::string& h5_path, const std::string& xmf_path) const {
  const std::string h5_name = std::filesystem::path(h5_path).filename().string();
  const std::string tmp = xmf_path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << xdmf_header();
    for (size_t k = 0; k < frames_.size(); ++k)
      out << xdmf_frame(h5_name, frames_[k].first, frames_[k].second, frame_particles_[k], dim_);
    out << kXdmfTrailer;
    if (!out.flush())
      throw std::runtime_error("cannot write the ParaView sidecar " + xmf_path);
  }
  std::filesystem::rename(tmp, xmf_path);
}

OutputFile OutputFile::reopen(const std::string& path, RunConfig& cfg, int& next_frame) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const h5::Id fapl = access_plist();
  OutputFile out;
  out.path_ = path;
  out.dim_ = cfg.model.grid.dim();
  out.materials_ = int(cfg.model.materials.size());
  out.file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get());
  if (out.file_ < 0)
    throw InputError(path + ": cannot open the run file for restart");
  const std::vector<int> frames = complete_frames(out.file_);
  if (frames.empty())
    throw InputError(path + ": no complete frame to restart from");
  const int last = frames.back();
  // Drop incomplete frames after the last complete one.
  for (const char* group : {"particles", "grid", "matrices"}) {
    if (!h5::exists(out.file_, group))
      continue;
    h5::Id g = h5::open_group(out.file_, group);
    for (int k = last + 1; h5::exists(g.get(), frame_name(k)); ++k)
      H5Ldelete(g.get(), frame_name(k).c_str(), H5P_DEFAULT);
  }
  // Load the state of the last frame.
  try {
    load_frame_from(out.file_, last, cfg.model);
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": frame " + std::to_string(last) + ": " + e.what());
  }
  h5::Id parts = h5::open_group(out.file_, "particles");
  // Keep the series rows up to that step.
  h5::Id series = h5::open_group(out.file_, "series");
  const Field step = h5::read_doubles(series.get(), "step");
  hsize_t keep = 0;
  while (keep < hsize_t(step.rows()) && long(step(Index(keep), 0)) <= cfg.model.step)
    ++keep;
  for (const char* s : kSeries) {
    if (!h5::exists(series.get(), s)) { // a file of an earlier version: NaN rows so far
      h5::create_series(series.get(), s, 0);
      const std::vector<double> missing(keep, std::numeric_limits<double>::quiet_NaN());
      h5::append_series(series.get(), s, missing.data(), keep, 0);
    }
    h5::truncate_series(series.get(), s, keep);
  }
  h5::truncate_series(series.get(), "momentum", keep);
  for (int s = 0; s < 3; ++s) {
    const char* name = kMaterialSeries[s];
    if (!h5::exists(series.get(), name)) { // a file of an earlier version: NaN rows so far
      const hsize_t w = material_width(s, out.materials_, out.dim_);
      h5::create_series(series.get(), name, w);
      const std::vector<double> missing(keep * w, std::numeric_limits<double>::quiet_NaN());
      h5::append_series(series.get(), name, missing.data(), keep, w);
    }
    h5::truncate_series(series.get(), name, keep);
  }
  h5::set_attribute(out.file_, "status", std::string("running"));
  for (int k : frames) {
    h5::Id fg = h5::open_group(parts.get(), frame_name(k));
    out.frames_.emplace_back(k, h5::get_double_attribute(fg.get(), "time"));
    out.frame_particles_.push_back(cfg.model.particles.size());
  }
  h5::check(H5Fflush(out.file_, H5F_SCOPE_GLOBAL), "flush");
  for (size_t k = 0; k < out.frames_.size(); ++k) // the sidecar of this file, from scratch
    out.write_xdmf_frame(k);
  next_frame = last + 1;
  return out;
}

} // namespace smpm
