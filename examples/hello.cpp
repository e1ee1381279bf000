// SPDX-License-Identifier: BSD-3-Clause
// hello: MPM as matrices in one page.
//
// What it shows: the operators of one MPM step for four particles on a 1D grid of three cells
// (linear shape functions): S, the lumped mass m = SᵀM, the consistent mass m̃ = SᵀMS and the
// FMPM expansion matrix A = I − m⁻¹m̃ (FMPM 2026 §2.1, Eq. 1), and the spectrum of A.
// How to run: build/examples/hello
// What to look at: the rows of m̃ sum to m, and the eigenvalues of A lie in [0, 1), so the
// series (I + A + A² + …) m⁻¹ of FMPM(k) converges to m̃⁻¹.

#include <sparsempm/sparsempm.hpp>

#include <Eigen/Dense>
#include <iostream>

int main() {
  using namespace smpm;
  // 1. A 1D grid of 3 cells of size 1 (nodes at 0, 1, 2, 3) and 4 particles of mass 1/4.
  const Grid grid(1, {0, 0, 0}, {1, 1, 1}, {3, 1, 1});
  Particles particles = make_block(grid, {0.5, 0, 0}, {2.5, 0, 0}, {2, 1, 1}, 0.5, 0);
  particles.V.col(0) << 1.0, 1.0, -1.0, -1.0;

  // 2. Assemble the operators of the current configuration.
  const Operators ops = assemble(grid, particles, Shape::Linear);
  Eigen::IOFormat fmt(4, 0, "  ", "\n", "  [", "]");
  std::cout << "S (N x n):\n" << Eigen::MatrixXd(ops.S).format(fmt) << "\n";
  std::cout << "lumped mass m = S^T M:\n" << ops.m.transpose().format(fmt) << "\n";

  // 3. Momentum and lumped-mass velocity: p = S^T M V, v = m^-1 p.
  const Eigen::VectorXd p = ops.S.transpose() * (ops.M.asDiagonal() * particles.V);
  std::cout << "grid momentum p:\n" << p.transpose().format(fmt) << "\n";
  std::cout << "lumped velocity v = m^-1 p:\n"
            << ops.m_inv.cwiseProduct(p).transpose().format(fmt) << "\n";

  // 4. Consistent mass and expansion matrix.
  const Eigen::MatrixXd mt(consistent_mass(ops));
  const Eigen::MatrixXd A(expansion_matrix(ops));
  std::cout << "consistent mass m~ = S^T M S:\n" << mt.format(fmt) << "\n";
  std::cout << "row sums of m~ (= m):\n" << mt.rowwise().sum().transpose().format(fmt) << "\n";
  std::cout << "A = I - m^-1 m~:\n" << A.format(fmt) << "\n";

  // 5. Spectrum of A (real: A is similar to a symmetric matrix).
  const Eigen::VectorXd mu = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().real();
  std::cout << "eigenvalues of A:\n" << mu.transpose().format(fmt) << "\n";
  const bool in_range = mu.minCoeff() > -1e-12 && mu.maxCoeff() < 1;
  std::cout << "spec(A) in [0, 1): " << (in_range ? "yes" : "no") << "\n";
  return in_range ? 0 : 1;
}
