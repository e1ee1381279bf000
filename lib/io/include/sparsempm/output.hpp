// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file output.hpp
/// HDF5 output of a run, one file per run, with XDMF sidecars for ParaView. Its layout is
/// stated once, in run_file_layout() (frames named 000000, 000001, …): the writer makes those
/// objects and no others (a test walks a file against it), `smpm info --layout` prints it and
/// the site's run-file page shows that print. While the run is in progress its frames are files of
/// their own, each complete once named (OutputFile), so a kill at any instant keeps every completed
/// frame.

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/input.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/step_preparation.hpp"

#include <array>
#include <future>
#include <string>
#include <vector>

namespace smpm {

/// One object of a run file's layout: its path (`<frame>` stands for every frame's name,
/// `<matrix>` for S, G0, G1, G2 and consistent_mass, "@name" for an attribute), its shape (N
/// particles, na nodes with mass, nc contact nodes, d dimensions), what it holds, and the runs
/// that write it ("": every run).
struct LayoutEntry {
  const char* path;  ///< e.g. "/particles/<frame>/X", "/particles/<frame>@time"
  const char* shape; ///< e.g. "N x d", "na", "scalar", "text"
  const char* what;  ///< what it holds
  const char* when;  ///< the runs that write it ("1D", "contact", ...; "": every run)
};
/// The layout of a run file.
const std::vector<LayoutEntry>& run_file_layout();
/// The layout path of an object's path ("/particles/000012/X" → "/particles/<frame>/X").
std::string layout_pattern(const std::string& path);
/// The layout entry of an object's path, or nullptr for an object the layout does not name.
const LayoutEntry* layout_entry(const std::string& path);

/// An object found in a run file: its path, its shape (datasets) and its layout entry.
struct FileObject {
  std::string path;                   ///< its path in the file ("@name": an attribute)
  std::string shape;                  ///< a dataset's dimensions, as the layout writes them
  const LayoutEntry* entry = nullptr; ///< its layout entry; null when the layout lacks it
};
/// The root's attributes, the series and the last complete frame of a run file (every frame
/// holds the same objects), walked with HDF5 (H5Ovisit). Throws InputError for a file that is
/// not a run.
std::vector<FileObject> walk_run_file(const std::string& path);

/// One row of the energy series.
struct SeriesRow {
  long step = 0; ///< the steps taken (0: the state at t = 0)
  double t = 0;  ///< the time after them
  Energies e;    ///< the energies and momentum of the particles
  /// √((1/N) Σ_p |V_p(t) − V_p(0)|²): the per-step RMS of FMPM 2026 §3.1's velocity error,
  /// measured against the velocities at t = 0.
  double velocity_change = 0;
  double velocity_change_sum = 0; ///< its running sum over the steps (⟨error⟩ = sum / N_s)
  double fmpm_order = 0;          ///< the FMPM(k) loop's order ℓ reached on the step (0: none)
  std::vector<double> materials;  ///< material_sums: mass, momentum, centre of each material
  /// The reaction force of each velocity condition along its direction (Stepper::reactions; 0
  /// at t = 0), in the order of Model::bcs; empty without conditions.
  std::vector<double> reactions;
  /// The series of the run's parts (series_parts: the work of the artificial viscosity, plastic
  /// flow and friction, heat transport's thermal sums, a program's parts'), in the order of
  /// SeriesLayout::parts (the writer's; read_run leaves it empty).
  std::vector<double> parts;
};

/// What a restart continues besides the particles and clock of a frame: the Stepper's state
/// and the running sum of the velocity change (SeriesRow::velocity_change_sum). Stored with
/// every frame (`/state/<frame>`).
struct RunState {
  StepperState stepper;           ///< Stepper::state() at the frame
  double velocity_change_sum = 0; ///< SeriesRow::velocity_change_sum at the frame
};

namespace detail {
class RunReader;
/// The series of a run file (/series): the run's dimension, materials, whether it has heat
/// conditions of its reactions and the series of its parts.
struct SeriesLayout {
  int dim = 1;                        ///< d
  int materials = 0;                  ///< the materials of the per-material series
  std::vector<std::string> reactions; ///< the reaction columns' conditions (reaction_labels)
  std::vector<std::string> parts;     ///< the series of the run's parts (series_parts)
  SeriesLayout() = default;
  /// The series of a run of `cfg`.
  explicit SeriesLayout(const RunConfig& cfg);
  /// The name and width (0: one column) of every series, in the file's order.
  std::vector<std::pair<std::string, size_t>> columns() const;
};
} // namespace detail

/// A run's files while it is written, and their assembly into one file when it completes.
///
/// A run in progress is an index file (`path`, e.g. run.partial.h5) beside a directory of frame
/// files (run.partial.frames/000012.h5, one per frame, each holding the frame's objects at the
/// paths of run_file_layout() and the series rows since the frame before). Every file is
/// written under a temporary name, synced and renamed into place, so that a kill or a power
/// loss at any instant leaves each name whole or absent: the frames named in the directory are
/// the completed ones. A frame's sync and rename run on a second thread (no HDF5 call there)
/// while the run goes on; the next frame, a stop or the end waits for them. The index (the run's
/// input and status, external links to the frames for h5py, the series) and the XDMF sidecars are
/// replaced the same way after a frame, as often as their own cost allows (at most a fifth of the
/// run's time), and always when the status changes. finish() assembles the frames into one file of
/// the layout and moves it into place.
class OutputFile {
public:
  /// Starts the run `cfg` at `path` (its index; the frames directory beside it is made anew).
  /// Throws InputError naming the path when it cannot be created.
  OutputFile(const std::string& path, const RunConfig& cfg);
  /// Continues the run stored in `restart_from` (either layout, complete or not) at `path`:
  /// the state of its last complete frame is loaded into `cfg.model` (the rest of `cfg` must
  /// come from the run's stored input), later frames and series rows are dropped, and
  /// `next_frame` is set to the frame that follows. `restart_from` is written only when it is
  /// `path` itself (a run in progress continued in place); a file of one piece there (a run of
  /// an earlier version) is replaced, in one rename, by the index of its frames.
  static OutputFile reopen(const std::string& path, const std::string& restart_from, RunConfig& cfg,
                           int& next_frame);
  /// Names in the index the frames written since it was last written (best effort).
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  /// Takes over the run's files (the moved-from object names no frame).
  OutputFile(OutputFile&&) noexcept = default;

  /// Buffers one row of the series (written with the next frame).
  void add_series(const SeriesRow& row) { pending_.push_back(row); }
  /// Writes frame `frame` of the model (and its matrices when asked) with the buffered series
  /// rows as one frame file. The grid fields and contact nodes come from `prepared`, the
  /// preparation of the step that starts at this frame (Stepper::prepare), when given;
  /// otherwise (and for the matrices on the whole grid) from prepare_step on the frame.
  void write_frame(int frame, const Model& model, Shape shape, bool matrices,
                   const StepPreparation* prepared = nullptr);
  /// Records the run's end (the failure or interruption) with the series rows buffered since
  /// the last frame in the index. Does not throw: it is called while another failure is being
  /// reported (on a full disk the index keeps its status "running").
  void set_status(const std::string& status) noexcept;
  /// Marks the run completed, assembles its frames into one file moved (with fresh sidecars)
  /// to `target`, replacing what was there, and removes the index, its sidecars and frames.
  void finish(const std::string& target);
  /// Removes the index, its sidecars and frames: for a run whose first frame could not be
  /// written (nothing to keep, and no file that looks like a run). Does not throw.
  void discard() noexcept;
  /// The state a restart needs, stored with the frames written from now on.
  void set_run_state(const RunState& state) { state_ = state; }
  /// The path of the index (a run's partial twin).
  const std::string& path() const { return path_; }

  /// What the sidecars need of a written frame: its number, time and point counts (contact: 0
  /// when the frame has no contact node or the run one velocity field), and whether its
  /// particles have det F (files of earlier versions do not) and internal energy.
  struct FrameRecord {
    int frame = 0;   ///< the frame's number
    double time = 0; ///< its time t
    /// \var particles
    /// N, its particles
    /// \var nodes
    /// na, its nodes with mass (0 when a file of an earlier version lacks their positions)
    /// \var contact
    /// nc, its contact nodes (0 without contact nodes or with one velocity field)
    Index particles = 0, nodes = 0, contact = 0;
    int fields = 1; ///< n_f, the run's velocity fields
    /// Whether the particles have J = det F (files of earlier versions do not).
    bool has_J = true;
    /// The names of the parts' particle columns (particle_columns) the frame holds.
    std::vector<std::string> columns;
    bool has_matrices = false; ///< whether the frame has its matrices
  };

private:
  OutputFile() = default;
  void start(const RunConfig& cfg);
  void restore_frames(detail::RunReader& source, int last, bool in_place);
  void write_restart_index(const std::string& path, const std::vector<Field>& base, Index rows);
  // Writes the index and the sidecars again (`force`: now; else when their cost allows), with
  // the series rows since the last frame when `tail` (a stop, the end).
  void publish(bool force, bool tail = false);
  // Waits for the frame being synced and named, and adds it to the frames.
  void settle();
  void write_index(long file, bool tail);
  void write_sidecars(const std::string& h5_path, bool split) const;
  static FrameRecord record_of(long file, int frame);
  std::string path_, dir_; // the index and the frames directory
  std::string input_, source_, units_ = "none", status_ = "running";
  std::vector<std::string> overrides_, material_names_;
  detail::SeriesLayout layout_;
  int dim_ = 1;
  RunState state_;
  std::vector<FrameRecord> frames_; // the frames written and named so far
  // The frame being synced and named on another thread, with its series rows.
  std::future<void> committing_;
  FrameRecord committing_record_;
  std::vector<SeriesRow> committing_rows_;
  std::vector<SeriesRow> pending_; // the rows since the last frame
  /// The rows of the frames written since the index was: it holds the rows of its last frame
  /// (indexed_frame_) and before, indexed_rows_ of them.
  std::vector<SeriesRow> unindexed_;
  int indexed_frame_ = -1;
  long indexed_rows_ = 0;
  // The index's last writing: when it ended, what it cost (seconds) and the bytes of the index
  // and sidecars it wrote, for publish() and the room a frame needs.
  double published_at_ = 0, publish_cost_ = 0, published_bytes_ = 0;
};

/// The input text, overrides and frame list stored in a run file.
struct StoredRun {
  std::string input;                  ///< the input text, with the --set overrides appended
  std::vector<std::string> overrides; ///< the --set overrides
  std::string source;                 ///< the input file's name, as the run was given it
  /// The sparsempm version that wrote the file.
  std::string version, status;     ///< running | completed | failed: ... | interrupted: ...
  std::vector<double> frame_times; ///< the time of each complete frame, ascending
  std::vector<SeriesRow> series;   ///< the energy series, one row per step from t = 0
};
/// Reads the description of a run file (for `smpm info` and `--restart`).
StoredRun read_stored_run(const std::string& path);

/// The complete frames of a run file, ascending.
std::vector<int> run_frames(const std::string& path);
/// Loads the particle state and clock of one complete frame into `model` (whose grid and
/// materials must be those of the run, e.g. from stored_config). Throws InputError when the
/// frame's arrays disagree in length or width with each other or with the grid's dimension.
void load_frame(const std::string& path, int frame, Model& model);
/// The state stored with a frame (RunState). A file of an earlier version, without /state: the
/// frame's courant_budget attribute and the series row of the frame's step.
RunState read_run_state(const std::string& path, int frame);

/// The XDMF sidecars of a run file, each one temporal collection of one kind of points (so
/// that every reader opens it: ParaView's Xdmf3 and legacy XDMF readers, meshio's
/// TimeSeriesReader): the particles, the grid nodes with mass, the contact nodes (written for
/// a multimaterial run).
enum class Sidecar { Particles, Nodes, Contact };
/// Name of a sidecar of an HDF5 path: "run.h5" → "run.xmf", "run.nodes.xmf", "run.contact.xmf".
std::string xdmf_path(const std::string& h5_path, Sidecar which = Sidecar::Particles);
/// Every sidecar name of an HDF5 path, particles first.
std::vector<std::string> xdmf_paths(const std::string& h5_path);

} // namespace smpm
