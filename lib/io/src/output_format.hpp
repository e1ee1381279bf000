// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The layout of a run file shared by its writer (output.cpp, output_frame.cpp,
// output_xdmf.cpp) and reader (output_read.cpp): frame names, series names, the file access
// properties (internal to sparsempm_io).

#include "hdf5_util.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/output.hpp"
#include "sparsempm/step_preparation.hpp"

#include <string>
#include <vector>

namespace smpm::detail {

/// "000042" for frame 42.
std::string frame_name(int frame);

/// The one-column series, in the order of SeriesRow's fields.
extern const char* const kSeries[];
/// The per-material series (mass, momentum, centre of mass).
extern const char* const kMaterialSeries[];
/// The values of the rows for every series of `layout`, in the order of its columns() (rows ×
/// width; NaN where a row lacks a value).
std::vector<Field> series_values(const SeriesLayout& layout, const std::vector<SeriesRow>& rows);
/// Creates /series with every series of `layout`, empty and extendible in chunks of `chunk`
/// rows.
void create_series_group(hid_t file, const SeriesLayout& layout, hsize_t chunk = h5::kSeriesChunk);
/// Rows per chunk of the series of a run's index, which is written again after frames.
inline constexpr hsize_t kIndexSeriesChunk = 128;
/// Appends the rows to the extendible series of /series.
void append_series_rows(hid_t file, const SeriesLayout& layout, const std::vector<SeriesRow>& rows);
/// Writes /series with the rows as datasets of their size (a frame file's rows).
void write_series_rows(hid_t file, const SeriesLayout& layout, const std::vector<SeriesRow>& rows);

/// Writes the contact nodes of a multimaterial frame into its /grid group `g` (contact_nodes,
/// contact_fields, contact_normal, contact_separation, contact_approaching, contact_X) from the
/// frame's preparation (prepare_step) and momenta p = SᵀMV (output_contact.cpp).
void write_contact_nodes(hid_t g, const StepPreparation& prep, const Field& p);
/// `X` (n × d) with zeros to three columns as dataset `name` of group `g`: the geometry of a
/// 1D frame in its sidecar (ParaView and meshio read two or three coordinates).
void write_xyz(hid_t g, const std::string& name, const Field& X);
/// /vertices/<n> = 0, 1, …, n − 1 (an n × 1 int dataset, written once per count n > 0): the
/// connectivity of the sidecars' Polyvertex topology, one vertex cell per point.
void write_vertices(hid_t file, Index n);
/// `text` as XML character data: &, <, >, " and ' as entities (a file name may hold any).
std::string xml_escaped(const std::string& text);
/// The parts of a frame (output_frame.cpp): /particles/<name>, /grid/<name> (and
/// /matrices/<name>) from the step preparation `prepared` or the frame's own, the series rows
/// buffered since the last frame, /state/<name>.
void write_particles(hid_t file, const std::string& name, const Model& model);
void write_grid(hid_t file, const std::string& name, const Model& model, Shape shape, bool matrices,
                const StepPreparation* prepared);
void write_run_state(hid_t file, const std::string& name, const RunState& state);
/// An upper bound of the bytes of a frame file of `model` with `series_rows` rows of `columns`
/// values each: what write_frame makes sure the disk has before writing it.
double frame_bytes(const Model& model, const StepPreparation* prepared, bool matrices,
                   size_t series_rows, size_t columns);
/// Loads one frame's particle state and clock into `model`.
void load_frame_from(hid_t file, int frame, Model& model);

} // namespace smpm::detail
