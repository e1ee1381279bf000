#include "sparsempm/stability.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/products.hpp"

#include <Eigen/Eigenvalues>
#include <Spectra/GenEigsSolver.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

namespace smpm {

struct LinearizedStep::Impl {
  Model model; // the frozen configuration; V and stress serve as scratch state
  StepOptions opt;
  BoundaryConditions homogeneous; // the BC directions with zero values: Φ
  Operators ops;
  ConsistentMass mt;
  Field K; // N × d⁴ material tangents ∂σ_ab/∂L_cd (row-major ab, cd)
  double dt = 0;
  double speed = 0;   // max(c_wave, max|V_p|) of the frozen configuration (Δt → C)
  int flip_steps = 0; // periodic FMPM: FLIP steps before each FMPM step
  int d = 1;
  Index N = 0;
  // scratch
  mutable Field V, sig, p, f, pplus, v1, v, a, u, L;
  mutable StageWorkspace w;
  mutable FmpmWorkspace fw;

  void step(bool fmpm) const;
};

namespace {
Eigen::Matrix3d embed(const Particles& P, Index q) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  for (int a = 0; a < P.dim; ++a)
    for (int b = 0; b < P.dim; ++b)
      F(a, b) = P.F(q, a * P.dim + b);
  return F;
}
} // namespace

LinearizedStep::LinearizedStep(const Model& model, const StepOptions& options, double dt)
    : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  if (options.scheme != UpdateScheme::USL)
    throw InputError("the linearised step covers the USL scheme only");
  if (options.bc_ordering != BCOrdering::Correct)
    throw InputError("the linearised step covers the correct BC ordering only");
  if (options.velocity == VelocityUpdate::FMPM && options.fmpm.bc_method == BCMethod::Velocity)
    throw InputError("the linearised step does not cover the velocity BC method");
  validate(options.fmpm);
  if (options.velocity == VelocityUpdate::Exact && !options.solver)
    throw InputError("the exact velocity update needs a MassSolver");
  I.model = model;
  I.opt = options;
  I.speed = courant_of(model, 1.0) * model.grid.min_cell_size();
  I.d = model.grid.dim();
  I.N = model.particles.size();
  for (VelocityCondition c : model.bcs.conditions) {
    c.value = nullptr;
    I.homogeneous.conditions.push_back(std::move(c));
  }
  assemble(model.grid, model.particles, options.shape, I.ops);
  const bool full_mass =
      options.velocity == VelocityUpdate::Exact ||
      ((options.velocity == VelocityUpdate::FMPM || options.velocity == VelocityUpdate::XPIC) &&
       options.fmpm.order > 1);
  if (full_mass)
    assemble_consistent_mass(I.ops, I.mt);
  // Material tangents 𝕂_p = ∂σ/∂L from σ((I + ε E_cd) F) by central differences.
  const int d = I.d, d2 = d * d;
  I.K.setZero(I.N, d2 * d2);
  const double eps = 1e-6;
  const Particles& P = model.particles;
  for (Index q = 0; q < I.N; ++q) {
    const Material& mat = model.materials.at(size_t(P.material[q]));
    const Eigen::Matrix3d F = embed(P, q);
    for (int c = 0; c < d; ++c)
      for (int e = 0; e < d; ++e) {
        Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
        E(c, e) = eps;
        const Eigen::Matrix3d dsig =
            (cauchy_stress(mat, d, (Eigen::Matrix3d::Identity() + E) * F) -
             cauchy_stress(mat, d, (Eigen::Matrix3d::Identity() - E) * F)) /
            (2 * eps);
        for (int a = 0; a < d; ++a)
          for (int b = 0; b < d; ++b)
            I.K(q, (a * d + b) * d2 + c * d + e) = dsig(a, b);
      }
  }
  set_dt(dt);
}

LinearizedStep::~LinearizedStep() = default;
LinearizedStep::LinearizedStep(LinearizedStep&&) noexcept = default;

void LinearizedStep::set_dt(double dt) {
  if (!(dt > 0))
    throw InputError("time step must be positive");
  impl_->dt = dt;
  impl_->flip_steps = 0;
  if (impl_->opt.periodic_cx > 0) { // the Stepper's period: ceil(C_X / C) steps
    const double C = dt * impl_->speed / impl_->model.grid.min_cell_size();
    impl_->flip_steps = std::max(0, int(std::ceil(impl_->opt.periodic_cx / C * (1 - 1e-12))) - 1);
  }
}

double LinearizedStep::dt() const {
  return impl_->dt;
}
int LinearizedStep::steps_per_application() const {
  return impl_->flip_steps + 1;
}
Index LinearizedStep::rows() const {
  return impl_->N * (impl_->d + impl_->d * impl_->d);
}
const Operators& LinearizedStep::operators() const {
  return impl_->ops;
}

// One linearised step on (V, sig) in place; fmpm = false gives a FLIP step.
void LinearizedStep::Impl::step(bool fmpm) const {
  Particles& P = const_cast<Particles&>(model.particles);
  P.V = V;
  P.stress = sig;
  const LoopConstraints bc{&model.grid, &homogeneous, 0.0};
  map_momentum(ops, P, p, w);
  homogeneous.zero_directions(p); // Φ p
  internal_force(ops, P, f, w);
  homogeneous.zero_directions(f); // Φ f
  pplus = p + dt * f;
  lumped_solve(ops, pplus, v1);
  lumped_solve(ops, f, a);
  const VelocityUpdate kind = fmpm ? opt.velocity : VelocityUpdate::FLIP;
  const Field* strain_v = &v1;
  switch (kind) {
  case VelocityUpdate::FLIP:
    multiply(ops.S, a, u);
    V += dt * u; // V' = V + Δt S a
    break;
  case VelocityUpdate::XPIC:
    if (opt.fmpm.order > 1) {
      lumped_solve(ops, p, v);
      xpic_grid_velocity(ops, mt.matrix, opt.fmpm.order, v, u, fw);
      u += dt * a;
    } else {
      u = v1;
    }
    multiply(ops.S, u, V);
    break;
  case VelocityUpdate::Exact:
    opt.solver->solve(ops, mt.matrix, bc, pplus, v);
    multiply(ops.S, v, V);
    strain_v = &v;
    break;
  default: // PIC, FMPM(k)
    v = v1;
    if (kind == VelocityUpdate::FMPM && opt.fmpm.order > 1)
      fmpm_loop(ops, mt.matrix, opt.fmpm, bc, v, fw);
    multiply(ops.S, v, V);
    strain_v = &v;
  }
  // σ' = σ + Δt 𝕂 : L with L = G v.
  gradient_product(ops.G, d, *strain_v, L);
  const int d2 = d * d;
  for (Index q = 0; q < N; ++q)
    for (int r = 0; r < d2; ++r) {
      double s = 0;
      for (int c = 0; c < d2; ++c)
        s += K(q, r * d2 + c) * L(q, c);
      sig(q, r) += dt * s;
    }
}

void LinearizedStep::perform_op(const double* x, double* y) const {
  Impl& I = *impl_;
  const Index nv = I.N * I.d, ns = I.N * I.d * I.d;
  I.V = Eigen::Map<const Field>(x, I.N, I.d);
  I.sig = Eigen::Map<const Field>(x + nv, I.N, I.d * I.d);
  for (int s = 0; s < I.flip_steps; ++s)
    I.step(false);
  I.step(I.opt.velocity != VelocityUpdate::FLIP);
  Eigen::Map<Field>(y, I.N, I.d) = I.V;
  Eigen::Map<Field>(y + nv, I.N, I.d * I.d) = I.sig;
  (void)ns;
}

Eigen::MatrixXd LinearizedStep::dense() const {
  const Index n = rows();
  Eigen::MatrixXd T(n, n);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n), col(n);
  for (Index j = 0; j < n; ++j) {
    e[j] = 1;
    perform_op(e.data(), col.data());
    T.col(j) = col;
    e[j] = 0;
  }
  return T;
}

double spectral_radius(const LinearizedStep& T, Index dense_limit) {
  if (T.rows() <= dense_limit)
    return Eigen::EigenSolver<Eigen::MatrixXd>(T.dense(), false)
        .eigenvalues()
        .cwiseAbs()
        .maxCoeff();
  // Large T: the spectrum crowds the unit circle (eigenvalue 1 for every force-free stress,
  // |λ| ≈ 1 for every elastic mode), where Arnoldi converges very slowly. Power iteration first
  // measures the growth per application over the second half of 300 applications; growth within
  // 10⁻³ of 1 is reported as ρ = 1. Otherwise an eigenvalue stands out and Spectra's Arnoldi
  // solver, started from the power iterate, resolves it.
  const Index n = T.rows();
  Eigen::VectorXd x(n), y(n);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  for (Index i = 0; i < n; ++i)
    x[i] = normal(rng);
  x.normalize();
  const int applications = 300;
  double log_growth = 0;
  for (int k = 0; k < applications; ++k) {
    T.perform_op(x.data(), y.data());
    const double g = y.norm();
    if (!(g > 0) || !std::isfinite(g))
      return g > 0 ? g : 0.0;
    if (k >= applications / 2)
      log_growth += std::log(g);
    x = y / g;
  }
  const double rate = std::exp(log_growth / (applications - applications / 2));
  if (std::abs(rate - 1) <= 1e-3)
    return 1.0;
  if (rate < 1)
    return rate;
  struct Op { // Spectra's operator concept over a const T
    using Scalar = double;
    const LinearizedStep& T;
    Index rows() const { return T.rows(); }
    Index cols() const { return T.cols(); }
    void perform_op(const double* in, double* out) const { T.perform_op(in, out); }
  } op{T};
  Spectra::GenEigsSolver<Op> eigs(op, 1, std::min<Index>(n, 30));
  eigs.init(x.data());
  eigs.compute(Spectra::SortRule::LargestMagn, 300, 1e-10);
  if (eigs.info() != Spectra::CompInfo::Successful)
    return rate; // the measured growth: already beyond 1 + 10⁻³
  return std::abs(eigs.eigenvalues()[0]);
}

double courant_of(const Model& model, double dt) {
  const double c = max_wave_speed(model.materials, model.particles);
  const double vmax = model.particles.size() ? model.particles.V.rowwise().norm().maxCoeff() : 0;
  return dt * std::max(c, vmax) / model.grid.min_cell_size();
}

CriticalCourant critical_courant(const Model& model, const StepOptions& options, double tol,
                                 double c_max, double resolution) {
  const double dt_per_c = 1.0 / courant_of(model, 1.0); // Δt for C = 1
  LinearizedStep T(model, options, 0.05 * dt_per_c);
  CriticalCourant out;
  auto stable = [&](double C, double& rho) {
    T.set_dt(C * dt_per_c);
    rho = std::pow(spectral_radius(T), 1.0 / T.steps_per_application()); // growth per step
    ++out.evaluations;
    return rho <= 1 + tol;
  };
  double lo = 0, hi = 0.05, rho_lo = 1, rho = 0;
  while (stable(hi, rho)) { // bracket: lo stable, hi unstable
    lo = hi;
    rho_lo = rho;
    if (hi >= c_max) {
      out.courant = lo;
      out.rho = rho_lo;
      return out;
    }
    hi = std::min(2 * hi, c_max);
  }
  while (hi - lo > resolution) {
    const double mid = 0.5 * (lo + hi);
    if (stable(mid, rho)) {
      lo = mid;
      rho_lo = rho;
    } else {
      hi = mid;
    }
  }
  out.courant = lo;
  out.rho = rho_lo;
  return out;
}

Model shifted(const Model& model, const std::array<double, 3>& shift) {
  Model m = model;
  for (int a = 0; a < m.grid.dim(); ++a)
    m.particles.X.col(a).array() += shift[size_t(a)] * m.grid.cell_size(a);
  (void)assemble(m.grid, m.particles, Shape::Linear); // throws if a particle left the grid
  return m;
}

ConfigurationSweep sweep_shifts(const Model& model, const StepOptions& options, int shifts,
                                double tol, double resolution) {
  if (shifts < 1)
    throw InputError("the number of lattice shifts must be at least 1");
  ConfigurationSweep out;
  out.minimum.courant = std::numeric_limits<double>::infinity();
  // The lattice repeats itself after one particle spacing 2 r⁰: shifts j/shifts of it (in cells
  // along each axis) reach every distinct position of the lattice relative to the grid.
  std::array<double, 3> period{0, 0, 0};
  for (int a = 0; a < model.grid.dim(); ++a)
    period[size_t(a)] = model.particles.size()
                            ? 2 * model.particles.half_length(0, a) / model.grid.cell_size(a)
                            : 1.0;
  for (int j = 0; j < shifts; ++j) {
    const double f = double(j) / shifts;
    const std::array<double, 3> s{f * period[0], f * period[1], f * period[2]};
    std::ostringstream name;
    name << "shift " << s[0];
    const CriticalCourant c = critical_courant(shifted(model, s), options, tol, 2.0, resolution);
    out.all.emplace_back(name.str(), c.courant);
    if (c.courant < out.minimum.courant) {
      out.minimum = c;
      out.configuration = name.str();
    }
  }
  return out;
}

} // namespace smpm
