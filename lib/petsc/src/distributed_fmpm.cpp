// SPDX-License-Identifier: BSD-3-Clause
// FMPM 2026 Table 1 across ranks: the serial loop's control (fmpm_recursion) over PETSc Vecs,
// each pass one MatMult of m̃.
#include "sparsempm/petsc.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <functional>
#include <utility>

namespace smpm::petsc {

namespace {

void ensure_like(OwnedVec& x, Vec like);

// The algebra of fmpm_recursion on distributed vectors: Δv(ℓ) in w.prev, the next in w.next.
struct PetscLoop {
  const DistributedGrid& grid;
  const DistributedOperators& ops;
  const FmpmOptions& opt;
  const LoopConstraints& bc;
  Vec v;
  DistributedFmpmWorkspace& w;
  Field dv_owned, v_owned;

  bool corrects() const { return bc.bcs && opt.bc_method == BCMethod::Incremental; }
  void pass(double c, bool fused) {
    SMPM_PETSC_CALL(MatMult(ops.mt_d, w.prev, w.product));                // m̃ Δv(ℓ−1)
    SMPM_PETSC_CALL(VecPointwiseMult(w.product, ops.m_inv_d, w.product)); // S⁺S Δv = m⁻¹ m̃ Δv
    SMPM_PETSC_CALL(VecWAXPY(w.next, -1.0, w.product, w.prev)); // Δv(ℓ) = A Δv(ℓ−1) (Eq. 6)
    if (c != 1)
      SMPM_PETSC_CALL(VecScale(w.next, c)); // blended recursion (§3.3)
    if (fused)
      SMPM_PETSC_CALL(VecAXPY(v, 1.0, w.next)); // v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ) (Eq. 5)
    std::swap(w.prev, w.next);
  }
  const PolynomialPasses& passes() { return polynomial_passes(opt, w.passes); }
  void polynomial_pass(double a, double b, bool first, bool fused) {
    if (first) { // r(1) = Δv(1)
      ensure_like(w.residual, w.prev);
      SMPM_PETSC_CALL(VecCopy(w.prev, w.residual));
    }
    SMPM_PETSC_CALL(MatMult(ops.mt_d, w.prev, w.product));                // m̃ Δv(ℓ−1)
    SMPM_PETSC_CALL(VecPointwiseMult(w.product, ops.m_inv_d, w.product)); // S⁺S Δv(ℓ−1)
    SMPM_PETSC_CALL(VecAXPY(w.residual, -1.0, w.product)); // r(ℓ) = r(ℓ−1) − S⁺S Δv(ℓ−1)
    SMPM_PETSC_CALL(VecCopy(w.prev, w.next));
    SMPM_PETSC_CALL(VecAXPBY(w.next, a, b, w.residual)); // Δv(ℓ) = a r(ℓ) + b Δv(ℓ−1)
    if (fused)
      SMPM_PETSC_CALL(VecAXPY(v, 1.0, w.next)); // v⁺(ℓ) = v⁺(ℓ−1) + Δv(ℓ)
    std::swap(w.prev, w.next);
  }
  void correct(int) { // (1): Table 2's bottom block on the nodes this rank owns
    if (!corrects())
      return;
    get_owned(grid, w.prev, ops.dim, w.owned);
    bc.bcs->zero_directions(grid.owned(), w.owned);
    set_owned(grid, w.owned, w.prev);
  }
  void accumulate() { SMPM_PETSC_CALL(VecAXPY(v, 1.0, w.prev)); }
  bool tests_convergence() const { return opt.metric != ConvergenceMetric::None; }
  bool converged(int, double& metric) { // (3): the sums of convergence_sums over the ranks
    get_owned(grid, w.prev, ops.dim, dv_owned);
    get_owned(grid, v, ops.dim, v_owned);
    double eps = 0;
    if (opt.metric == ConvergenceMetric::Changes) {
      const double local = v_owned.rows() ? v_owned.rowwise().norm().maxCoeff() : 0.0;
      double largest = 0;
      MPI_Allreduce(&local, &largest, 1, MPI_DOUBLE, MPI_MAX, grid.comm());
      eps = 0.01 * largest;
    }
    const MetricSums local = convergence_sums(opt.metric, dv_owned, v_owned, ops.active, eps);
    double parts[2] = {local.numerator, local.denominator}, sums[2] = {0, 0};
    MPI_Allreduce(parts, sums, 2, MPI_DOUBLE, MPI_SUM, grid.comm());
    metric = convergence_ratio({sums[0], sums[1]});
    return metric < opt.dynamic_limit;
  }
};

void ensure_like(OwnedVec& x, Vec like) {
  PetscInt have = -1, want = 0;
  SMPM_PETSC_CALL(VecGetLocalSize(like, &want));
  if (x.get())
    SMPM_PETSC_CALL(VecGetLocalSize(x, &have));
  if (have != want)
    SMPM_PETSC_CALL(VecDuplicate(like, x.out()));
}

void apply_owned(const DistributedGrid& grid, int components, Vec x, Field& work,
                 const std::function<void(Field&)>& change) {
  get_owned(grid, x, components, work);
  change(work);
  set_owned(grid, work, x);
}

} // namespace

namespace {
// The algebra of fmpm_bc_sequence and grid_velocity_bc_sequence on distributed vectors.
struct PetscSequence {
  const DistributedGrid& grid;
  const DistributedOperators& ops;
  const FmpmOptions& opt;
  const LoopConstraints& bc;
  Vec p_plus; // null: fmpm_velocity, which starts from v⁺(1)
  Vec v;
  DistributedFmpmWorkspace& w;

  void constrain_momentum() {
    Field m_owned;
    get_owned(grid, ops.m, 1, m_owned);
    const Eigen::VectorXd m = m_owned.col(0);
    apply_owned(grid, ops.dim, p_plus, w.owned,
                [&](Field& owned) { bc.bcs->constrain_momentum(grid.owned(), m, bc.time, owned); });
  }
  void lumped_solve() { SMPM_PETSC_CALL(VecPointwiseMult(v, ops.m_inv_d, p_plus)); }
  FmpmReport loop() {
    validate(opt);
    ensure_like(w.prev, v);
    ensure_like(w.next, v);
    ensure_like(w.product, v);
    SMPM_PETSC_CALL(VecCopy(v, w.prev)); // Δv(1) = v⁺(1)
    PetscLoop loop{grid, ops, opt, bc, v, w, {}, {}};
    return fmpm_recursion(opt, loop, w.metrics);
  }
  void constrain_velocity() {
    apply_owned(grid, ops.dim, v, w.owned, [&](Field& owned) {
      bc.bcs->constrain_velocity(grid.owned(), bc.time, owned, &ops.active);
    });
  }
};
} // namespace

FmpmReport fmpm_velocity(const DistributedGrid& grid, const DistributedOperators& ops,
                         const FmpmOptions& opt, const LoopConstraints& bc, Vec v,
                         DistributedFmpmWorkspace& w) {
  PetscSequence seq{grid, ops, opt, bc, nullptr, v, w};
  return fmpm_bc_sequence(opt, bc.bcs != nullptr, seq);
}

FmpmReport updated_velocity(const DistributedGrid& grid, const DistributedOperators& ops,
                            const FmpmOptions& opt, const LoopConstraints& bc, Vec p_plus, Vec v,
                            DistributedFmpmWorkspace& w) {
  PetscSequence seq{grid, ops, opt, bc, p_plus, v, w};
  return grid_velocity_bc_sequence(opt, bc.bcs != nullptr, true, seq);
}

} // namespace smpm::petsc
