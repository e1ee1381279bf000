// HDF5 output: CSR matrices read back equal the in-memory operators (exactly), frames hold
// the particle state, and restart loads the last frame.

#include "support.hpp"

#include "hdf5_util.hpp"
#include <sparsempm/output.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace smpm;

namespace {
std::string example_text(const std::string& name) {
  std::ifstream in(std::string(SMPM_EXAMPLES_DIR) + "/" + name);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

SparseRowMatrix read_csr(hid_t group) {
  const Field data = h5::read_doubles(group, "data");
  const std::vector<int> indices = h5::read_ints(group, "indices");
  const std::vector<int> indptr = h5::read_ints(group, "indptr");
  const std::vector<int> shape = h5::read_ints(group, "shape");
  return Eigen::Map<const SparseRowMatrix>(shape[0], shape[1], Index(indices.size()), indptr.data(),
                                           indices.data(), data.data());
}
} // namespace

TEST_CASE("CSR matrices read back from HDF5 equal the in-memory ones", "[output]") {
  RunConfig cfg =
      read_input(example_text("two_disks.toml"), "two_disks.toml", {"output.matrices=true"});
  const std::string path = (std::filesystem::temp_directory_path() / "smpm_csr_test.h5").string();
  {
    OutputFile out(path, cfg);
    out.write_frame(0, cfg.model, cfg.step.shape, true);
  }
  const Operators ops = assemble(cfg.model.grid, cfg.model.particles, cfg.step.shape);
  const SparseRowMatrix mt = SparseRowMatrix(consistent_mass(ops));
  h5::Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  REQUIRE(file);
  h5::Id frame = h5::open_group(file.get(), "matrices/000000");
  auto same = [](const SparseRowMatrix& a, const SparseRowMatrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
           (Eigen::MatrixXd(a) - Eigen::MatrixXd(b)).cwiseAbs().maxCoeff() == 0.0;
  };
  h5::Id S = h5::open_group(frame.get(), "S");
  CHECK(same(read_csr(S.get()), ops.S));
  h5::Id G1 = h5::open_group(frame.get(), "G1");
  CHECK(same(read_csr(G1.get()), ops.G[1]));
  h5::Id M = h5::open_group(frame.get(), "consistent_mass");
  CHECK(same(read_csr(M.get()), mt));
  // The frame's particle state is stored exactly.
  h5::Id parts = h5::open_group(file.get(), "particles/000000");
  CHECK((h5::read_doubles(parts.get(), "X") - cfg.model.particles.X).cwiseAbs().maxCoeff() == 0);
  CHECK((h5::read_doubles(parts.get(), "V") - cfg.model.particles.V).cwiseAbs().maxCoeff() == 0);
  file.reset();
  std::filesystem::remove(path);
  std::filesystem::remove(xdmf_path(path));
}
