#include "sparsempm/operators.hpp"

namespace smpm {

void assemble(const Grid& grid, const Particles& particles, Shape shape, Operators& ops) {
  ops.dim = grid.dim();
  assemble_shape(grid, particles, shape, ops.S, ops.G, ops.support);
  ops.M = particles.mass;
  ops.m.noalias() = ops.S.transpose() * ops.M; // m = Sᵀ M
  const double tol = kMassTolerance * (ops.m.size() ? ops.m.maxCoeff() : 0.0);
  ops.active = ops.m.array() > tol;
  ops.m_inv = ops.active.select(ops.m.array().inverse(), 0.0).matrix();
}

Operators assemble(const Grid& grid, const Particles& particles, Shape shape) {
  Operators ops;
  assemble(grid, particles, shape, ops);
  return ops;
}

Eigen::VectorXi active_nodes(const Operators& ops) {
  Eigen::VectorXi idx(ops.active.count());
  for (Index i = 0, k = 0; i < ops.active.size(); ++i)
    if (ops.active[i])
      idx[k++] = int(i);
  return idx;
}

SparseMatrix consistent_mass(const Operators& ops) {
  const SparseRowMatrix MS = ops.M.asDiagonal() * ops.S;
  SparseMatrix mt = SparseMatrix(ops.S.transpose()) * MS;
  return mt;
}

SparseMatrix S_plus(const Operators& ops) {
  SparseMatrix Sp = ops.m_inv.asDiagonal() * SparseMatrix(ops.S.transpose() * ops.M.asDiagonal());
  Sp.prune(0.0);
  return Sp;
}

SparseMatrix expansion_matrix(const Operators& ops) {
  SparseMatrix A = -(ops.m_inv.asDiagonal() * consistent_mass(ops));
  A.prune([&](Index i, Index j, double) { return ops.active[i] && ops.active[j]; });
  const Index n = ops.num_nodes();
  SparseMatrix I(n, n);
  I.reserve(Eigen::VectorXi::Constant(n, 1));
  for (Index i = 0; i < n; ++i)
    if (ops.active[i])
      I.insert(i, i) = 1.0;
  A += I;
  return A;
}

} // namespace smpm
