// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The baseline of tests/bench/bench_step.cpp: one USL FLIP step written as plain loops over
// particles and nodes, without stored operators (the matrix-free MPM that FMPM 2026 §3.4 compares
// against).

#include <sparsempm/model.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace smpm::bench {

// The baseline: one USL FLIP step in D = 2 or 3 dimensions written as plain loops over particles
// and nodes (linear shape functions on unit cells from the origin, linear elasticity).
template <int D>
struct MatrixFree {
  std::array<int, 3> nodes;
  std::vector<double> m, p, f; // m: n; p, f: n × D
  // The 2^D nodes of particle X's cell (x fastest) with their weights and gradients, written
  // out per dimension.
  static void cell(const double* X, const std::array<int, 3>& nodes, size_t k[8], double w[8],
                   double g[8][3]) {
    const int i = int(X[0]), j = int(X[1]);
    const double tx = X[0] - i, ty = X[1] - j;
    const double wx[2] = {1 - tx, tx}, wy[2] = {1 - ty, ty}, s[2] = {-1, 1};
    const size_t nx = size_t(nodes[0]), base = size_t(i) + size_t(j) * nx;
    if constexpr (D == 2) {
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const int c = a + 2 * b;
          k[c] = base + size_t(a) + size_t(b) * nx;
          w[c] = wx[a] * wy[b];
          g[c][0] = s[a] * wy[b];
          g[c][1] = wx[a] * s[b];
        }
    } else {
      const int l = int(X[2]);
      const double tz = X[2] - l, wz[2] = {1 - tz, tz};
      const size_t nxy = nx * size_t(nodes[1]), base3 = base + size_t(l) * nxy;
      for (int e = 0; e < 2; ++e)
        for (int b = 0; b < 2; ++b)
          for (int a = 0; a < 2; ++a) {
            const int c = a + 2 * b + 4 * e;
            k[c] = base3 + size_t(a) + size_t(b) * nx + size_t(e) * nxy;
            w[c] = wx[a] * wy[b] * wz[e];
            g[c][0] = s[a] * wy[b] * wz[e];
            g[c][1] = wx[a] * s[b] * wz[e];
            g[c][2] = wx[a] * wy[b] * s[e];
          }
    }
  }
  void step(smpm::Model& model, double dt) {
    auto& P = model.particles;
    const double lam = model.materials[0].lame_lambda(), G = model.materials[0].shear_modulus();
    const Eigen::Index N = P.size();
    const size_t n = size_t(nodes[0]) * nodes[1] * nodes[2];
    m.assign(n, 0);
    p.assign(n * D, 0);
    f.assign(n * D, 0);
    size_t k[8];
    double w[8], g[8][3];
    for (Eigen::Index q = 0; q < N; ++q) { // P2G: mass, momentum, internal force
      cell(P.X.row(q).data(), nodes, k, w, g);
      const double* F = P.F.row(q).data();
      const double* sig = P.stress.row(q).data();
      double J = F[0];
      if constexpr (D == 2)
        J = F[0] * F[3] - F[1] * F[2];
      if constexpr (D == 3)
        J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
            F[2] * (F[3] * F[7] - F[4] * F[6]);
      const double vol = P.volume0[q] * J, M = P.mass[q];
      for (int c = 0; c < (1 << D); ++c) {
        m[k[c]] += w[c] * M;
        for (int a = 0; a < D; ++a) {
          p[k[c] * D + a] += w[c] * M * P.V(q, a);
          double fa = 0;
          for (int b = 0; b < D; ++b)
            fa += sig[a * D + b] * g[c][b];
          f[k[c] * D + a] -= vol * fa;
        }
      }
    }
    for (size_t i = 0; i < n; ++i) // grid update: a = f/m, v⁺ = (p + f dt)/m
      for (int a = 0; a < D; ++a) {
        const size_t j = i * D + a;
        if (m[i] > 1e-12) {
          p[j] = (p[j] + f[j] * dt) / m[i];
          f[j] /= m[i];
        } else {
          p[j] = f[j] = 0;
        }
      }
    for (Eigen::Index q = 0; q < N; ++q) { // G2P: FLIP, position, L, F, stress
      cell(P.X.row(q).data(), nodes, k, w, g);
      double acc[D] = {}, vel[D] = {}, L[D * D] = {};
      for (int c = 0; c < (1 << D); ++c)
        for (int a = 0; a < D; ++a) {
          acc[a] += w[c] * f[k[c] * D + a];
          vel[a] += w[c] * p[k[c] * D + a];
          for (int b = 0; b < D; ++b)
            L[a * D + b] += p[k[c] * D + a] * g[c][b];
        }
      for (int a = 0; a < D; ++a) {
        P.V(q, a) += dt * acc[a];
        P.X(q, a) += dt * vel[a];
      }
      double* F = P.F.row(q).data();
      double Fn[D * D], tr = 0;
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          double s = 0;
          for (int c = 0; c < D; ++c)
            s += L[a * D + c] * F[c * D + b];
          Fn[a * D + b] = F[a * D + b] + dt * s;
        }
      for (int a = 0; a < D; ++a)
        tr += Fn[a * D + a] - 1;
      double* sig = P.stress.row(q).data();
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          F[a * D + b] = Fn[a * D + b];
          const double eps = 0.5 * (Fn[a * D + b] + Fn[b * D + a]) - (a == b ? 1.0 : 0.0);
          sig[a * D + b] = 2 * G * eps + (a == b ? lam * tr : 0.0);
        }
    }
  }
};

} // namespace smpm::bench
