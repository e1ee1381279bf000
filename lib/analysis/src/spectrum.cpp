// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/spectrum.hpp"

#include "dense_of.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/stages.hpp"

#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsSolver.h>

#include <functional>
#include <limits>
#include <vector>

namespace smpm {

namespace {
// y = W x on the active nodes for a symmetric W given by a callback (Spectra's concept).
struct ActiveOp {
  using Scalar = double;
  Index n;
  std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> apply;
  Index rows() const { return n; }
  Index cols() const { return n; }
  void perform_op(const double* x, double* y) const {
    Eigen::VectorXd in = Eigen::Map<const Eigen::VectorXd>(x, n), out(n);
    apply(in, out);
    Eigen::Map<Eigen::VectorXd>(y, n) = out;
  }
};

double largest(const ActiveOp& op, Index dense_limit) {
  if (op.n <= dense_limit) {
    const Eigen::MatrixXd W = detail::dense_of(op);
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (W + W.transpose()),
                                                          Eigen::EigenvaluesOnly)
        .eigenvalues()
        .maxCoeff();
  }
  ActiveOp copy = op;
  Spectra::SymEigsSolver<ActiveOp> eigs(copy, 1, std::min<Index>(op.n, 40));
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestAlge, 5000, 1e-10);
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw NumericalError("Spectra did not converge to an extreme eigenvalue of the mass matrix");
  return eigs.eigenvalues()[0];
}
} // namespace

MassSpectrum mass_spectrum(const Operators& ops, const SparseRowMatrix& mt, Index dense_limit) {
  const Eigen::VectorXi act = active_nodes(ops);
  const Index na = act.size(), n = ops.num_nodes();
  MassSpectrum out;
  out.active = na;
  Eigen::VectorXd r(na); // m^{-1/2}
  for (Index k = 0; k < na; ++k)
    r[k] = 1 / std::sqrt(ops.m[act[k]]);
  Eigen::VectorXd full(n), prod(n);
  auto mt_active = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { // y = m̃_aa x
    full.setZero();
    for (Index k = 0; k < na; ++k)
      full[act[k]] = x[k];
    prod.noalias() = mt * full;
    y.resize(na);
    for (Index k = 0; k < na; ++k)
      y[k] = prod[act[k]];
  };
  // ρ(A) = λ_max(I − B), B = m^{-1/2} m̃ m^{-1/2}.
  ActiveOp IB{na, [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
                Eigen::VectorXd t;
                mt_active(r.cwiseProduct(x), t);
                y = x - r.cwiseProduct(t);
              }};
  out.rho_A = largest(IB, dense_limit);
  out.min_eig_minv_mt = 1 - out.rho_A;
  // cond(m̃): λ_max(m̃), then λ_min(m̃) = λ_max − λ_max(λ_max I − m̃).
  ActiveOp M{na, mt_active};
  const double lmax = largest(M, dense_limit);
  ActiveOp shifted{na, [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
                     mt_active(x, y);
                     y = lmax * x - y;
                   }};
  const double lmin = lmax - largest(shifted, dense_limit);
  out.cond_mt = lmin > 0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  return out;
}

double truncation_error(const Operators& ops, const SparseRowMatrix& mt, const FmpmOptions& opt,
                        const Field& p, const Field& v_exact) {
  Field v;
  lumped_solve(ops.m_inv, p, v);
  FmpmWorkspace w;
  fmpm_loop(ops.m_inv, mt, opt, {}, v, w);
  const double error = (v - v_exact).norm(), scale = v_exact.norm();
  // A model at rest: both are zero and so is the error (never 0/0).
  if (!(scale > 0))
    return error > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  return error / scale;
}

} // namespace smpm
