// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/scheme.hpp"
#include "sparsempm/step_part.hpp"

#include "radius.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace smpm {

namespace {
// The linearised strain update σ' = σ + Δt 𝕂 : L, L = G v, with 𝕂 fixed at the frozen F.
class TangentStressUpdate final : public StrainUpdate {
public:
  TangentStressUpdate(const Field& K, Field& L) : K_(K), L_(L) {}
  void update(const ParticleOperators& op, const Field& v, double dt,
              ParticleFields& fields) override {
    const int d2 = op.dim * op.dim;
    L_.resize(op.rows, d2);
    velocity_gradient(op, v, L_);
    for (Index q = 0; q < op.rows; ++q)
      for (int r = 0; r < d2; ++r) {
        double s = 0;
        for (int c = 0; c < d2; ++c)
          s += K_(q, r * d2 + c) * L_(q, c);
        fields.stress(q, r) += dt * s;
      }
  }

private:
  const Field& K_;
  Field& L_;
};

// Material tangents 𝕂_p = ∂σ/∂L (N × d⁴, row-major ab, cd) of σ(f F) of each particle's
// material (stress_tangent), then of the parts whose particles' stress is another function of
// their state (StepPart::tangents: plasticity).
Field material_tangents(const Model& model, const std::vector<std::unique_ptr<StepPart>>& parts) {
  const Particles& P = model.particles;
  const int d = P.dim, d2 = d * d;
  Field K = Field::Zero(P.size(), d2 * d2);
  for (Index q = 0; q < P.size(); ++q) {
    const Material& mat = model.materials.at(size_t(P.material[q]));
    const Eigen::Matrix3d F = embed_3d(P.F.row(q).data(), d);
    stress_tangent(
        d, [&](const Eigen::Matrix3d& f) { return cauchy_stress(mat, d, f * F); }, K.row(q).data());
  }
  for (const std::unique_ptr<StepPart>& part : parts)
    part->tangents(model, K);
  return K;
}
} // namespace

struct LinearizedStep::Impl {
  Model model; // the frozen configuration
  StepOptions opt;
  std::unique_ptr<MassSolver> solver;
  BoundaryConditions homogeneous; // the BC directions with zero values
  StepPreparation prep;           // the frozen configuration's operators (and m̃ when used)
  Field K;                        // material tangents
  double dt = 0;
  const NodeSums* sums = nullptr; // across processes: the sums of the node fields
  int flip_steps = 0;             // periodic FMPM: FLIP steps before each FMPM step
  int d = 1;
  Index N = 0;
  // The state and scratch of perform_op: V, σ and the parts' state columns (the velocity-gradient
  // transfer's L_p, which P2G reads), and scratch.
  mutable Field X, V, F, sig, L;
  std::vector<Field*> state; // the parts' columns of the state, in model's particles
  Index state_columns = 0;   // their columns in all
  mutable StepBuffers buffers;
  std::vector<std::unique_ptr<StepPart>> parts;
  std::vector<StageHooks*> hooks;
  StepContext context; // the step's context but for grid_update (m̃ or m̃_L, the parts' terms)

  void begin_parts();
  void step(bool grid_update) const;
};

LinearizedStep::LinearizedStep(const Model& model, const StepOptions& options, double dt)
    : impl_(std::make_unique<Impl>()) {
  init(model, options, dt, nullptr);
}

LinearizedStep::LinearizedStep(const Model& model, const StepOptions& options, double dt,
                               NodeSums& sums)
    : impl_(std::make_unique<Impl>()) {
  if (!model.bcs.walls.empty())
    throw InputError("the linearised step across processes does not take moving walls yet");
  if (options.velocity == VelocityUpdate::XPIC)
    throw InputError("the linearised step across processes is FLIP, PIC, FMPM(k) or the exact "
                     "update (not XPIC) for now");
  init(model, options, dt, &sums);
  if (impl_->solver && !impl_->solver->across_processes())
    throw InputError("the exact update across processes needs a MassSolver that solves across "
                     "them (e.g. sparsempm::petsc's distributed_mass_solver_factory), not "
                     "one process's");
}

void LinearizedStep::init(const Model& model, const StepOptions& options, double dt,
                          NodeSums* sums) {
  validate(options);
  if (options.fmpm.metric != ConvergenceMetric::None &&
      (options.velocity == VelocityUpdate::FMPM || options.velocity == VelocityUpdate::XPIC))
    throw InputError("the linearised step needs a fixed FMPM order: dynamic FMPM stops at an "
                     "order that depends on the state, which is not a linear map");
  std::vector<std::unique_ptr<StepPart>> parts = step_parts(options);
  for (const std::unique_ptr<StepPart>& part : parts) { // one rule for every part
    if (const std::string why = part->not_linearised(model); !why.empty())
      throw InputError(why);
  }
  if (sums)
    check_distributed(parts, model, "the linearised step");
  Impl& I = *impl_;
  I.sums = sums;
  I.model = model;
  I.opt = options;
  if (options.velocity == VelocityUpdate::Exact)
    I.solver = options.exact_solver(velocity_solver_options(options));
  I.d = model.grid.dim();
  I.N = model.particles.size();
  if (sums) // this process's particles on their window, with the total masses over all
    I.prep.ops.node_range = NodeRange::Particles;
  prepare_step(model, options.shape, I.prep, sums); // on the whole grid (NodeRange::Grid)
  // The BC directions with zero values: walls frozen on the nodes they select now.
  for (VelocityCondition c : I.prep.bcs.conditions) {
    c.value = nullptr;
    c.wall_state.reset();
    c.wall = -1;
    I.homogeneous.conditions.push_back(std::move(c));
  }
  I.K = material_tangents(I.model, parts);
  I.F = model.particles.F;
  I.parts = std::move(parts);
  I.begin_parts();
  set_dt(dt);
}

// The context of the linearised steps: the operators, the homogeneous conditions, m̃ when the
// update uses it, and what each part adds that is linear in the state (begin_linearised).
void LinearizedStep::Impl::begin_parts() {
  context = {.options = &opt,
             .ops = &prep.ops,
             .solver = solver.get(),
             .grid = &prep.ops.grid,
             .bcs = &homogeneous,
             .gravity = {0, 0, 0},
             .time = 0,
             .grid_update = true,
             .sums = sums};
  X = model.particles.X;
  ParticleFields fields{X, V, F, sig, model.particles.volume0};
  StrainCouplings strain; // the tangents stand for the strain update's states
  StepStart start{model, opt, prep, context, fields, strain, buffers, hooks, &state};
  for (const std::unique_ptr<StepPart>& part : parts)
    part->begin_linearised(start);
  if (!context.mt && uses_consistent_mass(opt, true))
    context.mt = &prep.consistent_mass();
  context.hooks = hooks;
  state_columns = 0;
  for (const Field* f : state)
    state_columns += f->cols();
}

LinearizedStep::~LinearizedStep() = default;
LinearizedStep::LinearizedStep(LinearizedStep&&) noexcept = default;

void LinearizedStep::set_dt(double dt) {
  if (!(dt > 0))
    throw InputError("time step must be positive");
  impl_->dt = dt;
  impl_->flip_steps = 0;
  if (impl_->opt.periodic_cx > 0 && impl_->opt.velocity != VelocityUpdate::FLIP) // the Stepper's
    impl_->flip_steps =
        periodic_fmpm_period(impl_->opt.periodic_cx,
                             impl_->sums ? impl_->sums->maximum(courant_of(impl_->model, dt))
                                         : courant_of(impl_->model, dt)) -
        1;
}

double LinearizedStep::dt() const {
  return impl_->dt;
}
int LinearizedStep::steps_per_application() const {
  return impl_->flip_steps + 1;
}
Index LinearizedStep::rows() const {
  const Index d2 = impl_->d * impl_->d;
  return impl_->N * (impl_->d + d2 + impl_->state_columns);
}
const Operators& LinearizedStep::operators() const {
  return impl_->prep.ops;
}

// One linearised step on (V, sig) in place: the Stepper's scheme_step on the frozen operators,
// with scratch positions (the operators do not follow them).
void LinearizedStep::Impl::step(bool grid_update) const {
  X = model.particles.X;
  StepContext c = context;
  c.dt = dt;
  c.grid_update = grid_update;
  ParticleFields fields{X, V, F, sig, model.particles.volume0};
  TangentStressUpdate strain(K, L);
  scheme_step(c, fields, strain, buffers);
}

void LinearizedStep::perform_op(const double* x, double* y) const {
  Impl& I = *impl_;
  const Index nv = I.N * I.d, ns = I.N * I.d * I.d;
  I.V = Eigen::Map<const Field>(x, I.N, I.d);
  I.sig = Eigen::Map<const Field>(x + nv, I.N, I.d * I.d);
  Index at = nv + ns;
  for (Field* f : I.state) {
    *f = Eigen::Map<const Field>(x + at, I.N, f->cols());
    at += f->size();
  }
  for (int s = 0; s < I.flip_steps; ++s)
    I.step(false);
  I.step(I.opt.velocity != VelocityUpdate::FLIP);
  Eigen::Map<Field>(y, I.N, I.d) = I.V;
  Eigen::Map<Field>(y + nv, I.N, I.d * I.d) = I.sig;
  at = nv + ns;
  for (const Field* f : I.state) {
    Eigen::Map<Field>(y + at, I.N, f->cols()) = *f;
    at += f->size();
  }
}

Eigen::MatrixXd LinearizedStep::dense() const {
  return detail::dense_of(*this);
}

std::string_view to_string(SpectralStatus s) {
  switch (s) {
  case SpectralStatus::Converged:
    return "converged";
  case SpectralStatus::NotConverged:
    return "not converged";
  case SpectralStatus::NonFinite:
    return "non-finite";
  }
  return "?";
}

Eigen::VectorXd power_start(Index rows) {
  Eigen::VectorXd x(rows);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  for (Index i = 0; i < rows; ++i)
    x[i] = normal(rng);
  x.normalize();
  return x;
}

SpectralRadius spectral_radius(const LinearizedStep& T, Index dense_limit) {
  return detail::operator_radius(T, dense_limit);
}

} // namespace smpm
