// The XDMF sidecar of a run file, for ParaView (output.hpp).

#include "output_format.hpp"

#include "sparsempm/output.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace smpm {

using namespace detail;

std::string xdmf_path(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xmf");
  return p.string();
}

namespace {
// `text` as XML character data: &, <, >, " and ' as entities (a file name may hold any of them).
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

const char* kXdmfTrailer = "  </Grid>\n </Domain>\n</Xdmf>\n";

std::string xdmf_header() {
  return "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
         "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

// The <Grid> of one frame: particle positions and fields as HDF DataItems of `h5_name`.
std::string xdmf_frame(const std::string& h5_name, int frame, double time, Index N, int d) {
  const char* axes = "xyz";
  const std::string name = frame_name(frame), base = xml_escaped(h5_name) + ":/particles/" + name;
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

} // namespace smpm
