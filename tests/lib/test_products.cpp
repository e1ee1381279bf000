// The single-pass products equal the Eigen expressions they implement (round-off: 1e-13
// relative to the largest entry), on CPDI operators of random 2D and 3D clouds.

#include "support.hpp"

using namespace smpm;

TEST_CASE("single-pass sparse products equal their Eigen expressions", "[products]") {
  for (int dim = 1; dim <= 3; ++dim) {
    CAPTURE(dim);
    const Grid g = smpm::test::test_grid(dim, 10);
    const Particles P = smpm::test::random_cloud(g, 80, 3u + dim, 3.0, true);
    const Operators ops = assemble(g, P, Shape::CPDI);
    const Index n = g.num_nodes(), N = P.size();
    for (int c : {1, 2, 3, 4, 6, 7}) {
      CAPTURE(c);
      const Field X = Field::Random(n, c), Xp = Field::Random(N, c);
      Field Y;
      multiply(ops.S, X, Y);
      CHECK((Y - Field(ops.S * X)).cwiseAbs().maxCoeff() < 1e-13);
      multiply_transpose(ops.S, Xp, Y);
      CHECK((Y - Field(ops.S.transpose() * Xp)).cwiseAbs().maxCoeff() < 1e-13);
    }
    // L(p, a d + b) = (G_b v)_{pa}.
    const Field v = Field::Random(n, dim);
    Field L;
    gradient_product(ops.G, dim, v, L);
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b) {
        const Eigen::VectorXd expected = ops.G[b] * v.col(a);
        CHECK((L.col(a * dim + b) - expected).cwiseAbs().maxCoeff() < 1e-12);
      }
    // f(i, a) = Σ_b (G_bᵀ T_{·(a,b)})_i.
    const Field T = Field::Random(N, dim * dim);
    Field f;
    divergence_product(ops.G, dim, T, f);
    for (int a = 0; a < dim; ++a) {
      Eigen::VectorXd expected = Eigen::VectorXd::Zero(n);
      for (int b = 0; b < dim; ++b)
        expected += ops.G[b].transpose() * T.col(a * dim + b);
      CHECK((f.col(a) - expected).cwiseAbs().maxCoeff() < 1e-12);
    }
  }
}
