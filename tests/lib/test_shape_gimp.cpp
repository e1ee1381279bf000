// SPDX-License-Identifier: BSD-3-Clause
// uGIMP (Buzzi Eqs. 17-18): the average of the hat over the particle's domain, its closed forms
// against the integrals, and the domain it refuses.

#include "support.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <random>

using namespace smpm;
using smpm::test::approx;

TEST_CASE("1D uGIMP averages the hat over the particle domain", "[shape]") {
  // Domain [0.85, 1.35] around node 1: (1/0.5)(∫_{-0.15}^0 (1+r) dr + ∫_0^{0.35} (1−r) dr)
  //   = (0.13875 + 0.28875)/0.5 = 0.855; gradient (N_1(1.35) − N_1(0.85))/0.5 = −0.2/0.5.
  const Grid g(1, {0, 0, 0}, {1, 1, 1}, {4, 1, 1});
  Particles P;
  P.resize(1, 1);
  P.X(0, 0) = 1.1;
  P.half_length(0, 0) = 0.25;
  P.mass[0] = 1;
  const Operators ops = assemble(g, P, Shape::GIMP);
  CHECK(Eigen::MatrixXd(ops.S)(0, 1) == approx(0.855, 1e-14));
  CHECK(Eigen::MatrixXd(ops.G[0])(0, 1) == approx(-0.4, 1e-14));
}

TEST_CASE("uGIMP's closed forms equal the integrals of the hat over the domain", "[shape]") {
  // The assembly takes the hats at the centre of each part of the domain (shape_points.cpp);
  // here each entry is the integral form of Buzzi Eqs. 17-18 evaluated independently,
  // S_i = (H(r + l) - H(r - l))/(2l), G_i = (hat(r + l) - hat(r - l))/(2lh), on domains within
  // one cell (2 nodes), across one node (3 nodes, also 2l > 1) and across two (4 nodes, the
  // integrals), at seeded random positions. Round-off of values of size 1 and 1/h: 1e-14 and
  // 1e-13 / h.
  auto hat = [](double r) { return std::max(0.0, 1 - std::abs(r)); };
  auto H = [](double r) { // the antiderivative of the hat
    if (r <= -1)
      return 0.0;
    if (r <= 0)
      return 0.5 * (1 + r) * (1 + r);
    if (r <= 1)
      return 1 - 0.5 * (1 - r) * (1 - r);
    return 1.0;
  };
  for (double h : {1.0, 0.37}) {
    const Grid g(1, {-0.5, 0, 0}, {h, 1, 1}, {20, 1, 1});
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(3 * h, 17 * h), half(0.05, 1.2);
    Particles P;
    const int n = 400;
    P.resize(1, n);
    for (int p = 0; p < n; ++p) {
      P.X(p, 0) = pos(rng);
      P.half_length(p, 0) = half(rng) * h;
      P.mass[p] = 1;
    }
    const Operators ops = assemble(g, P, Shape::GIMP);
    int boxes[13] = {};
    for (int p = 0; p < n; ++p) {
      const double l = P.half_length(p, 0) / h;
      ++boxes[ops.S.outerIndexPtr()[p + 1] - ops.S.outerIndexPtr()[p]];
      for (SparseRowMatrix::InnerIterator it(ops.S, p), gt(ops.G[0], p); it; ++it, ++gt) {
        const double r = (P.X(p, 0) - g.node_coordinate(it.col(), 0)) / h;
        CAPTURE(h, p, l, r);
        CHECK(std::abs(it.value() - (H(r + l) - H(r - l)) / (2 * l)) < 1e-14);
        CHECK(std::abs(gt.value() - (hat(r + l) - hat(r - l)) / (2 * l * h)) < 1e-13 / h);
      }
    }
    // Each form was met: boxes of 2, 3 and 4 nodes.
    CHECK(boxes[2] > 0);
    CHECK(boxes[3] > 0);
    CHECK(boxes[4] > 0);
  }
}

TEST_CASE("uGIMP refuses a domain without length, naming the particle", "[shape]") {
  // S_i = (H(r + l) - H(r - l))/(2l) divides by the domain's length: l = 0 has no average (the
  // closed form of a two-node box would not divide and give the hat's values silently).
  const Grid g(2, {0, 0, 0}, {1, 1, 1}, {6, 6, 1});
  Particles P;
  P.resize(2, 2);
  P.X << 2.3, 2.4, 3.3, 3.6;
  P.half_length << 0.25, 0.25, 0.25, 0.0;
  P.mass.setOnes();
  CHECK_THROWS_WITH(assemble(g, P, Shape::GIMP),
                    Catch::Contains("particle 1 at (3.3, 3.6) has a uGIMP domain without length"));
}
