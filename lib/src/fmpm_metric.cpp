// SPDX-License-Identifier: BSD-3-Clause
// The convergence metric of dynamic FMPM (FMPM 2026 §3.4), in one process and across processes.
#include "sparsempm/fmpm.hpp"

namespace smpm {

namespace {
// The metric of dynamic FMPM across processes: the serial sums over every node once
// (NodeSums::sum_rows of each node's terms), with ε from the largest |v⁺_i| over the processes;
// so every process takes the same decision at each pass.
double distributed_metric(ConvergenceMetric metric, const Field& dv, const Field& v,
                          const Operators& ops, const NodeSums& sums) {
  const Index n = dv.rows();
  const double eps = metric == ConvergenceMetric::Changes
                         ? 0.01 * sums.maximum(n > 0 ? v.rowwise().norm().maxCoeff() : 0.0)
                         : 0.0;
  thread_local Field terms; // each node's numerator and denominator terms
  terms.resize(n, 2);
  for (Index i = 0; i < n; ++i) {
    const double dn = dv.row(i).norm(), vn = v.row(i).norm();
    if (metric == ConvergenceMetric::Means) {
      terms(i, 0) = dn;
      terms(i, 1) = vn;
    } else {
      const double den = vn + eps;
      terms(i, 0) = ops.active[i] && den > 0 ? dn / den : 0.0;
      terms(i, 1) = ops.active[i] ? 1.0 : 0.0;
    }
  }
  double s[2] = {0, 0};
  sums.sum_rows(terms, s);
  return convergence_ratio(MetricSums{s[0], s[1]});
}
} // namespace

double convergence_metric(ConvergenceMetric metric, const Field& dv, const Field& v,
                          const Operators& ops, const NodeSums* sums) {
  if (sums)
    return distributed_metric(metric, dv, v, ops, *sums);
  const double eps =
      metric == ConvergenceMetric::Changes ? 0.01 * v.rowwise().norm().maxCoeff() : 0.0;
  return convergence_ratio(convergence_sums(metric, dv, v, ops.active, eps));
}

MetricSums convergence_sums(ConvergenceMetric metric, const Field& dv, const Field& v,
                            const Eigen::Array<bool, Eigen::Dynamic, 1>& active, double eps) {
  const Eigen::VectorXd dn = dv.rowwise().norm(), vn = v.rowwise().norm();
  MetricSums s;
  if (metric == ConvergenceMetric::Means) {
    // Serial sums in node order: the rows of nodes without mass add zeros, so the bits do not
    // depend on how many such rows the numbering holds (a window of the grid or all of it).
    for (Index i = 0; i < dn.size(); ++i) {
      s.numerator += dn[i];
      s.denominator += vn[i];
    }
    return s;
  }
  for (Index i = 0; i < dn.size(); ++i)
    if (active[i]) {
      const double den = vn[i] + eps;
      s.numerator += den > 0 ? dn[i] / den : 0.0;
      s.denominator += 1;
    }
  return s;
}

} // namespace smpm
