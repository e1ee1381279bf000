// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/advance.hpp"

#include "sparsempm/diagnostics.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/transport.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace smpm {

void check_energy(const Model& model, double e, double e0, const FailureTest& test) {
  if (!std::isfinite(e))
    throw at_step(NumericalError("total energy is not finite"), model.step, model.time);
  // Body forces and driven BCs (values, moving walls) do work on the particles, and heat sources
  // and held temperatures put heat into them (which thermal expansion or a Mie–Grüneisen
  // particle's U turns into strain energy): their energy need not stay near its start, so the
  // growth test is off for them.
  const bool heated = model.particles.heat_source.size() > 0 &&
                      model.particles.heat_source.cwiseAbs().maxCoeff() > 0;
  const bool loaded = model.gravity[0] != 0 || model.gravity[1] != 0 || model.gravity[2] != 0 ||
                      model.bcs.driven() || !model.loads.empty() || !model.rigid.empty() ||
                      heated || !model.temperature_bcs.conditions.empty();
  if (loaded || !(test.energy_growth > 0) || !(e0 > 0) || e <= test.energy_growth * e0)
    return;
  const Particles& P = model.particles;
  Index fastest = 0;
  P.V.rowwise().squaredNorm().maxCoeff(&fastest);
  std::ostringstream os;
  os << "total energy " << e << " exceeds " << test.energy_growth << " times its start " << e0
     << " (unstable; fastest particle " << fastest << " at (";
  for (int a = 0; a < P.dim; ++a)
    os << (a ? ", " : "") << P.X(fastest, a);
  os << ") with speed " << P.V.row(fastest).norm() << ")";
  throw at_step(NumericalError(os.str()), model.step, model.time);
}

namespace {
// The failure of a Courant time step dt below test.min_time_step_fraction of the first, dt0.
void check_time_step(const Model& model, double dt, double dt0, const FailureTest& test) {
  if (!(test.min_time_step_fraction > 0) || dt >= test.min_time_step_fraction * dt0)
    return;
  std::ostringstream os;
  os << "the time step " << dt << " fell below " << test.min_time_step_fraction
     << " of the first step's " << dt0 << " (the signal speed grew " << dt0 / dt << " times)";
  // The most compressed Mie–Grüneisen particle: its wave speed diverges as 1 − J → 1/S₁.
  const Particles& P = model.particles;
  const Eigen::VectorXd J = P.jacobian();
  Index worst = -1;
  double eta = 0;
  for (Index p = 0; p < P.size(); ++p) {
    const Material& m = model.materials[size_t(P.material[p])];
    if (m.model != MaterialModel::MieGruneisen || !(m.hugoniot_slope > 0))
      continue;
    const double e = m.hugoniot_slope * (1 - J[p]);
    if (e > eta) {
      eta = e;
      worst = p;
    }
  }
  if (worst >= 0)
    os << "; particle " << worst << " is compressed to S1 (1 - J) = " << eta
       << ", near the Mie-Gruneisen limit 1";
  throw at_step(NumericalError(os.str()), model.step + 1, model.time); // the step not taken
}
} // namespace

namespace {
// The conduction limit F Δx_min² / D_max of heat transport (+∞ without it).
double conduction_limit(const Model& model, const AdvanceOptions& o, bool transport) {
  if (!(o.fourier >= 0) || !std::isfinite(o.fourier))
    throw InputError("the Fourier number must be positive (0: the default), got " +
                     number_text(o.fourier));
  if (!transport)
    return std::numeric_limits<double>::infinity();
  return (o.fourier > 0 ? o.fourier : default_fourier(model.grid.dim())) *
         diffusion_time(model.grid, model.materials, model.particles);
}

// The particle with the largest speed, for messages: " (particle p moves at |V| = v)".
std::string fastest_particle(const Model& model) {
  const Particles& P = model.particles;
  if (P.size() == 0)
    return "";
  Index fastest = 0;
  P.V.rowwise().squaredNorm().maxCoeff(&fastest);
  // stableNorm: a speed of 1e200 is told as such (its square overflows)
  return " (particle " + std::to_string(fastest) +
         " moves at |V| = " + number_text(P.V.row(fastest).stableNorm()) + ")";
}

// The first step's Δt and why: the Courant or the conduction limit.
double first_time_step(const Model& model, const AdvanceOptions& o, bool transport,
                       std::string& why) {
  const double speed = signal_speed(model), courant = stable_time_step(model, o.courant, speed);
  const double conduction = conduction_limit(model, o, transport);
  const double h = model.grid.min_cell_size();
  if (conduction < courant) {
    why = "the conduction limit time.fourier = " +
          number_text(o.fourier > 0 ? o.fourier : default_fourier(model.grid.dim())) +
          " times dx^2 / D with dx = " + number_text(h) +
          " and the largest diffusivity D = conductivity / (density heat_capacity) = " +
          number_text(h * h / diffusion_time(model.grid, model.materials, model.particles)) +
          " of the materials";
    return conduction;
  }
  const bool moving = max_particle_speed(model.particles) >= speed;
  why = "the Courant limit time.courant = " + number_text(o.courant) +
        " times dx = " + number_text(h) + " over the signal speed" +
        (moving ? fastest_particle(model)
                : " " + number_text(speed) + " (the materials' wave speed)");
  return courant;
}
} // namespace

void check_step_count(const Model& model, const AdvanceOptions& o, bool transport) {
  if (!(o.max_steps > 0))
    throw InputError("max_steps must be positive, got " + std::to_string(o.max_steps));
  // From t = 0 only: the first step's Δt of a run continued from a later step need not be the
  // run's, and the run was checked when it began.
  if (!(o.end > model.time) || model.particles.size() == 0 || model.step > 0)
    return;
  std::string why;
  const double dt = first_time_step(model, o, transport, why);
  const double span = o.end - model.time;
  // Landing on each stop: ceil(every / dt) steps per whole interval between stops.
  const double whole = o.land_on_stops && o.stop_every > 0 ? std::floor(span / o.stop_every) : 0;
  const double steps = whole > 0 ? whole * std::ceil(o.stop_every / dt) +
                                       std::ceil((span - whole * o.stop_every) / dt)
                                 : span / dt;
  if (!(steps <= double(o.max_steps)))
    throw InputError("time.end = " + number_text(o.end) + " would take about " +
                     number_text(steps) + " steps of dt = " + number_text(dt) + ", from " + why +
                     ": more than time.max_steps = " + std::to_string(o.max_steps));
}

namespace {
// The refusals of advance's options: an end before the model's time, a failure test that is
// not a number, a negative interval between stops.
void check_advance_options(const Model& model, const AdvanceOptions& o) {
  if (!(o.end >= model.time) || !std::isfinite(o.end))
    throw InputError("end time " + number_text(o.end) + " is before the model's time " +
                     number_text(model.time));
  if (std::isnan(o.failure.energy_growth))
    throw InputError("energy_growth must be a number (0 or less: no growth test), got nan");
  if (std::isnan(o.failure.min_time_step_fraction))
    throw InputError("min_time_step_fraction must be a number (0 or less: no test), got nan");
  SMPM_VERIFY(o.stop_every >= 0 && std::isfinite(o.stop_every),
              "advance: the interval between stops must be non-negative");
}

// The stops of a run: the multiples of `every` (none when it is 0), never past `end`.
struct Stops {
  double end, every;
  // Round-off allowance of the clock, relative to the times reached (never to the interval
  // between stops, which may exceed the whole run).
  double eps;
  // The next stop after t: the smallest multiple of `every` beyond t (and never past end).
  double next(double t) const {
    if (!(every > 0))
      return end;
    return std::min(end, (std::floor((t + eps) / every) + 1) * every);
  }
};

// The signal speed of the next step: the materials' wave speed (fixed unless Mie–Grüneisen
// particles change it with their state) and the largest particle speed, which the energies of
// each step provide.
struct SignalSpeed {
  bool shock;  // Mie–Grüneisen particles: the wave speed of each step's state
  double wave; // else the materials' wave speed, fixed
  explicit SignalSpeed(const Model& model)
      : shock(uses_shock_physics(model.materials)),
        wave(shock ? 0 : max_wave_speed(model.materials, model.particles)) {}
  double after_step(const Model& model, double max_speed) const {
    return std::max(shock ? max_wave_speed(model.materials, model.particles) : wave, max_speed);
  }
};

// The time step Δt of the next step: the Courant time step C Δx / speed, refused when it is not
// positive or falls below the failure test's fraction of the first step's, dt0 (set here on the
// first step unless the options give it); then the conduction limit, and with land_on_stops the
// time left to the next stop.
double next_time_step(const Model& model, const AdvanceOptions& o, double speed, double conduction,
                      double stop, bool first, double& dt0) {
  double dt = stable_time_step(model, o.courant, speed);
  if (!(dt > 0) || !std::isfinite(dt)) // a speed so large that C Δx / speed underflows
    throw at_step(NumericalError("the time step " + number_text(dt) + " is not positive" +
                                 fastest_particle(model)),
                  model.step + 1, model.time);
  if (first && !o.time_step_start)
    dt0 = dt;
  check_time_step(model, dt, dt0, o.failure);
  dt = std::min(dt, conduction);
  if (o.land_on_stops)
    dt = std::min(dt, stop - model.time);
  return dt;
}
} // namespace

AdvanceReport advance(Model& model, Stepper& stepper, const AdvanceOptions& o,
                      const StepObserver& observer) {
  const Stepper::Exclusive hold(stepper); // no other thread steps it between our steps
  check_advance_options(model, o);
  AdvanceReport report;
  report.energy_start = o.energy_start ? *o.energy_start : energies(model).total;
  const Stops stops{o.end, o.stop_every, 1e-12 * std::max(std::abs(o.end), std::abs(model.time))};
  const double eps = stops.eps;
  double stop = stops.next(model.time);
  const auto start = std::chrono::steady_clock::now();
  const SignalSpeed next_speed(model);
  double speed = signal_speed(model);
  double dt0 = o.time_step_start.value_or(0); // the first step's Courant time step
  // Heat transport: the explicit conduction limit F Δx² / D_max (the materials do not change).
  const bool transport = stepper.options().transport.update != TransportUpdate::Off;
  const double conduction = conduction_limit(model, o, transport);
  check_step_count(model, o, transport);
  PhaseTimes& times = stepper.times();
  const PhaseTimes times_start = times;
  while (model.time < o.end - eps) {
    PhaseClock clock;
    const double dt = next_time_step(model, o, speed, conduction, stop, report.steps == 0, dt0);
    clock.lap(times.energies);
    stepper.step(model, dt); // its parts timed by prepare_step and step
    PhaseClock after;
    ++report.steps;
    const Energies e = stepper.energies(model); // W(F_p) from the step's stress update
    speed = next_speed.after_step(model, e.max_speed);
    check_energy(model, e.total, report.energy_start, o.failure);
    report.energy_end = e.total;
    after.lap(times.energies);
    const bool at_stop = model.time >= stop - eps;
    if (at_stop)
      stop = stops.next(model.time);
    if (observer) {
      observer(model, e, at_stop);
      if (o.observer_changes_model) // new velocities or materials set the next time step
        speed = signal_speed(model);
    }
    check_interrupt(o.interrupt, [&] {
      return "after step " + std::to_string(model.step) + " (t = " + number_text(model.time) + ")";
    });
  }
  if (report.steps == 0)
    report.energy_end = energies(model).total;
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.times = times.since(times_start);
  return report;
}

} // namespace smpm
