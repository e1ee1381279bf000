// SPDX-License-Identifier: BSD-3-Clause
// Reading runs from TOML: the example input round trip, --set overrides, and the one-line
// messages for each class of bad input (file, line, key, value).

#include "support.hpp"

#include <sparsempm/input.hpp>

#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

using namespace smpm;
using smpm::test::approx;

namespace {
std::string example(const std::string& name) {
  std::ifstream in(std::string(SMPM_EXAMPLES_DIR) + "/" + name);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
std::string replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}
// "file:line:" of the first line of `text` containing `needle`.
std::string at(const std::string& text, const std::string& needle) {
  const size_t pos = text.find(needle);
  REQUIRE(pos != std::string::npos);
  return "bar.toml:" +
         std::to_string(1 + std::count(text.begin(), text.begin() + long(pos), '\n')) + ": ";
}
std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    (void)read_input(text, "bar.toml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
} // namespace

TEST_CASE("the vibrating bar input reads back as the FMPM 2026 §3.3 set-up", "[input]") {
  const RunConfig cfg = read_input(example("vibrating_bar.toml"), "vibrating_bar.toml");
  const Model& m = cfg.model;
  CHECK(m.grid.dim() == 1);
  CHECK(m.grid.num_nodes() == 49);
  CHECK(m.grid.origin(0) == -2.0);
  REQUIRE(m.particles.size() == 80); // 40 cells × 2 per cell
  CHECK(m.particles.mass.sum() == approx(0.5 * 40, 1e-12));
  for (Index p = 0; p < m.particles.size(); ++p) // v = 0.16 sin(πX/80), evaluated by muparser
    CHECK(m.particles.V(p, 0) ==
          approx(0.16 * std::sin(std::numbers::pi * m.particles.X(p, 0) / 80), 1e-15));
  REQUIRE(m.bcs.conditions.size() == 1);
  CHECK(m.bcs.conditions[0].nodes == std::vector<Index>{2}); // the node at x = 0
  CHECK(m.materials[0].youngs == 2.0);
  CHECK(cfg.time.courant == 0.5);
  CHECK(cfg.time.end == 400.0);
  CHECK(cfg.step.shape == Shape::CPDI);
  CHECK(cfg.step.velocity == VelocityUpdate::FLIP);
  CHECK(cfg.output.file == "vibrating_bar.h5");
  CHECK(cfg.output.every == 10.0);
  CHECK(cfg.text == example("vibrating_bar.toml"));
}

TEST_CASE("overrides given with --set change scalars, named materials and absent tables",
          "[input]") {
  const RunConfig cfg =
      read_input(example("vibrating_bar.toml"), "vibrating_bar.toml",
                 {"time.courant=0.3", "material.bar.youngs=3", "step.velocity=PIC",
                  "output.matrices=true", "loads.gravity=[-1.0]"});
  CHECK(cfg.time.courant == 0.3);
  CHECK(cfg.model.materials[0].youngs == 3.0);
  CHECK(cfg.step.velocity == VelocityUpdate::PIC);
  CHECK(cfg.output.matrices);
  CHECK(cfg.model.gravity[0] == -1.0);
  CHECK(cfg.text.find("#   time.courant=0.3") != std::string::npos); // recorded in the input
  CHECK_THROWS_WITH(read_input(example("vibrating_bar.toml"), "b.toml", {"time.courrant=0.3"}),
                    Catch::Contains("did you mean 'courant'"));
  CHECK_THROWS_WITH(
      read_input(example("vibrating_bar.toml"), "b.toml", {"material.steel.youngs=1"}),
      Catch::Contains("no [[material]] named or numbered 'steel'"));
}

TEST_CASE("scheme options: position alpha, deformation update, exact solver, frame landing",
          "[input]") {
  const std::string bar = example("vibrating_bar.toml");
  // The example sets α = 1; without the key α follows the velocity update (1 FLIP, ½ FMPM).
  CHECK(read_input(bar, "bar.toml").step.position_alpha == 1.0);
  const RunConfig unset =
      read_input(replace(bar, "position_alpha = 1.0", ""), "bar.toml",
                 {"step.velocity=FMPM", "step.order=4", "step.deformation=exponential",
                  "step.exact_mass_cutoff=0.05", "time.land_on_frames=false"});
  CHECK(!unset.step.position_alpha);
  CHECK(position_alpha(unset.step) == 0.5);
  CHECK(unset.step.deformation == DeformationUpdate::Exponential);
  CHECK(unset.step.exact_solver); // made for every input: analyses may add an exact row
  CHECK(!unset.time.land_on_frames);
  CHECK_THAT(error_of(bar, {"step.deformation=cubic"}),
             Catch::Contains("step.deformation") && Catch::Contains("linear | exponential"));
  CHECK_THAT(error_of(bar, {"step.exact_mass_cutoff=1.5"}),
             Catch::Contains("step.exact_mass_cutoff = 1.5: must lie in [0, 1)"));
  CHECK_THAT(error_of(bar, {"step.exact_regularization=2"}),
             Catch::Contains("step.exact_regularization = 2: must lie in [0, 1]"));
  // The comparisons' settings (Buzzi §5.5; contact 2020's "LR Once"), default the methods'.
  CHECK(unset.step.bc_ordering == BCOrdering::Correct);
  CHECK(unset.step.contact_corrections == ContactCorrections::Twice);
  const RunConfig compared =
      read_input(bar, "bar.toml", {"step.bc_ordering=improper", "step.contact_corrections=once"});
  CHECK(compared.step.bc_ordering == BCOrdering::Improper);
  CHECK(compared.step.contact_corrections == ContactCorrections::Once);
  CHECK_THAT(error_of(bar, {"step.bc_ordering=wrong"}),
             Catch::Contains("step.bc_ordering") && Catch::Contains("correct | improper"));
  CHECK_THAT(error_of(bar, {"step.contact_corrections=thrice"}),
             Catch::Contains("step.contact_corrections") && Catch::Contains("twice | once"));
}

TEST_CASE("the step options' limits are the library's, reported at the line of the key",
          "[input]") {
  // validate(StepOptions) holds every limit (step_options.hpp); the reader maps the option it
  // names to the line that set it, so a value the library refuses is refused here in its words.
  const std::string bar = example("vibrating_bar.toml");
  const std::string alpha = replace(bar, "position_alpha = 1.0", "position_alpha = 1.5");
  CHECK_THAT(error_of(alpha), Catch::StartsWith(at(alpha, "position_alpha = 1.5") +
                                                "step.position_alpha = 1.5: must lie in [0, 1]"));
  for (const auto& [set, message] : std::vector<std::pair<std::string, std::string>>{
           {"step.order=0", "step.order = 0: must be an integer from 1 to 100000"},
           {"step.order=100001", "step.order = 100001: must be an integer from 1 to 100000"},
           {"step.blend_every=0", "step.blend_every = 0: must be an integer from 1 to 100000"},
           {"step.blend_alpha=1.5", "step.blend_alpha = 1.5: must lie in [0, 1]"},
           {"step.periodic_cx=-1", "step.periodic_cx = -1: must be non-negative"},
           {"step.dynamic_limit=-1", "step.dynamic_limit = -1: must be non-negative"}}) {
    std::vector<std::string> sets{"step.velocity=FMPM", set};
    if (set.rfind("step.order", 0) != 0)
      sets.push_back("step.order=4");
    CHECK_THAT(error_of(bar, sets), Catch::Contains(message));
  }
  // C_X = 0 is the library's "FMPM on every step", as in StepOptions.
  CHECK(read_input(bar, "bar.toml", {"step.periodic_cx=0"}).step.periodic_cx == 0);
  try {
    validate(StepOptions{.fmpm = {.order = 0}});
    FAIL("order 0 accepted");
  } catch (const OptionError& e) {
    CHECK(e.key() == "order");
    CHECK(std::string(e.what()) == "order = 0: must be an integer from 1 to 100000");
  }
}

TEST_CASE("step.xpic_contact_term reads as step.xpic_contact, in the file and in --set",
          "[input]") {
  // true: the closed form with contact 2020 Eq. (37)'s term ("term"); false: without ("none").
  const std::string bar = example("vibrating_bar.toml");
  const std::string file = replace(bar, "[step]", "[step]\nxpic_contact_term = false");
  const RunConfig in_file = read_input(file, "bar.toml", {});
  CHECK(in_file.step.xpic_contact == XpicContact::None);
  REQUIRE(in_file.notes.size() == 1);
  CHECK_THAT(in_file.notes[0], Catch::Contains("step.xpic_contact = \"none\""));
  const RunConfig by_set = read_input(bar, "bar.toml", {"step.xpic_contact_term=true"});
  CHECK(by_set.step.xpic_contact == XpicContact::Term);
  REQUIRE(by_set.notes.size() == 1);
  CHECK_THAT(by_set.notes[0], Catch::Contains("--set step.xpic_contact=\"term\""));
  CHECK(read_input(bar, "bar.toml", {}).step.xpic_contact == XpicContact::Increments);
  const std::string both = replace(file, "[step]", "[step]\nxpic_contact = \"term\"");
  CHECK_THAT(error_of(both), Catch::Contains("earlier name of step.xpic_contact"));
}

TEST_CASE("the earlier names [scheme], update and --set scheme.* read as [step]", "[input]") {
  // One release of aliases (docs/guide/vocabulary.md): the same options, with a note each.
  const std::string bar = example("vibrating_bar.toml");
  const std::string old =
      replace(replace(bar, "[step]", "[scheme]"), "scheme = \"USL\"", "update = \"USF\"");
  const RunConfig earlier = read_input(old, "bar.toml", {"scheme.velocity=FMPM", "scheme.order=3"});
  const RunConfig current = read_input(replace(bar, "scheme = \"USL\"", "scheme = \"USF\""),
                                       "bar.toml", {"step.velocity=FMPM", "step.order=3"});
  CHECK(earlier.step.scheme == UpdateScheme::USF);
  CHECK(earlier.step.velocity == VelocityUpdate::FMPM);
  CHECK(earlier.step.fmpm.order == 3);
  CHECK(earlier.step.shape == current.step.shape);
  CHECK(position_alpha(earlier.step) == position_alpha(current.step));
  REQUIRE(earlier.notes.size() == 4); // [scheme], update and the two overrides
  CHECK_THAT(earlier.notes[0], Catch::Contains("[scheme] is now [step]"));
  CHECK_THAT(earlier.notes[1], Catch::Contains("step.update is now step.scheme"));
  CHECK_THAT(earlier.notes[2], Catch::Contains("--set scheme.velocity is now --set step.velocity"));
  CHECK(current.notes.empty());
  // The lines of the renamed table stay those of the file.
  const std::string bad = replace(old, "position_alpha = 1.0", "position_alpha = 2.0");
  CHECK_THAT(error_of(bad), Catch::StartsWith(at(bad, "position_alpha = 2.0") +
                                              "step.position_alpha = 2.0: must lie in [0, 1]"));
  // Both spellings at once are refused, at the line of the earlier one.
  const std::string both = old + "\n[step]\nvelocity = \"PIC\"\n";
  CHECK_THAT(error_of(both),
             Catch::StartsWith(at(both, "[scheme]") + "[scheme] is the earlier name of [step]"));
}

TEST_CASE("each class of bad input has a one-line message with file, line and key", "[input]") {
  const std::string bar = example("vibrating_bar.toml");
  // Unknown key, with the nearest valid key suggested and the line of the entry.
  CHECK_THAT(error_of(replace(bar, "cell_size = [1.0]", "cell_sizes = [1.0]")),
             Catch::StartsWith(at(bar, "cell_size") + "grid.cell_sizes") &&
                 Catch::Contains("unknown key (did you mean 'cell_size'?)"));
  // Missing required key.
  CHECK_THAT(error_of(replace(bar, "end = 400.0", "")),
             Catch::Contains("bar.toml: time.end: missing required key"));
  // Wrong type.
  CHECK_THAT(
      error_of(replace(bar, "density = 0.5", "density = \"heavy\"")),
      Catch::Contains(at(bar, "density") + "material.bar.density = 'heavy': expected a number"));
  // Non-positive density, modulus, cell size, Courant number.
  CHECK_THAT(error_of(replace(bar, "density = 0.5", "density = 0.0")),
             Catch::Contains(at(bar, "density") + "material.bar.density = 0.0: must be positive"));
  CHECK_THAT(error_of(replace(bar, "youngs = 2.0", "youngs = -2.0")),
             Catch::Contains(at(bar, "youngs") + "material.bar.youngs = -2.0: must be positive"));
  CHECK_THAT(error_of(replace(bar, "cell_size = [1.0]", "cell_size = [0.0]")),
             Catch::Contains("grid.cell_size: every cell size must be positive"));
  CHECK_THAT(error_of(replace(bar, "courant = 0.5 ", "courant = 0.0 ")),
             Catch::Contains(at(bar, "courant =") + "time.courant = 0.0: must be positive"));
  // Particles outside the grid.
  CHECK_THAT(error_of(replace(bar, "max = [40.0]", "max = [60.0]")),
             Catch::Contains("body.0.min/max") && Catch::Contains("particles outside the grid"));
  // An expression that does not parse.
  CHECK_THAT(error_of(replace(bar, "0.16*sin(pi*X/80)", "0.16*sin(pi*X/80")),
             Catch::Contains(at(bar, "velocity = [") + "body.0.velocity") &&
                 Catch::Contains("cannot parse"));
  // A TOML syntax error names its line.
  CHECK_THAT(error_of(replace(bar, "dim = 1", "dim = = 1")), Catch::StartsWith(at(bar, "dim = 1")));
  // Unknown choices name the valid ones.
  CHECK_THAT(error_of(replace(bar, "shape = \"cpdi\"", "shape = \"cpdx\"")),
             Catch::Contains("step.shape = 'cpdx'") && Catch::Contains("cpdi"));
  // Non-ASCII characters are allowed in comments and strings only (TOML), and rejected with
  // their line before the parser sees them.
  CHECK(read_input(replace(bar, "file = \"vibrating_bar.h5\"", "file = \"stab_ü.h5\" # ρ, 漢字"),
                   "bar.toml", {"step.shape=\"cpdi\" "})
            .output.file == "stab_ü.h5");
  CHECK_THAT(error_of(replace(bar, "density = 0.5", "density = 0.5 ρ")),
             Catch::StartsWith(at(bar, "density")) && Catch::Contains("non-ASCII"));
  CHECK_THAT(
      error_of(replace(bar, "file = \"vibrating_bar.h5\"", "file = \"\"\"a \\\n  ü.h5\"\"\"")),
      Catch::Contains("multi-line strings"));
  CHECK_THAT(error_of(replace(bar, "origin = [-2.0]", "origin = [-2.0\"\"=\"\u00fc\"]")),
             Catch::StartsWith(at(bar, "origin")) && Catch::Contains("non-ASCII"));
  // Every message is one line.
  CHECK(error_of(replace(bar, "end = 400.0", "")).find('\n') == std::string::npos);
}

TEST_CASE("heat transport: material, body, condition and step keys, and their messages",
          "[input][transport]") {
  const std::string bar = example("vibrating_bar.toml");
  // The bar with conduction: C_V, κ, T_ref on the material, a temperature expression on the
  // body, a temperature held at x = 0, FMPM(3) transport, F = 0.05.
  std::string heat = replace(bar, "poisson = 0.0",
                             "poisson = 0.0\nheat_capacity = 2.0\nconductivity = 0.5\n"
                             "reference_temperature = 290.0");
  heat = replace(heat, "ppc = [2]", "ppc = [2]\ntemperature = \"300 + X\"\nheat_source = 0.25");
  heat = replace(heat, "[time]",
                 "[[bc]]\nplane = { axis = \"x\", at = 40.0 }\ntemperature = 350.0\n\n[time]");
  heat = replace(heat, "\n[output]", "transport = \"FMPM\"\ntransport_order = 3\n\n[output]");
  heat = replace(heat, "end = 400.0", "end = 400.0\nfourier = 0.05");
  const RunConfig cfg = read_input(heat, "bar.toml");
  const Material& m = cfg.model.materials[0];
  CHECK(m.heat_capacity == 2.0);
  CHECK(m.conductivity == 0.5);
  CHECK(m.reference_temperature == 290.0);
  CHECK(cfg.step.transport.update == TransportUpdate::FMPM);
  CHECK(cfg.step.transport.order == 3);
  CHECK(cfg.time.fourier == 0.05);
  const Particles& P = cfg.model.particles;
  REQUIRE(P.temperature.size() == P.size());
  for (Index p = 0; p < P.size(); ++p)
    CHECK(P.temperature[p] == approx(300 + P.X(p, 0), 1e-12));
  CHECK(P.heat_source.size() == P.size());
  CHECK(P.heat_source.maxCoeff() == 0.25);
  REQUIRE(cfg.model.temperature_bcs.conditions.size() == 1);
  CHECK(cfg.model.temperature_bcs.conditions[0].nodes == std::vector<Index>{42}); // x = 40
  CHECK(cfg.model.temperature_bcs.conditions[0].value_at(0, Eigen::Vector3d::Zero()) == 350.0);
  CHECK(cfg.model.bcs.conditions.size() == 1); // the velocity condition stays apart
  // Without a temperature on the body: the material's reference temperature.
  const RunConfig plain = read_input(replace(heat, "temperature = \"300 + X\"\n", ""), "bar.toml");
  CHECK(plain.model.particles.temperature.maxCoeff() == 290.0);
  CHECK(plain.model.particles.temperature.minCoeff() == 290.0);

  // Messages: one line naming the file, line, key and value.
  CHECK_THAT(error_of(replace(heat, "heat_capacity = 2.0\n", "")),
             Catch::Contains(at(heat, "[[material]]") +
                             "material.bar.heat_capacity: is required with step.transport = FMPM"));
  CHECK_THAT(error_of(replace(heat, "reference_temperature = 290.0", "reference_temperature = 0")),
             Catch::Contains("material.bar.reference_temperature = 0: must be positive"));
  CHECK_THAT(error_of(replace(heat, "conductivity = 0.5", "conductivity = -0.5")),
             Catch::Contains("material.bar.conductivity = -0.5: must be non-negative"));
  CHECK_THAT(error_of(replace(heat, "\"300 + X\"", "\"300 - 10*X\"")),
             Catch::Contains("body.0.temperature") && Catch::Contains("at particle") &&
                 Catch::Contains("positive"));
  CHECK_THAT(error_of(replace(heat, "temperature = 350.0", "temperature = -5.0")),
             Catch::Contains("bc.1.temperature = -5.0: must be positive"));
  CHECK_THAT(error_of(replace(heat, "transport_order = 3", "transport_order = -1")),
             Catch::Contains("step.transport_order = -1"));
  CHECK_THAT(error_of(replace(heat, "transport_order = 3\n", "")),
             Catch::Contains("step.transport_order") && Catch::Contains("with transport = FMPM"));
  CHECK_THAT(error_of(replace(heat, "transport = \"FMPM\"", "transport = \"FLIP\"")),
             Catch::Contains("step.transport = 'FLIP'") && Catch::Contains("lumped"));
  CHECK_THAT(error_of(replace(heat, "fourier = 0.05", "fourier = 0.0")),
             Catch::Contains("time.fourier = 0.0: must be positive"));
  // A temperature asked for without transport: the forgotten step.transport is named.
  const std::string off = replace(heat, "transport = \"FMPM\"\ntransport_order = 3\n", "");
  CHECK_THAT(error_of(off),
             Catch::Contains("body.0.temperature") && Catch::Contains("needs step.transport"));
  CHECK_THAT(error_of(replace(off, "temperature = \"300 + X\"\nheat_source = 0.25", "")),
             Catch::Contains("bc.1.temperature: needs step.transport"));
  // A node held by two temperature conditions; a table with a temperature and velocities.
  CHECK_THAT(error_of(replace(heat, "[time]",
                              "[[bc]]\nbox = { min = [39.0], max = [41.0] }\n"
                              "temperature = 360.0\n\n[time]")),
             Catch::Contains("[[bc]]: node 42 is held by both 'bc.1.temperature' and "
                             "'bc.2.temperature'"));
  CHECK_THAT(error_of(replace(heat, "temperature = 350.0", "temperature = 350.0\nfixed = [\"x\"]")),
             Catch::Contains("bc.1.fixed") && Catch::Contains("separate tables"));
}

TEST_CASE("a bitmap body: the particles of a PNG's dark pixels, one material per grey range",
          "[input]") {
  // NairnMPM's BMPRegion: a 128 × 128 PNG (written here with libpng) holding a black disk of
  // radius R = 40 pixels centred in the image, a grey square (level 128) in its top-left
  // corner, white elsewhere; pixel_size s = 0.1, the image's lower-left corner at (1, 1), 2 × 2
  // particles per cell of 0.5. The disk body (levels [0, 100]) holds π R² s² of area within one
  // pixel of the perimeter (|A − π R² s²| ≤ 2π R s²) and has its centroid at the disk's centre
  // within half a pixel; the square (levels [101, 200], a second material, from the same image)
  // holds 10 × 10 pixels of area, its own particles only.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("smpm_image_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const int n = 128;
  const double R = 40, s = 0.1;
  std::vector<png_byte> pixels(size_t(n * n), 255);
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const double u = col + 0.5 - 64, v = row + 0.5 - 64;
      if (u * u + v * v <= R * R)
        pixels[size_t(row * n + col)] = 0;
      else if (row < 10 && col < 10)
        pixels[size_t(row * n + col)] = 128;
    }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = n;
  image.height = n;
  image.format = PNG_FORMAT_GRAY;
  REQUIRE(
      png_image_write_to_file(&image, (dir / "disk.png").c_str(), 0, pixels.data(), 0, nullptr));
  const std::string head = R"([grid]
dim = 2
origin = [0.0, 0.0]
cell_size = [0.5, 0.5]
cells = [32, 32]
[[material]]
name = "a"
model = "neo-hookean"
density = 2.0
youngs = 100.0
poisson = 0.3
[[material]]
name = "b"
model = "neo-hookean"
density = 1.0
youngs = 100.0
poisson = 0.3
[time]
end = 1.0
)";
  const std::string disk = R"([[body]]
material = "a"
region = "image"
image = "disk.png"
pixel_size = 0.1
origin = [1.0, 1.0]
levels = [0, 100]
ppc = [2, 2]
)";
  // The same image, the grey levels of the square, material b.
  const std::string square =
      replace(replace(disk, "\"a\"", "\"b\""), "levels = [0, 100]", "levels = [101, 200]");
  // The image's path is relative to the input file.
  const std::string source = (dir / "in.toml").string();
  const RunConfig cfg = read_input(head + disk + square, source, {});
  const Particles& P = cfg.model.particles;
  double area[2] = {0, 0};
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (Index p = 0; p < P.size(); ++p) {
    const int m = P.material[p];
    REQUIRE((m == 0 || m == 1));
    area[m] += P.volume0[p];
    if (m == 0)
      centre += P.volume0[p] * P.X.row(p).head<2>().transpose();
  }
  centre /= area[0];
  const double disk_area = std::numbers::pi * R * R * s * s;
  CHECK(std::abs(area[0] - disk_area) <= 2 * std::numbers::pi * R * s * s);
  CHECK((centre - Eigen::Vector2d(1 + 6.4, 1 + 6.4)).norm() <= 0.5 * s);
  CHECK(std::abs(area[1] - 100 * s * s) <= 4 * 10 * s * s); // the square, within a pixel
  // The square is the image's top-left corner: y near the top, x near the left.
  for (Index p = 0; p < P.size(); ++p)
    if (P.material[p] == 1)
      CHECK((P.X(p, 0) < 1 + 10 * s + 0.25 && P.X(p, 1) > 1 + (n - 10) * s - 0.25));
  // Bad input, in one line naming the key: an unreadable file, a 1D or 3D grid, levels out of
  // range, an image reaching outside the grid.
  const auto error = [&](const std::string& text) {
    try {
      (void)read_input(text, source, {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(error(head + replace(disk, "disk.png", "none.png")),
             Catch::Contains("body.0.image = 'none.png': cannot read") &&
                 Catch::Contains("none.png"));
  CHECK_THAT(error(head + replace(disk, "levels = [0, 100]", "levels = [0, 300]")),
             Catch::Contains("body.0.levels") && Catch::Contains("0 <= lo <= hi <= 255"));
  CHECK_THAT(error(head + replace(disk, "origin = [1.0, 1.0]", "origin = [5.0, 5.0]")),
             Catch::Contains("body.0.image") &&
                 Catch::Contains("reaches (17.8, 17.8), outside the grid"));
  const std::string head3 =
      replace(replace(replace(replace(head, "dim = 2", "dim = 3"), "[0.0, 0.0]", "[0.0, 0.0, 0.0]"),
                      "cells = [32, 32]", "cells = [32, 32, 2]"),
              "cell_size = [0.5, 0.5]", "cell_size = [0.5, 0.5, 0.5]");
  CHECK_THAT(error(head3 + replace(replace(disk, "ppc = [2, 2]", "ppc = [2, 2, 2]"),
                                   "origin = [1.0, 1.0]", "origin = [1.0, 1.0, 0.0]")),
             Catch::Contains("an image body needs a 2D grid"));
  CHECK(error(head + replace(disk, "disk.png", "none.png")).find('\n') == std::string::npos);
  std::filesystem::remove_all(dir);
}
