// SPDX-License-Identifier: BSD-3-Clause
// HDF5 output: CSR matrices read back equal the in-memory operators (exactly), frames hold
// the particle state, and restart loads the last frame.

#include "support.hpp"

#include "hdf5_util.hpp"
#include <sparsempm/output.hpp>
#include <sparsempm/run.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
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

TEST_CASE("a run file moved to another OutputFile keeps its state, frames and sidecar",
          "[output]") {
  // OutputFile's move is member-wise (the file handle left closed behind): the moved-to object
  // writes the restart state given before the move, the per-material series of every material,
  // and appends to the sidecar it started.
  RunConfig cfg = read_input(example_text("two_disks.toml"), "two_disks.toml");
  const std::string path = (std::filesystem::temp_directory_path() / "smpm_move_test.h5").string();
  const RunState state{
      .stepper = {.courant_budget = 0.75, .friction_work = 2.5, .viscous_work = 0.125},
      .velocity_change_sum = 3.0};
  {
    OutputFile first(path, cfg);
    first.set_run_state(state);
    first.write_frame(0, cfg.model, cfg.step.shape, false);
    SeriesRow row;
    row.step = 1;
    row.t = 0.5;
    row.materials.assign(5, 1.0); // material_sums of the one 2D material: 1 + 2d
    first.add_series(row);
    OutputFile out(std::move(first));
    cfg.model.time = 0.5;
    cfg.model.step = 1;
    out.write_frame(1, cfg.model, cfg.step.shape, false);
    out.finish(path);
  }
  const RunState back = read_run_state(path, 1);
  CHECK(back.stepper.courant_budget == 0.75);
  CHECK(back.stepper.friction_work == 2.5);
  CHECK(back.stepper.viscous_work == 0.125);
  CHECK(back.velocity_change_sum == 3.0);
  CHECK(run_frames(path) == std::vector<int>{0, 1});
  {
    h5::Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    REQUIRE(file);
    h5::Id series = h5::open_group(file.get(), "series");
    CHECK(h5::read_doubles(series.get(), "material_centre").cols() == 2); // one material, 2D
  }
  std::ifstream xmf(xdmf_path(path));
  std::stringstream text;
  text << xmf.rdbuf();
  CHECK(text.str().find("particles 000000") != std::string::npos);
  CHECK(text.str().find("particles 000001") != std::string::npos);
  std::filesystem::remove(path);
  std::filesystem::remove(xdmf_path(path));
}

TEST_CASE("the restart state of a file without /state comes from its frame and series",
          "[output]") {
  // Files of earlier versions stored periodic FMPM's budget on the frame and the running sums
  // only in the series: read_run_state takes the series row of the frame's step.
  RunConfig cfg = read_input(example_text("two_disks.toml"), "two_disks.toml");
  const std::string path = (std::filesystem::temp_directory_path() / "smpm_old_state.h5").string();
  {
    OutputFile out(path, cfg);
    const std::vector<std::string> parts = detail::SeriesLayout(cfg).parts; // the parts' series
    for (long step = 0; step <= 2; ++step) {
      SeriesRow row;
      row.step = step;
      for (const std::string& name : parts) // the dissipated work: friction and viscosity's
        row.parts.push_back(name == "friction"  ? 10.0 * double(step)
                            : name == "viscous" ? 0.5 * double(step)
                                                : 0.0);
      row.velocity_change_sum = 0.25 * double(step);
      row.materials.assign(5, 1.0);
      out.add_series(row);
    }
    cfg.model.step = 1; // the frame of step 1, written after the rows of steps 0-2
    out.write_frame(0, cfg.model, cfg.step.shape, false);
    out.finish(path); // a file of one piece, as earlier versions wrote
  }
  {
    h5::Id file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    REQUIRE(file);
    REQUIRE(H5Ldelete(file.get(), "state", H5P_DEFAULT) >= 0);
    h5::Id frame = h5::open_group(file.get(), "particles/000000");
    h5::set_attribute(frame.get(), "courant_budget", 1.5);
  }
  const RunState back = read_run_state(path, 0);
  CHECK(back.stepper.courant_budget == 1.5);
  CHECK(back.stepper.friction_work == 10.0);
  CHECK(back.stepper.viscous_work == 0.5);
  CHECK(back.velocity_change_sum == 0.25);
  std::filesystem::remove(path);
  std::filesystem::remove(xdmf_path(path));
}

TEST_CASE("a run file holds the objects of its layout and no others", "[output]") {
  // run_file_layout() states the layout once (output.hpp): every object of a file has its entry,
  // and every entry of the runs the file is one of is found (a 1D bar with its matrices, two
  // blocks in contact).
  const auto dir = std::filesystem::temp_directory_path();
  struct Case {
    const char* example;
    std::vector<std::string> sets;
    std::vector<std::string> when; // the runs this file is one of
  };
  for (const Case& c : std::vector<Case>{
           {"vibrating_bar.toml",
            {"time.end=20", "output.matrices=true"},
            {"", "1D", "output.matrices"}},
           {"two_block_compression.toml", {"time.end=1"}, {"", "contact"}},
           {"shock_split_bar.toml",
            {"time.end=0.0001", "material.left.shear=85500.0", "material.left.yield_stress=140.0"},
            {"", "yield_stress"}}}) {
    CAPTURE(c.example);
    RunConfig cfg = read_input(example_text(c.example), c.example, c.sets);
    const std::string path = (dir / (std::string("smpm_layout_") + c.example + ".h5")).string();
    RunOptions options;
    options.output = path;
    run(cfg, options);
    std::set<std::string> found;
    for (const FileObject& o : walk_run_file(path)) {
      CAPTURE(o.path);
      REQUIRE(o.entry);
      found.insert(o.entry->path);
    }
    for (const LayoutEntry& e : run_file_layout())
      if (std::find(c.when.begin(), c.when.end(), e.when) != c.when.end()) {
        CAPTURE(e.path);
        CHECK(found.count(e.path) == 1);
      }
    std::filesystem::remove(path);
    std::filesystem::remove(xdmf_path(path));
  }
  CHECK(layout_pattern("/matrices/000012/G1/indptr") == "/matrices/<frame>/<matrix>/indptr");
  CHECK(layout_pattern("/state/1234567@courant_budget") == "/state/<frame>@courant_budget");
}

TEST_CASE("a restart continues the plastic state bit for bit", "[output]") {
  // The shock with nickel's shear modulus and J2 plasticity (tests/cli/test_shock.py), run to
  // 0.4 µs in one go and to 0.2 µs then restarted to 0.4 µs: the last frames (positions,
  // stresses, ε̄ᵖ, b̄ᵉ) and the plastic work of the series are the same bits; the frames hold
  // the layout's plastic entries.
  const std::vector<std::string> sets = {
      "material.left.shear=85500.0", "material.right.shear=85500.0",
      "material.left.yield_stress=140.0", "material.right.yield_stress=140.0",
      "output.every=0.0001"};
  const auto dir = std::filesystem::temp_directory_path();
  auto path = [&](const char* name) {
    return (dir / (std::string("smpm_plastic_") + name)).string();
  };
  auto config = [&](const char* end) {
    std::vector<std::string> s = sets;
    s.push_back(std::string("time.end=") + end);
    return read_input(example_text("shock_split_bar.toml"), "shock_split_bar.toml", s);
  };
  for (const char* p : {"full", "half", "rest"}) // what an interrupted run of the test left
    for (const std::string& h5 : {path(p) + ".h5", path(p) + ".partial.h5"}) {
      std::filesystem::remove(h5);
      for (const std::string& x : xdmf_paths(h5))
        std::filesystem::remove(x);
    }
  RunOptions full, half, rest;
  full.output = path("full") + ".h5";
  half.output = path("half") + ".h5";
  rest.output = path("rest") + ".h5";
  rest.restart_from = half.output;
  RunConfig c_full = config("0.0004"), c_half = config("0.0002"), c_rest = config("0.0004");
  run(c_full, full);
  run(c_half, half);
  run(c_rest, rest);
  h5::Id a(H5Fopen(full.output.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  h5::Id b(H5Fopen(rest.output.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  REQUIRE(a);
  REQUIRE(b);
  h5::Id fa = h5::open_group(a.get(), "particles/000004"),
         fb = h5::open_group(b.get(), "particles/000004");
  for (const char* field : {"X", "V", "stress", "plastic_strain", "elastic_cauchy_green"}) {
    CAPTURE(field);
    const Field x = h5::read_doubles(fa.get(), field), y = h5::read_doubles(fb.get(), field);
    REQUIRE(x.rows() == y.rows());
    CHECK(x == y);
  }
  CHECK(h5::read_doubles(fa.get(), "plastic_strain").maxCoeff() > 0);
  h5::Id sa = h5::open_group(a.get(), "series"), sb = h5::open_group(b.get(), "series");
  const Field pa = h5::read_doubles(sa.get(), "plastic"),
              pb = h5::read_doubles(sb.get(), "plastic");
  CHECK(pa(pa.rows() - 1, 0) > 0);
  CHECK(pa(pa.rows() - 1, 0) == pb(pb.rows() - 1, 0));
  for (const char* p : {"full", "half", "rest"}) {
    std::filesystem::remove(path(p) + ".h5");
    for (const std::string& x : xdmf_paths(path(p) + ".h5"))
      std::filesystem::remove(x);
  }
}
