// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file particle_columns.hpp
/// The optional columns of Particles: those a part of the step (step_part.hpp) adds to the
/// particles (internal energies, temperatures, heat sources, velocity gradients, the plastic
/// state). Each part declares its columns once, in its own file; one list (particle_columns)
/// serves Particles::resize and append, the selection of particles across processes, the frames
/// and restarts of a run file, its XDMF sidecar, the layout `smpm info --layout` prints and the
/// Python views.

#include "sparsempm/particles.hpp"

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace smpm {

struct Model; // model.hpp

/// The values per particle of a column.
enum class ColumnWidth {
  One,    ///< one (an N vector)
  Tensor, ///< d², a d × d tensor row-major
  Nine    ///< 9, a 3 × 3 tensor row-major whatever d
};

/// The values a column's entries may take (a restart checks them).
enum class ColumnRange {
  Finite,      ///< any finite value
  Positive,    ///< positive and finite (absolute temperatures)
  NonNegative, ///< non-negative and finite (equivalent plastic strains)
};

/// One optional column of Particles. A column is present when it has a row per particle and
/// absent (empty) otherwise.
struct ParticleColumn {
  std::string_view name = {}; ///< dataset name in frames, Python attribute
  /// The member, N entries ... (neither member: the column is Particles::columns[name])
  Eigen::VectorXd Particles::*vector = nullptr;
  Field Particles::*field = nullptr;       ///< ... or N × width entries
  ColumnWidth width = ColumnWidth::One;    ///< values per particle
  ColumnRange range = ColumnRange::Finite; ///< the values a restart accepts
  /// Why the range, in the message of a value outside it ("": "it must be ...").
  std::string_view range_reason = {};
  /// Present in every particle set, zeros unless a part sets it (Particles::resize makes it
  /// zeros; a frame without it reads as zeros unless the run requires it).
  bool always = false;
  /// Frames store it, and a restart reads it back (false: it comes from the input every run).
  bool in_frames = true;
  /// The values of the particles of P (one row each) that lack the column when a set that has
  /// it is joined to one that does not (Particles::append); null: such sets are not joined.
  Field (*absent)(const Particles& P) = nullptr;
  /// Whether a run of `model` needs the column in the frame it restarts from; null: never.
  bool (*required)(const Model& model) = nullptr;
  std::string_view why_required = {}; ///< why, in the message of a restart from a frame without it
  std::string_view shape = {};        ///< its shape in the layout ("N", "N x d^2", "N x 9")
  std::string_view meaning = {};      ///< what it holds, one line (layout, Python)
  std::string_view needs = {};        ///< the input entry that brings it ("" : always possible)
  std::string_view xdmf = {};         ///< its attribute name in the XDMF sidecar ("": not shown)
};

/// Every optional column, in the order of the parts that declare them (step_parts).
const std::vector<ParticleColumn>& particle_columns();
/// The message of a value x outside column c's range: " (temperatures are absolute: positive and
/// finite)", " (it must be non-negative and finite)", ...
std::string range_message(const ParticleColumn& c);

/// The entries per particle of column c for particles of dimension d.
Index column_width(const ParticleColumn& c, int d);
/// Whether P holds column c (a row for each particle, column_width entries each).
bool has_column(const Particles& P, const ParticleColumn& c);
/// Column c of P as an N × width row-major view (P must hold it).
Eigen::Map<Field> column_values(Particles& P, const ParticleColumn& c);
/// Column c of P as an N × width row-major view (P must hold it).
Eigen::Map<const Field> column_values(const Particles& P, const ParticleColumn& c);
/// Sets column c of P to `values` (P.size() × column_width rows; N × 1 for a vector column).
void set_column(Particles& P, const ParticleColumn& c, const Eigen::Ref<const Field>& values);
/// The rows and columns of column c as P stores it, whatever they are (a vector: its size × 1;
/// absent: 0 × 0).
std::pair<Index, Index> stored_shape(const Particles& P, const ParticleColumn& c);
/// Stores `values` as column c of P without checking their shape (a frame's values, checked
/// afterwards by stored_shape; a vector column takes the first column).
void store_column(Particles& P, const ParticleColumn& c, Field values);
/// Empties column c of P.
void clear_column(Particles& P, const ParticleColumn& c);

} // namespace smpm
