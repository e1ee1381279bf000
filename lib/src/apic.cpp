// SPDX-License-Identifier: BSD-3-Clause
// APIC's weights and mass operator (stages.hpp; Jiang, Schroeder, Selle, Teran & Stomakhin 2015,
// "The affine particle-in-cell method", ACM TOG 34(4):51): the inertia tensor D_p, the weights
// Ĝ = D_p⁻¹ S Δ over S's pattern, and m̃_A.
#include "sparsempm/stages.hpp"

#include "kernels.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace smpm {

using detail::bad_particle;
using detail::by_dim;

std::array<const double*, 3> ApicWeights::pointers() const {
  std::array<const double*, 3> p{};
  for (size_t b = 0; b < 3; ++b)
    p[b] = g[b].empty() ? nullptr : g[b].data();
  return p;
}

void apic_weights(const ParticleOperators& op, const AffineOffsets& offsets, Shape shape,
                  ApicWeights& weights) {
  const size_t entries = size_t(op.outer[op.rows]);
  for (int b = op.dim; b < 3; ++b)
    weights.g[size_t(b)].clear();
  for (int b = 0; b < op.dim; ++b) {
    SMPM_VERIFY(offsets.delta[size_t(b)].size() >= entries,
                "apic_weights: the affine offsets must be those of the operators");
    weights.g[size_t(b)].resize(entries); // indexed as S (absolute)
  }
  if (shape == Shape::Linear) { // the multilinear limit: Ĝ = ∇S (Jiang et al. 2015 §5.3)
    for (int b = 0; b < op.dim; ++b)
      std::copy(op.G[size_t(b)], op.G[size_t(b)] + entries, weights.g[size_t(b)].begin());
    return;
  }
  by_dim(op.dim, [&]<int D>() {
    using Mat = Eigen::Matrix<double, D, D>;
    using Vec = Eigen::Matrix<double, D, 1>;
    const auto& delta = offsets.delta;
    detail::parallel_for(op.rows, [&](Index q) {
      const int k0 = op.outer[q], k1 = op.outer[q + 1];
      Mat Dp = Mat::Zero(); // D_p = Σ_i S_pi Δ_pi Δ_piᵀ
      for (int k = k0; k < k1; ++k) {
        Vec dk;
        for (int b = 0; b < D; ++b)
          dk[b] = delta[size_t(b)][size_t(k)];
        Dp.noalias() += op.S[k] * dk * dk.transpose();
      }
      const Eigen::LLT<Mat> llt(Dp);
      const double largest = Dp.diagonal().maxCoeff();
      const double pivot = llt.info() == Eigen::Success
                               ? Vec(llt.matrixLLT().diagonal()).cwiseAbs2().minCoeff()
                               : 0.0;
      if (!(pivot > 1e-12 * largest) || !std::isfinite(largest))
        bad_particle(op.first + q,
                     "a singular APIC inertia tensor D_p (its least Cholesky pivot; a collapsed "
                     "domain: try gimp or bspline2)",
                     pivot);
      for (int k = k0; k < k1; ++k) { // Ĝ_pi = D_p⁻¹ S_pi Δ_pi
        Vec dk;
        for (int b = 0; b < D; ++b)
          dk[b] = op.S[k] * delta[size_t(b)][size_t(k)];
        const Vec g = llt.solve(dk);
        for (int b = 0; b < D; ++b)
          weights.g[size_t(b)][size_t(k)] = g[b];
      }
    });
  });
}

ParticleOperators with_weights(const ParticleOperators& op, const ApicWeights& weights) {
  ParticleOperators view = op;
  for (int b = 0; b < op.dim; ++b) {
    SMPM_VERIFY(weights.g[size_t(b)].size() >= size_t(op.outer[op.rows]),
                "with_weights: the APIC weights must be those of the operators");
    view.G[size_t(b)] = weights.g[size_t(b)].data();
  }
  return view;
}

void assemble_apic_mass(const Operators& ops, const ConstFieldRef& X, Shape shape,
                        ConsistentMass& mt) {
  const ParticleOperators op = particle_operators(ops);
  AffineOffsets offsets;
  affine_offsets(op, ops.grid, X, offsets);
  ApicWeights weights;
  apic_weights(op, offsets, shape, weights);
  assemble_affine_mass(ops, X, weights.pointers(), mt);
}

} // namespace smpm
