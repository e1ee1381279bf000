// SPDX-License-Identifier: BSD-3-Clause
// Reading run files: the description of a run (smpm info, --restart), its complete frames and
// the state of one frame.

#include "sparsempm/output.hpp"
#include "sparsempm/particle_columns.hpp"

#include "hdf5_util.hpp"
#include "output_format.hpp"
#include "run_reader.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/plasticity.hpp"
#include "sparsempm/run_file.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace smpm {

using namespace detail;

StoredRun read_stored_run(const std::string& path) {
  check_regular_file(path, kMaxRunFileBytes, "run file");
  RunReader r(path);
  const hid_t f = r.index();
  StoredRun run;
  try {
    run.input = h5::get_string_attribute(f, "input");
    run.overrides = h5::get_strings_attribute(f, "overrides");
    if (h5::has_attribute(f, "source"))
      run.source = h5::get_string_attribute(f, "source");
    run.version = h5::get_string_attribute(f, "version");
    run.status = h5::get_string_attribute(f, "status");
    for (int frame : r.frames()) {
      try {
        h5::Id g = h5::open_group(r.frame(frame), "particles/" + frame_name(frame));
        run.frame_times.push_back(h5::get_double_attribute(g.get(), "time"));
      } catch (const h5::Error&) {
        break; // a frame file that cannot be read (damaged): no frame from it on
      }
    }
    // The series; files of earlier versions lack some (their rows keep the defaults).
    auto column = [&](const char* name) { return r.has_series(name) ? r.series(name) : Field(); };
    const Field step = r.series("step"), t = r.series("t");
    const Field kin = r.series("kinetic"), str = r.series("strain"), tot = r.series("total");
    const Field vc = column("velocity_change"), vs = column("velocity_change_sum");
    for (Index k = 0; k < step.rows(); ++k) {
      SeriesRow row;
      row.step = long(step(k, 0));
      row.t = t(k, 0);
      row.e.kinetic = kin(k, 0);
      row.e.strain = str(k, 0);
      row.e.total = tot(k, 0);
      if (k < vs.rows() && k < vc.rows()) {
        row.velocity_change = vc(k, 0);
        row.velocity_change_sum = vs(k, 0);
      }
      run.series.push_back(row);
    }
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": not a sparsempm run file (" + e.what() + ")");
  }
  return run;
}

namespace {
// Throws std::runtime_error unless the frame's arrays have N rows and the widths of dimension d.
void check_frame_shapes(const Particles& P, int d) {
  const Index N = P.X.rows();
  auto expect = [&](const char* name, Index rows, Index cols, Index want_cols) {
    if (rows != N || cols != want_cols)
      throw std::runtime_error(std::string(name) + " is " + std::to_string(rows) + " x " +
                               std::to_string(cols) + ", expected " + std::to_string(N) + " x " +
                               std::to_string(want_cols) + " (X has " + std::to_string(N) +
                               " rows)");
  };
  expect("X", P.X.rows(), P.X.cols(), d);
  expect("V", P.V.rows(), P.V.cols(), d);
  expect("F", P.F.rows(), P.F.cols(), d * d);
  expect("stress", P.stress.rows(), P.stress.cols(), d * d);
  expect("mass", P.mass.rows(), 1, 1);
  expect("volume0", P.volume0.rows(), 1, 1);
  expect("half_length", P.half_length.rows(), P.half_length.cols(), d);
  expect("material", P.material.rows(), 1, 1);
  for (const ParticleColumn& c : particle_columns()) { // the parts' columns it holds
    const auto [rows, cols] = stored_shape(P, c);
    if (c.always || rows > 0)
      expect(std::string(c.name).c_str(), rows, cols, column_width(c, d));
  }
}

// Throws std::runtime_error naming the dataset unless every value a step reads is in its range:
// a damaged frame would otherwise be continued (a NaN position fails some steps later, a NaN
// energy or a negative mass runs on).
void check_frame_values(const Particles& P, const Model& model) {
  const std::pair<const char*, const Field*> finite[] = {
      {"X", &P.X}, {"V", &P.V}, {"F", &P.F}, {"stress", &P.stress}};
  for (const auto& [name, f] : finite)
    if (!f->allFinite())
      throw std::runtime_error(std::string(name) + " holds a value that is not finite");
  for (const ParticleColumn& c : particle_columns()) { // the parts' columns it holds
    if (!has_column(P, c))
      continue;
    const Eigen::Map<const Field> v = column_values(P, c);
    if (c.range == ColumnRange::Finite && !v.allFinite())
      throw std::runtime_error(std::string(c.name) + " holds a value that is not finite");
    for (Index k = 0; c.range != ColumnRange::Finite && k < v.size(); ++k) {
      const double x = v.data()[k];
      if (std::isfinite(x) && (c.range == ColumnRange::Positive ? x > 0 : x >= 0))
        continue;
      throw std::runtime_error(std::string(c.name) + " holds " + number_text(x) + range_message(c));
    }
  }
  const std::pair<const char*, const double*> positive[] = {{"mass", P.mass.data()},
                                                            {"volume0", P.volume0.data()},
                                                            {"half_length", P.half_length.data()}};
  const Index counts[] = {P.mass.size(), P.volume0.size(), P.half_length.size()};
  for (size_t k = 0; k < 3; ++k)
    for (Index i = 0; i < counts[k]; ++i)
      if (!(positive[k].second[i] > 0) || !std::isfinite(positive[k].second[i]))
        throw std::runtime_error(std::string(positive[k].first) + " holds " +
                                 number_text(positive[k].second[i]) +
                                 " (it must be positive and finite)");
  const int materials = int(model.materials.size());
  for (Index p = 0; p < P.material.size(); ++p)
    if (P.material[p] < 0 || P.material[p] >= materials)
      throw std::runtime_error("material holds the id " + std::to_string(P.material[p]) +
                               " of particle " + std::to_string(p) + " (the run has " +
                               std::to_string(materials) + " materials)");
}

} // namespace

namespace detail {

void load_frame_from(hid_t file, int frame, Model& model) {
  h5::Id parts = h5::open_group(file, "particles");
  h5::Id g = h5::open_group(parts.get(), frame_name(frame));
  Particles P;
  P.X = h5::read_doubles(g.get(), "X");
  P.V = h5::read_doubles(g.get(), "V");
  P.F = h5::read_doubles(g.get(), "F");
  P.stress = h5::read_doubles(g.get(), "stress");
  P.mass = h5::read_doubles(g.get(), "mass").col(0);
  P.volume0 = h5::read_doubles(g.get(), "volume0").col(0);
  P.half_length = h5::read_doubles(g.get(), "half_length");
  P.dim = model.grid.dim();
  for (const ParticleColumn& c : particle_columns()) { // the parts' columns
    if (!c.in_frames) { // the input's (the model holds them for the same particles)
      if (has_column(model.particles, c) && model.particles.size() == P.X.rows())
        set_column(P, c, column_values(model.particles, c));
    } else if (h5::exists(g.get(), std::string(c.name))) {
      store_column(P, c, h5::read_doubles(g.get(), std::string(c.name)));
    } else if (c.required && c.required(model)) { // part of the state
      throw std::runtime_error(std::string(c.name) + " is missing (" + std::string(c.why_required) +
                               ")");
    } else if (c.always) {
      set_column(P, c, Field::Zero(P.X.rows(), column_width(c, P.dim)));
    }
  }
  const std::vector<int> mat = h5::read_ints(g.get(), "material");
  P.material = Eigen::Map<const Eigen::VectorXi>(mat.data(), Index(mat.size()));
  check_frame_shapes(P, P.dim);
  check_frame_values(P, model);
  const double time = h5::get_double_attribute(g.get(), "time");
  const long step = h5::get_long_attribute(g.get(), "step");
  if (!(time >= 0) || !std::isfinite(time) || step < 0)
    throw std::runtime_error("the frame's time " + number_text(time) + " or step " +
                             std::to_string(step) + " is out of range");
  model.particles = std::move(P);
  model.time = time;
  model.step = step;
}
} // namespace detail

std::vector<int> run_frames(const std::string& path) {
  check_regular_file(path, kMaxRunFileBytes, "run file");
  return RunReader(path).frames();
}

namespace {
// Throws InputError naming the file, frame and attribute unless the state can be continued.
const RunState& checked(const RunState& s, const std::string& path, int frame) {
  const std::pair<const char*, double> values[] = {{"courant_budget", s.stepper.courant_budget},
                                                   {"friction_work", s.stepper.friction_work},
                                                   {"viscous_work", s.stepper.viscous_work},
                                                   {"plastic_work", s.stepper.plastic_work},
                                                   {"velocity_change_sum", s.velocity_change_sum}};
  for (const auto& [name, v] : values)
    if (!std::isfinite(v) || (v < 0 && name == values[0].first))
      throw InputError(path + ": frame " + std::to_string(frame) + ": the state's " + name + " = " +
                       number_text(v) + " (it must be finite" +
                       (name == values[0].first ? " and non-negative)" : ")"));
  return s;
}

RunState read_state(const std::string& path, int frame);
} // namespace

RunState read_run_state(const std::string& path, int frame) {
  RunState state;
  try {
    state = read_state(path, frame);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) { // a missing or unreadable attribute
    throw InputError(path + ": frame " + std::to_string(frame) + ": its state: " + e.what());
  }
  return checked(state, path, frame);
}

namespace {
RunState read_state(const std::string& path, int frame) {
  RunState state;
  long step = 0;
  {
    RunReader r(path);
    const hid_t f = r.frame(frame);
    const std::string name = frame_name(frame);
    if (h5::exists(f, "state") && !h5::exists(f, "state/" + name))
      throw std::runtime_error("/state/" + name + " is missing (the state a restart continues)");
    if (h5::exists(f, "state")) {
      h5::Id g = h5::open_group(f, "state/" + name);
      state.stepper.courant_budget = h5::get_double_attribute(g.get(), "courant_budget");
      state.stepper.friction_work = h5::get_double_attribute(g.get(), "friction_work");
      state.stepper.viscous_work = h5::get_double_attribute(g.get(), "viscous_work");
      if (h5::has_attribute(g.get(), "plastic_work")) // files before J2 plasticity lack it
        state.stepper.plastic_work = h5::get_double_attribute(g.get(), "plastic_work");
      state.velocity_change_sum = h5::get_double_attribute(g.get(), "velocity_change_sum");
      return state;
    }
    // A file of an earlier version: the budget on the frame, the sums in its step's series row.
    h5::Id g = h5::open_group(f, "particles/" + name);
    if (h5::has_attribute(g.get(), "courant_budget"))
      state.stepper.courant_budget = h5::get_double_attribute(g.get(), "courant_budget");
    step = h5::get_long_attribute(g.get(), "step");
  }
  // The last row at or before the frame's step: its running sums.
  RunReader r(path);
  const Field steps = r.series("step");
  Index last = -1;
  for (Index k = 0; k < steps.rows(); ++k)
    if (long(steps(k, 0)) <= step)
      last = k;
  auto at_last = [&](const char* name) { // NaN where the file lacks the series
    const Field v = r.has_series(name) ? r.series(name) : Field();
    return last >= 0 && last < v.rows() ? v(last, 0) : std::numeric_limits<double>::quiet_NaN();
  };
  if (const double v = at_last("velocity_change_sum"); std::isfinite(v))
    state.velocity_change_sum = v;
  const double friction = at_last("friction"), viscous = at_last("viscous");
  if (std::isfinite(friction) && std::isfinite(viscous)) {
    const double plastic = at_last("plastic");
    state.stepper = {state.stepper.courant_budget, friction, viscous,
                     std::isfinite(plastic) ? plastic : 0.0};
  }
  return state;
}
} // namespace

void load_frame(const std::string& path, int frame, Model& model) {
  RunReader r(path);
  try {
    load_frame_from(r.frame(frame), frame, model);
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": frame " + std::to_string(frame) + ": " + e.what());
  }
}

} // namespace smpm
