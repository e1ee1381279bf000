// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Shared test helpers: one approx() and seeded random particle clouds.

#include <catch2/catch.hpp>
#include <sparsempm/sparsempm.hpp>

#include <cmath>
#include <random>
#include <string>

namespace smpm::test {

/// |actual − value| ≤ abs + rel |value|.
inline Catch::Detail::Approx approx(double value, double abs, double rel = 0) {
  return Catch::Detail::Approx(value).margin(abs).epsilon(rel);
}

/// A material of the given model and elastic constants.
inline Material material(const std::string& name, MaterialModel model, double youngs,
                         double poisson, double density = 1.0) {
  return Material{
      .name = name, .model = model, .density = density, .youngs = youngs, .poisson = poisson};
}

/// A grid of `cells` cells per axis with a different cell size on each axis.
inline Grid test_grid(int dim, int cells) {
  return Grid(dim, {-1.0, 0.5, 2.0}, {1.0, 0.5, 2.0}, {cells, cells, cells});
}

/// N particles at random positions at least `margin` cells inside the grid, with random
/// half-lengths in [0.1, 0.5] h and, when `deform`, F = I + 0.3 U(−1, 1) (det F > 0.2).
inline Particles random_cloud(const Grid& g, Index N, unsigned seed, double margin, bool deform) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int d = g.dim();
  Particles P;
  P.resize(d, N);
  for (Index p = 0; p < N; ++p) {
    for (int a = 0; a < d; ++a) {
      const double h = g.cell_size(a);
      P.X(p, a) = g.origin(a) + h * (margin + u(rng) * (g.cells(a) - 2 * margin));
      P.half_length(p, a) = h * (0.1 + 0.4 * u(rng));
    }
    if (deform) {
      for (;;) {
        for (int k = 0; k < d * d; ++k)
          P.F(p, k) = (k % (d + 1) == 0 ? 1.0 : 0.0) + 0.3 * (2 * u(rng) - 1);
        if (P.jacobian()[p] > 0.2)
          break;
      }
    }
    P.mass[p] = 0.5 + u(rng);
    P.volume0[p] = 1;
  }
  return P;
}

/// A random affine velocity field V = V₀ + L₀ x on the particles (Eigen's Random: V₀, L₀ in
/// [−1, 1]) and its gradient on every particle, L_p = L₀ (N × d², row-major).
struct AffineField {
  Field V, L;
};
inline AffineField random_affine_field(const Particles& P) {
  const int d = P.dim;
  const Eigen::MatrixXd L0 = Eigen::MatrixXd::Random(d, d);
  const Eigen::RowVectorXd V0 = Eigen::RowVectorXd::Random(d);
  AffineField f{P.X * L0.transpose(), Field(P.size(), d * d)};
  f.V.rowwise() += V0;
  for (Index q = 0; q < P.size(); ++q)
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        f.L(q, a * d + b) = L0(a, b);
  return f;
}

/// The largest |entry| of a matrix.
inline double max_abs(const Eigen::MatrixXd& a) {
  return a.cwiseAbs().maxCoeff();
}

/// Particles on a regular lattice (ppc per axis) over cells [lo, lo + count) of each axis,
/// each jittered by up to ±jitter of its spacing, with half-lengths shrunk by (1 − 2 jitter)
/// so that every domain stays inside its own lattice site (and the block).
inline Particles jittered_lattice(const Grid& g, int lo, int count, int ppc, double jitter,
                                  unsigned seed) {
  std::array<double, 3> a_lo{}, a_hi{};
  for (int a = 0; a < g.dim(); ++a) {
    a_lo[a] = g.origin(a) + lo * g.cell_size(a);
    a_hi[a] = a_lo[a] + count * g.cell_size(a);
  }
  Particles P = make_block(g, a_lo, a_hi, {ppc, ppc, ppc}, 1.0, 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Index p = 0; p < P.size(); ++p)
    for (int a = 0; a < g.dim(); ++a) {
      P.X(p, a) += jitter * 2 * P.half_length(p, a) * u(rng);
      P.half_length(p, a) *= 1 - 2 * jitter;
    }
  return P;
}

/// Relative change of total energy of the free-vibrating bar of FMPM 2026 §3.3 (L = 40, cell 1,
/// 2 ppc, E = 2, ρ = 0.5, v₀ = 0.16) after `periods` periods at Courant number C, run by
/// advance() (the last step shortened to land on the end); NaN when the run fails (NumericalError:
/// NaN, det F ≤ 0, leaving the grid, total energy above 10× its start).
inline double bar_energy_change(const StepOptions& options, double courant, double periods = 5) {
  const BarSetup bar;
  Model model = vibrating_bar(bar);
  Stepper stepper(options);
  try {
    const AdvanceReport r =
        advance(model, stepper, {.end = periods * bar_period(bar), .courant = courant});
    return (r.energy_end - r.energy_start) / r.energy_start;
  } catch (const NumericalError&) {
    return std::nan("");
  }
}

/// The heat content Σ_p M_p C_V T_p of a model's particles (C_V of each particle's material).
inline double heat_content(const Model& m) {
  const Particles& P = m.particles;
  double sum = 0;
  for (Index p = 0; p < P.size(); ++p)
    sum += P.mass[p] * m.materials[size_t(P.material[p])].heat_capacity * P.temperature[p];
  return sum;
}

} // namespace smpm::test
