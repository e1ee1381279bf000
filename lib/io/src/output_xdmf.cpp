// SPDX-License-Identifier: BSD-3-Clause
// The XDMF sidecars of a run file, for ParaView and meshio (output.hpp).
//
// Each sidecar is one temporal collection of uniform grids of one kind of points (particles,
// grid nodes, contact nodes), every grid a Polyvertex topology with its connectivity
// (/vertices/<n>: one vertex cell per point), the points' positions as its geometry and as an
// attribute, and whole arrays as attributes (no HyperSlab): the layout ParaView's Xdmf3
// readers, its legacy XDMF reader and meshio's TimeSeriesReader all read. The tensors σ and F
// (d² columns, row-major) are "Matrix" attributes: the legacy reader reshapes a 2D "Tensor"
// (fewer than 9 components) and Xdmf3 reorders a 3D one, which the transposes F
// (tests/io/check_readers.py).

#include "output_format.hpp"

#include "sparsempm/output.hpp"
#include "sparsempm/particle_columns.hpp"

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace smpm {

using namespace detail;

namespace {
constexpr std::array<const char*, 3> kSidecarSuffix{"", ".nodes", ".contact"};
constexpr std::array<const char*, 3> kCollectionName{"particles", "grid nodes", "contact nodes"};
} // namespace

std::string xdmf_path(const std::string& h5_path, Sidecar which) {
  std::filesystem::path p(h5_path);
  p.replace_extension(std::string(kSidecarSuffix[size_t(which)]) + ".xmf");
  return p.string();
}

std::vector<std::string> xdmf_paths(const std::string& h5_path) {
  return {xdmf_path(h5_path, Sidecar::Particles), xdmf_path(h5_path, Sidecar::Nodes),
          xdmf_path(h5_path, Sidecar::Contact)};
}

namespace detail {
std::string xml_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&apos;";
      break;
    default:
      out += c;
    }
  }
  return out;
}
} // namespace detail

namespace {
const char* kXdmfTrailer = "  </Grid>\n </Domain>\n</Xdmf>\n";

// The sidecar's head: the data file's name and the material names (id: name) as Information
// elements, and the opening of the temporal collection.
std::string xdmf_header(Sidecar which, const std::string& h5_name,
                        const std::vector<std::string>& materials) {
  std::string names;
  for (size_t m = 0; m < materials.size(); ++m)
    names += (m ? "; " : "") + std::to_string(m) + ": " + materials[m];
  return "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
         "  <Information Name=\"data\" Value=\"" +
         xml_escaped(h5_name) +
         "\"/>\n"
         "  <Information Name=\"materials\" Value=\"" +
         xml_escaped(names) + "\"/>\n  <Grid Name=\"" + kCollectionName[size_t(which)] +
         "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

// One <Grid> of a sidecar: n points whose datasets are in group `base` of the HDF5 file.
class GridBlock {
public:
  GridBlock(const std::string& h5_name, const std::string& base, Index n, int d)
      : file_(xml_escaped(h5_name)), base_(file_ + ":" + base), n_(n), d_(d) {}

  // The grid's opening: time (full precision), the Polyvertex topology and the geometry
  // (dataset `geometry`, d columns; `geometry_1d` with three in 1D).
  void open(const std::string& name, double time, const std::string& geometry,
            const std::string& geometry_1d) {
    x_.precision(std::numeric_limits<double>::max_digits10);
    x_ << "   <Grid Name=\"" << name << "\" GridType=\"Uniform\">\n"
       << "    <Time Value=\"" << time << "\"/>\n"
       << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n_
       << "\" NodesPerElement=\"1\">\n     <DataItem Dimensions=\"" << n_
       << " 1\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << file_ << ":/vertices/" << n_
       << "</DataItem>\n    </Topology>\n"
       << "    <Geometry GeometryType=\"" << (d_ == 2 ? "XY" : "XYZ") << "\">\n     "
       << item(d_ == 1 ? geometry_1d : geometry, d_ == 1 ? 3 : d_, "Float") << "\n"
       << "    </Geometry>\n";
  }
  // An attribute of `cols` columns per point (0: a 1D dataset): a scalar, a vector of d, or a
  // matrix (σ and F, d² columns in row-major order as in the run file).
  void attribute(const std::string& name, const std::string& set, Index cols,
                 const char* type = "Float") {
    const char* kind = cols <= 1 ? "Scalar" : cols == d_ ? "Vector" : "Matrix";
    x_ << "    <Attribute Name=\"" << name << "\" AttributeType=\"" << kind
       << "\" Center=\"Node\">\n     " << item(set, cols, type) << "\n    </Attribute>\n";
  }
  std::string close() {
    x_ << "   </Grid>\n";
    return x_.str();
  }

private:
  std::string item(const std::string& set, Index cols, const char* type) const {
    std::ostringstream s;
    s << "<DataItem Dimensions=\"" << n_ << (cols ? " " + std::to_string(cols) : "")
      << "\" NumberType=\"" << type << "\" Precision=\"" << (type[0] == 'I' ? 4 : 8)
      << "\" Format=\"HDF\">" << base_ << "/" << set << "</DataItem>";
    return s.str();
  }
  std::string file_, base_;
  Index n_;
  int d_;
  std::ostringstream x_;
};

using FrameRecord = OutputFile::FrameRecord;

// The <Grid> of one frame in a sidecar; empty when the frame has no such points.
std::string xdmf_frame(Sidecar which, const std::string& h5_name, const FrameRecord& f, int d) {
  const std::string name = frame_name(f.frame);
  const Index dd = Index(d) * d;
  if (which == Sidecar::Particles) {
    if (f.particles == 0)
      return {};
    GridBlock g(h5_name, "/particles/" + name, f.particles, d);
    g.open("particles " + name, f.time, "X", "xyz");
    g.attribute("position", "X", d == 1 ? 0 : d);
    g.attribute("velocity", "V", d == 1 ? 0 : d);
    g.attribute("stress", "stress", d == 1 ? 0 : dd);
    g.attribute("F", "F", d == 1 ? 0 : dd);
    if (f.has_J)
      g.attribute("J", "J", 0);
    for (const ParticleColumn& c : particle_columns()) // the parts' columns, as they name them
      if (!c.xdmf.empty() &&
          std::find(f.columns.begin(), f.columns.end(), c.name) != f.columns.end())
        g.attribute(std::string(c.xdmf), std::string(c.name),
                    d == 1 || c.width == ColumnWidth::One ? 0 : column_width(c, d));
    for (const char* s : {"mass", "volume", "volume0"})
      g.attribute(s, s, 0);
    g.attribute("half_length", "half_length", d == 1 ? 0 : d);
    g.attribute("material", "material", 0, "Int");
    return g.close();
  }
  if (which == Sidecar::Nodes) {
    if (f.nodes == 0)
      return {};
    GridBlock g(h5_name, "/grid/" + name, f.nodes, d);
    g.open("grid nodes " + name, f.time, "X", "xyz");
    g.attribute("position", "X", d == 1 ? 0 : d);
    g.attribute("node", "nodes", 0, "Int");
    if (f.fields > 1)
      g.attribute("field", "field", 0, "Int");
    g.attribute("mass", "m", 0);
    g.attribute("momentum", "p", d == 1 ? 0 : d);
    g.attribute("velocity", "v", d == 1 ? 0 : d);
    return g.close();
  }
  if (f.contact == 0)
    return {};
  GridBlock g(h5_name, "/grid/" + name, f.contact, d);
  g.open("contact nodes " + name, f.time, "contact_X", "contact_xyz");
  g.attribute("position", "contact_X", d == 1 ? 0 : d);
  g.attribute("node", "contact_nodes", 0, "Int");
  g.attribute("normal", "contact_normal", d == 1 ? 0 : d);
  g.attribute("separation", "contact_separation", 0);
  g.attribute("approaching", "contact_approaching", 0, "Int");
  return g.close();
}

// Whether a run has the sidecar at all: the contact nodes' only with two or more fields.
bool has_sidecar(Sidecar which, const std::vector<FrameRecord>& frames) {
  return which != Sidecar::Contact || (!frames.empty() && frames.front().fields > 1);
}
} // namespace

// The sidecars of `h5_path`, each written whole and renamed into place (a reader never meets
// one half written): the frames in their files (`split`: a run in progress) or in `h5_path`.
void OutputFile::write_sidecars(const std::string& h5_path, bool split) const {
  const std::string h5_name = std::filesystem::path(h5_path).filename().string();
  const std::string dir_name = std::filesystem::path(dir_).filename().string();
  for (const Sidecar which : {Sidecar::Particles, Sidecar::Nodes, Sidecar::Contact}) {
    const std::string xmf = xdmf_path(h5_path, which);
    if (!has_sidecar(which, frames_)) { // one of an earlier run of this path that this one has not
      std::error_code ec;
      std::filesystem::remove(xmf, ec);
      continue;
    }
    std::string text = xdmf_header(which, h5_name, material_names_);
    for (const FrameRecord& f : frames_)
      text += xdmf_frame(which, split ? dir_name + "/" + frame_name(f.frame) + ".h5" : h5_name, f,
                         dim_);
    text += kXdmfTrailer;
    const std::string tmp =
        (std::filesystem::path(dir_) / (std::filesystem::path(xmf).filename().string() + ".tmp"))
            .string();
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out << text;
      if (!out.flush())
        throw std::runtime_error("cannot write the ParaView sidecar " + xmf);
    }
    std::filesystem::rename(tmp, xmf);
  }
}

} // namespace smpm
