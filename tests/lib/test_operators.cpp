// SPDX-License-Identifier: BSD-3-Clause
// Matrix identities of the assembled operators (FMPM 2026 §2.1, Eq. 1): m = SᵀM, rows of
// m̃ sum to m, m̃ symmetric positive semidefinite, spec(m⁻¹m̃) ⊂ (0, 1], spec(A) ⊂ [0, 1).

#include "support.hpp"

#include <Eigen/Dense>

using namespace smpm;
using smpm::test::approx;

namespace {
Eigen::MatrixXd active_block(const SparseMatrix& A, const Eigen::VectorXi& act) {
  const Eigen::MatrixXd D(A);
  return D(act, act);
}
} // namespace

TEST_CASE("lumped and consistent mass identities on random clouds", "[operators]") {
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI}) {
      CAPTURE(dim, to_string(shape));
      const Grid g = smpm::test::test_grid(dim, 10);
      const Particles P = smpm::test::random_cloud(g, 60, 31u * dim, 3.0, true);
      const Operators ops = assemble(g, P, shape);
      const double scale = ops.m.maxCoeff();
      // Σ m_i = Σ M_p (mass is conserved by the partition of unity).
      CHECK(ops.m.sum() == approx(P.mass.sum(), 0, 1e-13));
      const SparseMatrix mt = consistent_mass(ops);
      const Eigen::VectorXd one = Eigen::VectorXd::Ones(g.num_nodes());
      // Rows of m̃ sum to m: m̃ 1 = Sᵀ M S 1 = Sᵀ M = m.
      CHECK((mt * one - ops.m).cwiseAbs().maxCoeff() < 1e-13 * scale);
      // Symmetric to round-off.
      CHECK((Eigen::MatrixXd(mt) - Eigen::MatrixXd(mt).transpose()).cwiseAbs().maxCoeff() <
            1e-14 * scale);
      // S⁺S 1 = m⁻¹ Sᵀ M S 1 = m⁻¹ m = 1 on active nodes.
      const SparseMatrix SpS = S_plus(ops) * SparseMatrix(ops.S);
      const Eigen::VectorXi act = active_nodes(ops);
      const Eigen::VectorXd rows = SpS * one;
      CHECK((rows(act).array() - 1.0).abs().maxCoeff() < 1e-13);
    }
}

TEST_CASE("spectrum of m^-1 m~ lies in (0, 1] and spec(A) in [0, 1)", "[operators]") {
  // Dense Eigen eigensolvers on small jittered lattices with 3 particles per cell per axis,
  // dense enough that m̃ is non-singular on the active nodes.
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI}) {
      CAPTURE(dim, to_string(shape));
      const int cells = dim == 3 ? 7 : 9;
      const Grid g(dim, {0, 0, 0}, {1, 0.5, 2}, {cells, cells, cells});
      const int count = dim == 3 ? 2 : 4;
      const Particles P = smpm::test::jittered_lattice(g, 3, count, 3, 0.3, 11u * dim);
      const Operators ops = assemble(g, P, shape);
      const Eigen::VectorXi act = active_nodes(ops);
      const Eigen::MatrixXd mt = active_block(consistent_mass(ops), act);
      const Eigen::VectorXd m = ops.m(act);
      // PSD (in fact PD here): eigenvalues of the symmetric m̃.
      const Eigen::VectorXd lam_mt =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(mt).eigenvalues();
      CHECK(lam_mt.minCoeff() > 0.0);
      // m⁻¹m̃ is similar to the symmetric m^{-1/2} m̃ m^{-1/2}.
      const Eigen::VectorXd r = m.cwiseSqrt().cwiseInverse();
      const Eigen::MatrixXd B = r.asDiagonal() * mt * r.asDiagonal();
      const Eigen::VectorXd lam = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(B).eigenvalues();
      CHECK(lam.minCoeff() > 0.0);
      CHECK(lam.maxCoeff() == approx(1.0, 1e-12)); // the constant vector: m⁻¹m̃ 1 = 1
      // spec(A) = 1 − spec(m⁻¹m̃) ⊂ [0, 1): from the nonsymmetric A itself.
      const Eigen::MatrixXd A = active_block(expansion_matrix(ops), act);
      const Eigen::VectorXcd mu = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues();
      CHECK(mu.imag().cwiseAbs().maxCoeff() < 1e-10);
      CHECK(mu.real().minCoeff() > -1e-12);
      CHECK(mu.real().maxCoeff() < 1.0);
      // A = I − S⁺S (FMPM 2026 Eq. 1).
      const SparseMatrix SpS = S_plus(ops) * SparseMatrix(ops.S);
      const Eigen::MatrixXd IA =
          Eigen::MatrixXd::Identity(act.size(), act.size()) - active_block(SpS, act);
      CHECK((IA - A).cwiseAbs().maxCoeff() < 1e-13);
    }
}
