// SPDX-License-Identifier: BSD-3-Clause
// The toy part of toy_part.cpp (a program's capability in one file) in the step, appends,
// frames, the layout, the series, a restart and the linearised step's refusal.

#include "support.hpp"
#include "toy_part.hpp"

#include <sparsempm/output.hpp>
#include <sparsempm/run.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/stability.hpp>
#include <sparsempm/step_part.hpp>

#include "hdf5_util.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <span>

using namespace smpm;

namespace {

// The block of toy.toml: a block in free flight at V = (0.3, 0.4), |V| = 0.5, no force, so
// s_p = 0.5 t.
RunConfig config(const std::string& end) {
  return read_input_file(std::string(SMPM_PARTS_DIR) + "/toy.toml", {"time.end=" + end});
}

Field series_of(const std::string& path, const char* name) {
  h5::Id f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  REQUIRE(f);
  h5::Id s = h5::open_group(f.get(), "series");
  return h5::read_doubles(s.get(), name);
}

Field frame_column(const std::string& path, const char* frame) {
  h5::Id f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  REQUIRE(f);
  h5::Id g = h5::open_group(f.get(), (std::string("particles/") + frame).c_str());
  return h5::read_doubles(g.get(), std::string(toy::path_length.name).c_str());
}

void remove_run(const std::string& path) {
  for (const std::string& p : {path, path + ".partial.h5"}) {
    std::filesystem::remove(p);
    for (const std::string& x : xdmf_paths(p))
      std::filesystem::remove(x);
  }
}

} // namespace

TEST_CASE("a program's part carries its column through the step", "[parts]") {
  REQUIRE(particle_columns().back().name == toy::path_length.name); // registered before main
  RunConfig cfg = config("4.0");
  Model& m = cfg.model;
  Stepper stepper(cfg.step);
  const double dt = 0.1;
  for (int n = 0; n < 20; ++n)
    stepper.step(m, dt);
  // s_p = |V| t = 0.5 × 2.0 for every particle: the block translates rigidly, its velocities
  // change by rounding only (tolerance 1e-12 of s).
  const Field s = column_values(m.particles, toy::path_length);
  REQUIRE(s.rows() == m.particles.size());
  CHECK((s.array() - 1.0).abs().maxCoeff() < 1e-12);
  double mean = 0;
  const Energies e = energies(m);
  toy::path_length_mean({m, e, stepper.state()}, std::span(&mean, 1));
  CHECK(std::abs(mean - 1.0) < 1e-12);
  // Appending a set that lacks the column gives its particles the column's start values (0).
  Particles more = m.particles;
  more.columns.clear();
  const Index n0 = m.particles.size();
  m.particles.append(more);
  const Field all = column_values(m.particles, toy::path_length);
  CHECK(all.topRows(n0) == s);
  CHECK(all.bottomRows(n0).isZero(0));
  // resize starts a set without it.
  m.particles.resize(2, m.particles.size());
  CHECK_FALSE(has_column(m.particles, toy::path_length));
  CHECK(m.particles.columns.count(toy::path_length.name) == 0);
}

TEST_CASE("a program's part is in frames, series and the layout, and a restart continues it",
          "[parts]") {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string full = (dir / "smpm_toy_full.h5").string(),
                    half = (dir / "smpm_toy_half.h5").string(),
                    rest = (dir / "smpm_toy_rest.h5").string();
  for (const std::string& p : {full, half, rest})
    remove_run(p);
  RunOptions o_full, o_half, o_rest;
  o_full.output = full;
  o_half.output = half;
  o_rest.output = rest;
  o_rest.restart_from = half;
  RunConfig c_full = config("4.0"), c_half = config("2.0"), c_rest = config("4.0");
  run(c_full, o_full);
  run(c_half, o_half);
  run(c_rest, o_rest);
  // The last frame (t = 4): s_p = 0.5 × 4 to rounding (1e-12), the same bits after a restart.
  const Field a = frame_column(full, "000004"), b = frame_column(rest, "000004");
  REQUIRE(a.rows() == c_full.model.particles.size());
  CHECK((a.array() - 2.0).abs().maxCoeff() < 1e-12);
  CHECK(a == b);
  // The series: one row per step, 0 at t = 0 and 0.5 t after; the same bits after a restart.
  const Field t = series_of(full, "t"), s = series_of(full, "path_length_mean"),
              s_rest = series_of(rest, "path_length_mean");
  REQUIRE(s.rows() == t.rows());
  CHECK(s(0, 0) == 0);
  CHECK((s - 0.5 * t).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(s == s_rest);
  // Every object of the file has its entry in the layout, the part's among them.
  std::set<std::string> found;
  for (const FileObject& o : walk_run_file(full)) {
    CAPTURE(o.path);
    REQUIRE(o.entry);
    found.insert(o.entry->path);
  }
  CHECK(found.count("/particles/<frame>/path_length") == 1);
  CHECK(found.count("/series/path_length_mean") == 1);
  // The XDMF sidecar shows it to ParaView by its name.
  std::ifstream sidecar(xdmf_path(full));
  const std::string xdmf{std::istreambuf_iterator<char>(sidecar), {}};
  CHECK(xdmf.find("Name=\"path_length\"") != std::string::npos);
  for (const std::string& p : {full, half, rest})
    remove_run(p);
}

TEST_CASE("a part registered after the list was read is refused", "[parts]") {
  // The list is read (particle_columns: by every particle set, frame and layout) before main's
  // tests run here; a late part would be in some Steppers and layouts and not in others.
  REQUIRE(particle_columns().back().name == toy::path_length.name);
  CHECK_THROWS_AS(
      register_step_part({.make = [](const StepOptions&) { return std::unique_ptr<StepPart>(); }}),
      UsageError);
}

TEST_CASE("the linearised step refuses a program's part by the parts' one rule", "[parts]") {
  RunConfig cfg = config("4.0");
  try {
    LinearizedStep T(cfg.model, cfg.step, 0.1);
    FAIL("the linearised step took the part");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()) ==
          "the particles' path lengths are not linear in the step's state");
  }
}
