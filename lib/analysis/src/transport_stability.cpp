// SPDX-License-Identifier: BSD-3-Clause
// The linearised transport step and its critical Fourier number (transport_stability.hpp).

#include "sparsempm/transport_stability.hpp"

#include "radius.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/scheme.hpp"
#include "sparsempm/step_preparation.hpp"

#include <cmath>
#include <string>

namespace smpm {

struct TransportStep::Impl {
  Model model;
  StepOptions options;
  double dt = 0;
  StepPreparation prep;
  BoundaryConditions homogeneous; // the conditions' nodes with zero values
  std::unique_ptr<MassSolver> solver;
  mutable Eigen::VectorXd T;
  mutable TransportState state;
  TransportContext context;
};

TransportStep::TransportStep(const Model& model, const StepOptions& options, double dt)
    : impl_(std::make_unique<Impl>()) {
  validate(options);
  if (options.transport.update == TransportUpdate::Off)
    throw InputError("the transport stability needs heat transport (step.transport = lumped, "
                     "FMPM or exact)");
  Impl& I = *impl_;
  I.model = model;
  I.options = options;
  I.prep.ops.node_range = options.nodes;
  I.model.particles.heat_source.resize(0); // the linear part: no sources
  prepare_step(I.model, options.shape, I.prep);
  if (options.transport.limiter != TransportLimiter::None)
    throw InputError("the transport limiter (transport_limiter = \"" +
                     std::string(to_string(options.transport.limiter)) +
                     "\") is not linear: the transport stability analysis takes \"none\"");
  prepare_heat_transport(I.model, I.prep, options.transport.update);
  I.homogeneous = I.prep.temperature_bcs;
  for (VelocityCondition& c : I.homogeneous.conditions) {
    c.value = {};
    c.wall_state.reset();
  }
  if (options.transport.update == TransportUpdate::Exact)
    I.solver = options.exact_solver(transport_solver_options(options));
  TransportContext& c = I.context;
  c.update = options.transport.update;
  c.fmpm = transport_fmpm_options(options);
  c.ops = &I.prep.transport;
  c.ct = uses_consistent_capacity(options) ? &I.prep.consistent_capacity() : nullptr;
  c.solver = I.solver.get();
  c.bcs = &I.homogeneous;
  c.temperature = &I.T;
  c.absolute = false; // perturbations of either sign
  set_dt(dt);
}

TransportStep::~TransportStep() = default;
TransportStep::TransportStep(TransportStep&&) noexcept = default;

void TransportStep::set_dt(double dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw InputError("TransportStep: the time step must be positive and finite, got " +
                     number_text(dt));
  impl_->dt = dt;
}
double TransportStep::dt() const {
  return impl_->dt;
}
Index TransportStep::rows() const {
  return impl_->model.particles.size();
}

void TransportStep::perform_op(const double* x, double* y) const {
  const Impl& I = *impl_;
  I.T = Eigen::Map<const Eigen::VectorXd>(x, rows());
  transport_content(I.prep.ops, I.context, 0.0, I.state);
  transport_update(I.prep.ops, I.context, nullptr, 0.0, I.dt, I.state);
  transport_particles(I.prep.ops, I.context, I.dt, I.state);
  Eigen::Map<Eigen::VectorXd>(y, rows()) = I.T;
}

Eigen::MatrixXd TransportStep::dense() const {
  return detail::dense_of(*this);
}

SpectralRadius spectral_radius(const TransportStep& T, Index dense_limit) {
  return detail::operator_radius(T, dense_limit);
}

CriticalFourier critical_fourier(const Model& model, const StepOptions& options, double tol,
                                 double f_max, double resolution, double hint,
                                 const std::atomic<int>* interrupt) {
  const double diffusion = diffusion_time(model.grid, model.materials, model.particles);
  if (!std::isfinite(diffusion))
    throw InputError("the transport stability needs a material that conducts (conductivity > 0)");
  TransportStep T(model, options, 0.05 * diffusion);
  const CriticalCourant c = detail::critical_parameter(
      [&](double F, int& steps) {
        T.set_dt(F * diffusion);
        steps = 1;
        return spectral_radius(T);
      },
      "F*", tol, f_max, resolution, hint, interrupt, SmallCourantScan{});
  return {.critical_fourier = c.critical_courant,
          .stable_from = c.stable_from,
          .small = c.small,
          .floor = c.floor,
          .rho_limit = c.rho_limit,
          .growth_rate = c.growth_rate,
          .rho_T = c.rho_T,
          .evaluations = c.evaluations,
          .not_converged = c.not_converged,
          .non_finite = c.non_finite};
}

} // namespace smpm
