// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file input.hpp
/// Reading a run from a TOML input file (toml++), with expressions (muparser).
///
/// The schema (tables and keys) is the interface of `smpm run`; examples/vibrating_bar.toml
/// shows every table. Errors are InputError messages of the form
///     file:line: section.key = value: what is wrong
/// and name the nearest valid key when a key is unknown.

#include "sparsempm/model.hpp"
#include "sparsempm/step_options.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace smpm {

/// The [time] table of an input file: the clock of a run.
struct TimeSettings {
  double courant = 0.5; ///< C in Δt = C Δx_min / max(c_wave, max|V_p|) (FMPM 2026 §3.3)
  double end = 0;       ///< simulated end time
  /// Shorten the step before each output frame to land on it (frames at multiples of
  /// output.every); false: constant Courant steps, frames at the first step past each multiple.
  bool land_on_frames = true;
  /// F in Δt ≤ F Δx_min² / D_max, the Fourier number of conduction (heat transport; D = κ/(ρ C_V),
  /// diffusion_time), positive when given; unset (0): default_fourier (0.1, below the smallest
  /// critical Fourier number of transport_stability.hpp's study, 0.229).
  double fourier = 0;
  /// The most steps a run may take (AdvanceOptions::max_steps): a run whose first time step
  /// implies more (with a step more per frame it lands on) is refused before it starts.
  long max_steps = 10'000'000;
};

/// The [output] table of an input file.
struct OutputSettings {
  std::string file;      ///< HDF5 output path
  double every = 0;      ///< simulated time between frames
  bool matrices = false; ///< also write S, G_d and m̃ of every frame in CSR form
  /// The consistent unit system of the input's numbers, stored in the run file (the attribute
  /// `/@units`) for the plotting scripts' axis labels: "SI", "mm-ms-g" (mm, ms, g: MPa, m/s, mJ) or
  /// "none" (unstated: the labels say "input units"). It changes no number.
  std::string units = "none";
};
/// The unit systems output.units names (kUnitSystems[0] is the default, "none").
inline constexpr const char* kUnitSystems[] = {"none", "SI", "mm-ms-g"};

/// Everything `smpm run` needs: the model at t = 0, the step options, the clock and output.
struct RunConfig {
  std::string source;                 ///< input file name (for messages)
  std::string text;                   ///< full input text, with the --set overrides appended
  std::vector<std::string> overrides; ///< the --set section.key=value strings applied
  /// One line for each name of the earlier vocabulary the input used ([scheme] for [step],
  /// step.update for step.scheme), accepted in this release only.
  std::vector<std::string> notes;
  Model model;           ///< the model at t = 0 ([grid], [[material]], bodies, [[bc]], ...)
  StepOptions step;      ///< the options of every step ([step])
  TimeSettings time;     ///< [time]
  OutputSettings output; ///< [output]
};

/// Parses `text` (the contents of the file `source`) after applying `overrides`, each
/// "section.key=value" (value parsed as a TOML value, else taken as a string; arrays of
/// tables are addressed by name or index, e.g. "material.bar.youngs=3"). A file the input names
/// by a relative path (an image body's) is looked for in `file_directories`, in order, then in
/// the directory of `source`. Throws InputError.
RunConfig read_input(const std::string& text, const std::string& source,
                     const std::vector<std::string>& overrides = {},
                     const std::vector<std::string>& file_directories = {});
/// The conditions of [[bc]] tables: velocity conditions and moving walls (Model::bcs), and
/// temperature conditions (Model::temperature_bcs).
struct ConditionTables {
  BoundaryConditions velocity;    ///< fixed = [...], velocity = {...} and wall = {...}
  BoundaryConditions temperature; ///< temperature = value (heat transport)
};
/// Reads [[bc]] tables given as TOML text (as they stand in an input file; the Python module's
/// Model.add_bc writes them) into conditions on `grid`, with the checks and messages of
/// read_input ("source:line: bc.0.wall.depth = ...: ..."). Throws InputError.
ConditionTables read_bc_tables(const std::string& text, const std::string& source,
                               const Grid& grid);
/// Reads [[contact]] tables given as TOML text against the model's materials (by name), as
/// read_input does: the velocity fields of the materials and the laws between them.
Contact read_contact_tables(const std::string& text, const std::string& source,
                            const std::vector<Material>& materials, int dim);

/// One key of the input files: the table of these is the reader's schema (an unknown key is one
/// it does not list, and --set addresses only these) and the site's input reference
/// (`smpm info --keys` prints it as TOML).
struct InputKey {
  std::string table;    ///< "grid", "step", "bc.wall", ...; "" for a table of the top level
  std::string key;      ///< its name in the table
  std::string type;     ///< what it holds: "number", "integer", "string", "array of d numbers", ...
  std::string fallback; ///< its default as TOML text, "required", or a rule ("end / 10")
  bool literal = false; ///< fallback is the TOML text of the value the reader takes
  std::string values;   ///< the values accepted: a range ("> 0") or the choices
  std::string unit;     ///< the dimension of a number ("length", "time", ...); "" if none
  std::string description; ///< what it sets, in one sentence
  std::string bad;         ///< a value the reader refuses, as TOML text ("" for none)
};
/// Every key of the input files, table by table, in the order of the reference.
const std::vector<InputKey>& input_keys();
/// Writes input_keys() as a TOML document, one [[key]] table per key with the fields of
/// InputKey (`smpm info --keys`; the site's build reads it).
void write_input_keys(std::ostream& out);

/// Most frames a run may write (output.every ≥ time.end / kMaxFrames).
inline constexpr long kMaxFrames = 100000;
/// Largest input file accepted (16 MiB).
inline constexpr long long kMaxInputBytes = 16LL << 20;
/// Reads and parses a file; throws InputError unless it is a regular file of at most
/// kMaxInputBytes that can be read.
RunConfig read_input_file(const std::string& path, const std::vector<std::string>& overrides = {});

} // namespace smpm
