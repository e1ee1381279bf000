// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/fmpm.hpp"

#include "enum_names.hpp"
#include "kernels.hpp"
#include "parallel.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/stages.hpp"

#include <cmath>
#include <string>

namespace smpm {

namespace {
constexpr detail::EnumNames<BCMethod, 4> kBCMethods{{{BCMethod::Incremental, "incremental"},
                                                     {BCMethod::Lumped, "lumped"},
                                                     {BCMethod::Velocity, "velocity"},
                                                     {BCMethod::Combined, "combined"}}};
constexpr detail::EnumNames<ConvergenceMetric, 3> kMetrics{
    {{ConvergenceMetric::None, "none"},
     {ConvergenceMetric::Means, "means"},
     {ConvergenceMetric::Changes, "changes"}}};
constexpr detail::EnumNames<Polynomial, 4> kPolynomials{
    {{Polynomial::Series, "series"},
     {Polynomial::Chebyshev, "chebyshev"},
     {Polynomial::LeastSquares, "least_squares"},
     {Polynomial::ChebyshevSquared, "chebyshev_squared"}}};
} // namespace

std::string_view to_string(BCMethod m) {
  return detail::enum_name(m, kBCMethods);
}
BCMethod bc_method_from_string(std::string_view name) {
  return detail::parse_enum(name, kBCMethods, "BC method");
}
std::string_view to_string(ConvergenceMetric m) {
  return detail::enum_name(m, kMetrics);
}
ConvergenceMetric convergence_metric_from_string(std::string_view name) {
  return detail::parse_enum(name, kMetrics, "convergence metric");
}
std::string_view to_string(Polynomial p) {
  return detail::enum_name(p, kPolynomials);
}
Polynomial polynomial_from_string(std::string_view name) {
  return detail::parse_enum(name, kPolynomials, "polynomial");
}

void validate(const FmpmOptions& opt) {
  const std::string range = "must be an integer from 1 to " + std::to_string(kMaxFmpmOrder);
  if (opt.order < 1 || opt.order > kMaxFmpmOrder)
    throw OptionError("order", std::to_string(opt.order), range);
  if (!(opt.blend_alpha >= 0 && opt.blend_alpha <= 1))
    throw OptionError("blend_alpha", number_text(opt.blend_alpha), "must lie in [0, 1]");
  if (opt.blend_every < 1 || opt.blend_every > kMaxFmpmOrder)
    throw OptionError("blend_every", std::to_string(opt.blend_every), range);
  if (!(opt.dynamic_limit >= 0) || !std::isfinite(opt.dynamic_limit))
    throw OptionError("dynamic_limit", number_text(opt.dynamic_limit),
                      "must be non-negative and finite");
  if (!(opt.interval_low >= 0 && opt.interval_low < 1))
    throw OptionError("interval_low", number_text(opt.interval_low), "must lie in [0, 1)");
  if (opt.polynomial == Polynomial::Series)
    return;
  if (opt.blend_alpha != 1)
    throw OptionError("blend_alpha", number_text(opt.blend_alpha),
                      "blends the series only; the " + std::string(to_string(opt.polynomial)) +
                          " polynomial takes none (1)");
  if ((opt.polynomial == Polynomial::Chebyshev || opt.polynomial == Polynomial::ChebyshevSquared) &&
      !(opt.interval_low > 0 && opt.interval_low < 1))
    throw OptionError("interval_low", number_text(opt.interval_low),
                      "the Chebyshev interval [interval_low, 1] needs 0 < interval_low < 1 "
                      "(smpm spectrum prints min eig(m^-1 m~))");
  if (opt.polynomial == Polynomial::ChebyshevSquared && opt.metric != ConvergenceMetric::None)
    throw OptionError("dynamic_metric", std::string(to_string(opt.metric)),
                      "dynamic FMPM would stop the squared Chebyshev loop before its second half, "
                      "where R_k is not the non-negative C_m^2 (set dynamic_metric = \"none\")");
  if (opt.polynomial == Polynomial::LeastSquares && opt.order > kMaxLeastSquaresOrder)
    throw OptionError("order", std::to_string(opt.order),
                      "the least-squares polynomial takes orders up to " +
                          std::to_string(kMaxLeastSquaresOrder));
}

double blend_factor(const FmpmOptions& opt, int ell) {
  return (opt.blend_every == 1 || ell % opt.blend_every == 1) ? opt.blend_alpha : 1.0;
}

namespace {
// y_i = m_i⁻¹ Σ_j m̃_ij x_j into row i of y, then finish(i, y_i); the column count is a
// compile-time constant when small. One row per iteration, so the threads write disjoint rows.
template <class Finish>
void reverse_map_rows(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, const Field& x,
                      Field& y, Finish&& finish) {
  const int* outer = mt.outerIndexPtr();
  const int* inner = mt.innerIndexPtr();
  const double* val = mt.valuePtr();
  const int c = int(x.cols());
  y.resize(mt.rows(), c);
  auto rows = [&]<int C>() {
    const int cols = C ? C : c;
    detail::parallel_for(mt.rows(), [&](Index i) {
      double acc[C ? C : 1];
      double* yi = y.data() + i * cols;
      double* out = C ? acc : yi;
      for (int a = 0; a < cols; ++a)
        out[a] = 0;
      for (int k = outer[i]; k < outer[i + 1]; ++k) {
        const double* xj = x.data() + Index(inner[k]) * cols;
        for (int a = 0; a < cols; ++a)
          out[a] += val[k] * xj[a];
      }
      for (int a = 0; a < cols; ++a)
        yi[a] = out[a] * m_inv[i];
      finish(i, cols, yi);
    });
  };
  if (!detail::dispatch_int<1, 2, 3>(c, rows))
    rows.template operator()<0>();
}

void check_product(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, const Field& x) {
  SMPM_VERIFY(mt.rows() == mt.cols() && x.rows() == mt.cols() && m_inv.size() == mt.rows(),
              "reverse_map_product: m~ must be n x n, x n x d and m_inv of size n");
}
} // namespace

void reverse_map_product(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, const Field& x,
                         Field& y) {
  check_product(m_inv, mt, x);
  reverse_map_rows(m_inv, mt, x, y, [](Index, int, double*) {});
}

void fmpm_pass(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, double c, const Field& dv,
               Field& next, Field* v) {
  check_product(m_inv, mt, dv);
  SMPM_VERIFY(&next != &dv && (!v || v->rows() == dv.rows()),
              "fmpm_pass: next must not alias dv, and v must have dv's rows");
  // The blend and the update of v as compile-time switches: the row loop stays branch-free.
  auto rows = [&]<bool Blend, bool AddV>() {
    reverse_map_rows(m_inv, mt, dv, next, [&](Index i, int cols, double* out) {
      const double* d = dv.data() + i * cols;
      for (int a = 0; a < cols; ++a) {
        out[a] = d[a] - out[a]; // Δv(ℓ) = Δv(ℓ−1) − S⁺S Δv(ℓ−1) = A Δv(ℓ−1)   (Eq. 6)
        if constexpr (Blend)
          out[a] *= c; // blended recursion (§3.3)
      }
      if constexpr (AddV) {
        double* vi = v->data() + i * cols;
        for (int a = 0; a < cols; ++a)
          vi[a] += out[a]; // v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ)                   (Eq. 5)
      }
    });
  };
  if (c != 1)
    v ? rows.template operator()<true, true>() : rows.template operator()<true, false>();
  else
    v ? rows.template operator()<false, true>() : rows.template operator()<false, false>();
}

namespace {
// One pass of a Chebyshev or least-squares member in one sweep over the rows of m̃:
// r −= m⁻¹ m̃ dv, next = a r + b dv and, when v is given, v += next (PolynomialPasses).
void polynomial_sweep(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt, double a, double b,
                      const Field& dv, Field& r, Field& next, Field* v) {
  check_product(m_inv, mt, dv);
  reverse_map_rows(m_inv, mt, dv, next, [&](Index i, int cols, double* out) {
    const double* d = dv.data() + i * cols;
    double* ri = r.data() + i * cols;
    for (int c = 0; c < cols; ++c) {
      ri[c] -= out[c];               // r(ℓ) = r(ℓ−1) − S⁺S Δv(ℓ−1)
      out[c] = a * ri[c] + b * d[c]; // Δv(ℓ) = a_ℓ r(ℓ) + b_ℓ Δv(ℓ−1)
    }
    if (v) {
      double* vi = v->data() + i * cols;
      for (int c = 0; c < cols; ++c)
        vi[c] += out[c]; // v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ)
    }
  });
}
} // namespace

FmpmReport fmpm_loop(const Eigen::VectorXd& m_inv, const SparseRowMatrix& mt,
                     const FmpmOptions& opt, const FmpmHooks& hooks, Field& v, FmpmWorkspace& w) {
  // The algebra of fmpm_recursion on Eigen fields: Δv(ℓ) in w.prev, the next one in w.next.
  struct EigenLoop {
    const Eigen::VectorXd& m_inv;
    const SparseRowMatrix& mt;
    const FmpmOptions& opt;
    const FmpmHooks& hooks;
    Field& v;
    FmpmWorkspace& w;
    bool corrects() const { return bool(hooks.velocity_bcs) || bool(hooks.contact); }
    void pass(double c, bool fused) {
      if (hooks.sums) { // across processes: m̃ Δv summed over them, then Eq. 6
        w.dv.noalias() = mt * w.prev;
        hooks.sums->add(w.dv);
        w.next = c * (w.prev - m_inv.asDiagonal() * w.dv);
        if (fused)
          v += w.next;
      } else {
        fmpm_pass(m_inv, mt, c, w.prev, w.next, fused ? &v : nullptr);
      }
      w.prev.swap(w.next);
    }
    const PolynomialPasses& passes() { return polynomial_passes(opt, w.passes); }
    void polynomial_pass(double a, double b, bool first, bool fused) {
      if (first)
        w.residual = w.prev; // r(1) = Δv(1)
      if (hooks.sums) {      // across processes: m̃ Δv summed over them
        w.dv.noalias() = mt * w.prev;
        hooks.sums->add(w.dv);
        w.residual -= m_inv.asDiagonal() * w.dv;
        w.next = a * w.residual + b * w.prev;
        if (fused)
          v += w.next;
      } else {
        polynomial_sweep(m_inv, mt, a, b, w.prev, w.residual, w.next, fused ? &v : nullptr);
      }
      w.prev.swap(w.next);
    }
    void correct(int ell) {
      if (hooks.velocity_bcs)
        hooks.velocity_bcs(ell, w.prev); // (1)
      if (hooks.contact)
        hooks.contact(ell, w.prev, v); // (2)
    }
    void accumulate() { v += w.prev; }
    bool tests_convergence() const { return bool(hooks.converged); }
    bool converged(int ell, double& metric) { return hooks.converged(ell, w.prev, v, metric); }
  };
  w.prev = v; // Δv(1) = v⁺(1)
  EigenLoop loop{m_inv, mt, opt, hooks, v, w};
  return fmpm_recursion(opt, loop, w.metrics);
}

FmpmHooks fmpm_hooks(const Operators& ops, const FmpmOptions& opt, const LoopConstraints& bc) {
  FmpmHooks hooks;
  hooks.sums = bc.sums;
  if (bc.bcs && opt.bc_method == BCMethod::Incremental) // Table 2, bottom block
    hooks.velocity_bcs = [bcs = bc.bcs, grid = bc.grid](int, Field& dv) {
      bcs->zero_directions(*grid, dv);
    };
  if (opt.metric != ConvergenceMetric::None) // dynamic FMPM (§3.4), over every process's nodes
    hooks.converged = [&ops, sums = bc.sums, metric = opt.metric, limit = opt.dynamic_limit](
                          int, const Field& dv, const Field& v, double& value) {
      value = convergence_metric(metric, dv, v, ops, sums);
      return value < limit;
    };
  return hooks;
}

namespace {
// The algebra of fmpm_bc_sequence and grid_velocity_bc_sequence on Eigen fields.
struct EigenSequence {
  const Operators& ops;
  const SparseRowMatrix* mt;
  const FmpmOptions& opt;
  const LoopConstraints& bc;
  double dt;
  Field& p_plus;
  Field* reaction;
  Field& v;
  FmpmWorkspace& w;
  const std::function<void(int, Field&, const Field&)>& contact;

  void constrain_momentum() {
    if (reaction) // task 2.a: p⁺ takes the BC velocity and f the reaction Δp/Δt
      bc.bcs->constrain_update(*bc.grid, ops.m, bc.time, dt, p_plus, *reaction);
    else
      bc.bcs->constrain_momentum(*bc.grid, ops.m, bc.time, p_plus);
  }
  void lumped_solve() { smpm::lumped_solve(ops.m_inv, p_plus, v); }
  FmpmReport loop() {
    SMPM_VERIFY(mt, "updated_velocity: FMPM(k > 1) needs m~");
    FmpmHooks hooks = fmpm_hooks(ops, opt, bc);
    hooks.contact = contact;
    return fmpm_loop(ops.m_inv, *mt, opt, hooks, v, w);
  }
  void constrain_velocity() { bc.bcs->constrain_velocity(*bc.grid, bc.time, v, &ops.active); }
};
} // namespace

FmpmReport fmpm_velocity(const Operators& ops, const SparseRowMatrix& mt, const FmpmOptions& opt,
                         const LoopConstraints& bc, Field& v, FmpmWorkspace& w,
                         const std::function<void(int, Field&, const Field&)>& contact) {
  EigenSequence seq{ops, &mt, opt, bc, 0, v, nullptr, v, w, contact};
  return fmpm_bc_sequence(opt, bc.bcs != nullptr, seq);
}

FmpmReport updated_velocity(const Operators& ops, const SparseRowMatrix* mt, const FmpmOptions& opt,
                            const LoopConstraints& bc, bool lumped_bcs, double dt, Field& p_plus,
                            Field* reaction, Field& v, FmpmWorkspace& w,
                            const std::function<void(int, Field&, const Field&)>& contact) {
  EigenSequence seq{ops, mt, opt, bc, dt, p_plus, reaction, v, w, contact};
  return grid_velocity_bc_sequence(opt, bc.bcs != nullptr, lumped_bcs, seq);
}

void xpic_grid_velocity(const Operators& ops, const SparseRowMatrix& mt, int m, const Field& v,
                        Field& u, FmpmWorkspace& w, const Field* dv) {
  SMPM_VERIFY(m >= 1, "XPIC order must be at least 1, got " + std::to_string(m));
  // v* = Σ_{k=2}^{m} (−1)^k (v*_k + ((m − 1)/m) Δv*_{k−1}) with
  // v*_k = ((m + 1 − k)/k) S⁺S v*_{k−1} and Δv*_k = ((m − k)/k) S⁺S Δv*_{k−1}  (Eqs. 42–44)
  w.prev = v;
  if (dv)
    w.dv = *dv; // Δv*_1 = Δv
  u.setZero(v.rows(), v.cols());
  for (int k = 2; k <= m; ++k) {
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    if (dv) { // ((m − 1)/m) Δv*_{k−1}, then Δv*_k
      u += (sign * double(m - 1) / m) * w.dv;
      reverse_map_product(ops.m_inv, mt, w.dv, w.next);
      w.dv = (double(m - k) / k) * w.next;
    }
    reverse_map_product(ops.m_inv, mt, w.prev, w.next);
    w.prev = (double(m + 1 - k) / k) * w.next;
    u += sign * w.prev;
  }
  u = double(m) * (v - u); // P V = m S (v − v*)                          (Eq. 41)
}

SparseMatrix fmpm_inverse(const Operators& ops, const FmpmOptions& opt) {
  validate(opt);
  const SparseMatrix A = expansion_matrix(ops);
  const Index n = ops.num_nodes();
  SparseMatrix term(n, n), sum(n, n);
  term.setIdentity();
  for (Index i = 0; i < n; ++i) // identity on active nodes only
    if (!ops.active[i])
      term.coeffRef(i, i) = 0;
  term.prune(0.0);
  sum = term;
  if (opt.polynomial == Polynomial::Series) {
    for (int ell = 2; ell <= opt.order; ++ell) {
      term = SparseMatrix(blend_factor(opt, ell) * (A * term));
      sum += term;
    }
  } else { // the passes of fmpm_recursion on matrices, m⁻¹m̃ Δv = Δv − A Δv
    const PolynomialPasses passes = polynomial_passes(opt);
    SparseMatrix residual = term;
    for (int ell = 2; ell <= opt.order; ++ell) {
      residual = SparseMatrix(residual - term + A * term);
      term = SparseMatrix(passes.a[size_t(ell - 2)] * residual + passes.b[size_t(ell - 2)] * term);
      sum += term;
    }
  }
  return sum * ops.m_inv.asDiagonal();
}

} // namespace smpm
