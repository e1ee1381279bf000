// SPDX-License-Identifier: BSD-3-Clause
// A capability added from outside the library as one part in one file (step_part.hpp): each
// particle's path length s_p = ∫ |V_p| dt, carried by the particles as a column of their own,
// advanced in a stage hook after the particle update (s_p += |V_p| Δt), with its series, the
// mass-weighted mean Σ M_p s_p / Σ M_p. Registered once (register_step_part), the part is in
// every Stepper of this program: its column is in frames and the layout, a restart continues
// it bit for bit, appends carry it, and the linearised step refuses it by the one rule every
// part answers. No other file of the library names it.

#include "support.hpp"

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

constexpr std::string_view kName = "path_length";

class PathLength final : public StepPart {
public:
  void start(Model& model) override;
  void begin(StepStart& s) override {
    const auto it = s.model.particles.columns.find(kName);
    REQUIRE(it != s.model.particles.columns.end()); // start gave it
    length_ = &it->second;
    s.hooks.push_back(this);
  }
  // s_p += |V_p| Δt with the velocities the particle update gave.
  void after_particles(const StepContext& c, const Field&, ParticleFields& f) override {
    for (Index p = 0; p < f.V.rows(); ++p)
      (*length_)(p, 0) += f.V.row(p).norm() * c.dt;
  }
  std::string not_linearised(const Model&) const override {
    return "the particles' path lengths are not linear in the step's state";
  }

private:
  Field* length_ = nullptr;
};

constexpr ParticleColumn kColumns[] = {
    {.name = kName,
     .range = ColumnRange::NonNegative,
     .absent = [](const Particles& P) { return Field(Field::Zero(P.size(), 1)); },
     .required = [](const Model&) { return true; },
     .why_required = "the run carries path lengths",
     .shape = "N",
     .meaning = "path length of each particle since t = 0",
     .needs = "",
     .xdmf = "path_length"}};

constexpr PartSeries kSeries[] = {{.name = "path_length_mean",
                                   .meaning = "mass-weighted mean path length",
                                   .needs = "the program's part"}};

void series_values(const SeriesInput& in, std::span<double> out) {
  const Particles& P = in.model.particles;
  out[0] = (P.mass.array() * column_values(P, kColumns[0]).col(0).array()).sum() / P.mass.sum();
}

void PathLength::start(Model& model) {
  Particles& P = model.particles;
  if (!has_column(P, kColumns[0])) // none yet: 0
    set_column(P, kColumns[0], Field::Zero(P.size(), 1));
}

// The part's one line: registered before main, so in every Stepper of this program.
const bool registered = [] {
  register_step_part({.make = [](const StepOptions&) -> std::unique_ptr<StepPart> {
                        return std::make_unique<PathLength>();
                      },
                      .columns = kColumns,
                      .series = kSeries,
                      .series_values = series_values});
  return true;
}();

// A block in free flight at V = (0.3, 0.4): |V| = 0.5, no force, so s_p = 0.5 t.
constexpr const char* kInput = R"(
[grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [1.0, 1.0]
cells = [12, 12]

[[material]]
name = "block"
model = "linear"
density = 1.0
youngs = 1.0
poisson = 0.3

[[body]]
material = "block"
region = "box"
min = [2.0, 2.0]
max = [5.0, 5.0]
ppc = [2, 2]
velocity = ["0.3", "0.4"]

[time]
courant = 0.5
end = 4.0

[step]
velocity = "FLIP"

[output]
file = "toy.h5"
every = 1.0
)";

RunConfig config(const std::string& end) {
  return read_input(kInput, "toy.toml", {"time.end=" + end});
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
  return h5::read_doubles(g.get(), std::string(kName).c_str());
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
  REQUIRE(registered);
  RunConfig cfg = config("4.0");
  Model& m = cfg.model;
  Stepper stepper(cfg.step);
  const double dt = 0.1;
  for (int n = 0; n < 20; ++n)
    stepper.step(m, dt);
  // s_p = |V| t = 0.5 × 2.0 for every particle: the block translates rigidly, its velocities
  // change by rounding only (tolerance 1e-12 of s).
  const Field s = column_values(m.particles, kColumns[0]);
  REQUIRE(s.rows() == m.particles.size());
  CHECK((s.array() - 1.0).abs().maxCoeff() < 1e-12);
  double mean = 0;
  const Energies e = energies(m);
  series_values({m, e, stepper.state()}, std::span(&mean, 1));
  CHECK(std::abs(mean - 1.0) < 1e-12);
  // Appending a set that lacks the column gives its particles the column's start values (0).
  Particles more = m.particles;
  more.columns.clear();
  const Index n0 = m.particles.size();
  m.particles.append(more);
  const Field all = column_values(m.particles, kColumns[0]);
  CHECK(all.topRows(n0) == s);
  CHECK(all.bottomRows(n0).isZero(0));
  // resize starts a set without it.
  m.particles.resize(2, m.particles.size());
  CHECK_FALSE(has_column(m.particles, kColumns[0]));
  CHECK(m.particles.columns.count(kName) == 0);
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
  REQUIRE(particle_columns().back().name == kName);
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
