// SPDX-License-Identifier: BSD-3-Clause
// The stability of heat transport (transport_stability.hpp): the linearised transport step is
// the Stepper's transport step, its matrix forms, and the critical Fourier numbers of the
// lumped, FMPM(k) and exact transport against their analytic limits and full runs.

#include "support.hpp"

#include <sparsempm/exact.hpp>
#include <sparsempm/transport_stability.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

using namespace smpm;
using smpm::test::approx;

namespace {
// The conduction bar of tests/lib/test_transport.cpp: [0, 1], `cells` cells, 2 particles per
// cell, D = 1, the ends held (at 400 and 350; the linearised step holds them at 0).
Model bar(int cells, int dim = 1) {
  const double h = 1.0 / cells;
  Model m(Grid(dim, {-h, -h, -h}, {h, h, h}, {cells + 2, cells + 2, cells + 2}));
  Material mat = smpm::test::material("bar", MaterialModel::Linear, 1e-9, 0.0);
  mat.heat_capacity = 1;
  mat.conductivity = 1;
  mat.reference_temperature = 300;
  m.materials = {mat};
  m.particles = make_block(m.grid, {0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 1.0, 0);
  for (const auto& [at, value] : {std::pair{0.0, 400.0}, std::pair{1.0, 350.0}}) {
    VelocityCondition c;
    c.nodes = nodes_on_plane(m.grid, 0, at);
    c.value = [v = value](double, const Eigen::Vector3d&) { return v; };
    c.label = "temperature";
    m.temperature_bcs.conditions.push_back(c);
  }
  return m;
}

StepOptions transport(TransportUpdate update, int order = 1) {
  StepOptions o;
  o.shape = Shape::Linear;
  o.transport.update = update;
  o.transport.order = order;
  o.exact_solver = cholmod_solver_factory();
  return o;
}
} // namespace

TEST_CASE("the linearised transport step is the Stepper's step, and its matrix forms",
          "[stability][transport]") {
  // An insulated bar (no conditions) makes the transport step linear in the temperatures: the
  // Stepper's step from any positive T equals 𝒯 T (1e-12 of T: the same stages), and 𝒯 has the
  // matrix forms of transport_stability.hpp, lumped I − Δt S c⁻¹ K c⁻¹ Sᵀ 𝗖 and FMPM(k)
  // S c̃_k⁻¹ (I − Δt K c⁻¹) Sᵀ 𝗖 with c̃_k⁻¹ = Σ_{j<k} A_cʲ c⁻¹ or c̃⁻¹ (exact), to 1e-12.
  Model m = bar(6);
  m.temperature_bcs.conditions.clear();
  const double dt = 0.3 / 36;
  Eigen::VectorXd T0(m.particles.size());
  for (Index p = 0; p < T0.size(); ++p)
    T0[p] = 300 + 40 * std::sin(3 * m.particles.X(p, 0)) + (p % 3);
  for (const auto& [update, order] :
       {std::pair{TransportUpdate::Lumped, 1}, std::pair{TransportUpdate::FMPM, 3},
        std::pair{TransportUpdate::Exact, 1}}) {
    CAPTURE(to_string(update));
    const TransportStep T(m, transport(update, order), dt);
    Eigen::VectorXd y(T0.size());
    T.perform_op(T0.data(), y.data());
    Model run = m;
    run.particles.temperature = T0;
    Stepper stepper(transport(update, order));
    stepper.step(run, dt);
    CHECK((y - run.particles.temperature).cwiseAbs().maxCoeff() <= 1e-12 * 300);
    // the matrix forms
    Operators ops = assemble(m.grid, m.particles, Shape::Linear);
    TransportOperators top;
    prepare_transport(ops, m.particles, m.materials, top,
                      update == TransportUpdate::Exact ? kMassTolerance : 0.0);
    const Eigen::MatrixXd S = Eigen::MatrixXd(folded_columns(ops, ops.S));
    const Eigen::MatrixXd K = Eigen::MatrixXd(conductivity_matrix(ops, top));
    const Eigen::MatrixXd ct = Eigen::MatrixXd(consistent_capacity(ops, top));
    const Eigen::MatrixXd cinv = top.nodes.m_inv.asDiagonal();
    const Eigen::MatrixXd StC = S.transpose() * top.capacity.asDiagonal();
    const Index n = cinv.rows(), N = S.rows();
    Eigen::MatrixXd expected;
    if (update == TransportUpdate::Lumped) {
      expected = Eigen::MatrixXd::Identity(N, N) - dt * S * cinv * K * cinv * StC;
    } else {
      Eigen::MatrixXd inverse = Eigen::MatrixXd::Zero(n, n); // c̃_k⁻¹ on the active nodes
      if (update == TransportUpdate::Exact) {
        std::vector<Index> act;
        for (Index i = 0; i < n; ++i)
          if (top.nodes.active[i])
            act.push_back(i);
        Eigen::MatrixXd ca(act.size(), act.size());
        for (size_t a = 0; a < act.size(); ++a)
          for (size_t b = 0; b < act.size(); ++b)
            ca(Index(a), Index(b)) = ct(act[a], act[b]);
        const Eigen::MatrixXd inv = ca.inverse();
        for (size_t a = 0; a < act.size(); ++a)
          for (size_t b = 0; b < act.size(); ++b)
            inverse(act[a], act[b]) = inv(Index(a), Index(b));
      } else {
        const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) - cinv * ct;
        Eigen::MatrixXd term = cinv;
        for (int j = 0; j < order; ++j, term = A * term)
          inverse += term;
      }
      expected = S * inverse * (Eigen::MatrixXd::Identity(n, n) - dt * K * cinv) * StC;
    }
    CHECK((T.dense() - expected).cwiseAbs().maxCoeff() <= 1e-12);
  }
}

TEST_CASE("critical Fourier numbers of the bar: lumped, FMPM(k) and exact (the transport Fig. "
          "12A)",
          "[stability][transport]") {
  // The grid forms conduct with the lumped nodal temperature c⁻¹ τ: the exact capacity solve
  // has the limit of λ_max(c⁻¹ K) = 4D/Δx² (linear elements), F* = 1/2 (measured 0.5125 on 10
  // cells with the held ends); PIC's projection damps the checkerboard (c⁻¹ c̃ = 1/3 there):
  // F* ≈ 1 (measured 1.093); FMPM(k) falls from PIC's to the exact solve's as k grows (0.788,
  // 0.615, 0.535, 0.514 for k = 2, 4, 8, 16); the lumped FLIP update, T_p += Δt S c⁻¹ q, is
  // the most stable (1.436; 3/2 for the checkerboard on an unbounded bar). Asserted: the order
  // of the six, F*(exact) within 3% of 1/2 and F*(PIC) within 10% of 1, and F* = FMPM(40)'s
  // equal to the exact solve's at the search's resolution.
  const Model m = bar(10);
  auto F = [&](TransportUpdate u, int k = 1) {
    return critical_fourier(m, transport(u, k)).critical_fourier;
  };
  const double lumped = F(TransportUpdate::Lumped), pic = F(TransportUpdate::FMPM, 1);
  const double f2 = F(TransportUpdate::FMPM, 2), f4 = F(TransportUpdate::FMPM, 4);
  const double f40 = F(TransportUpdate::FMPM, 40), exact = F(TransportUpdate::Exact);
  CAPTURE(lumped, pic, f2, f4, f40, exact);
  CHECK(lumped > pic);
  CHECK(pic > f2);
  CHECK(f2 > f4);
  CHECK(f4 > f40);
  CHECK(f40 == approx(exact, 2e-3));
  CHECK(exact == approx(0.5, 0, 0.03));
  CHECK(pic == approx(1.0, 0, 0.1));
}

TEST_CASE("the linearised transport step leaves out the sources (a linear map)",
          "[stability][transport]") {
  // A heat source r makes the step affine, T' = 𝒯 T + Δt S c⁻¹ Sᵀ M r: the linearised step is
  // its linear part, 𝒯 0 = 0 exactly.
  Model m = bar(6);
  m.particles.heat_source.setConstant(m.particles.size(), 7.0);
  for (TransportUpdate u : {TransportUpdate::Lumped, TransportUpdate::FMPM}) {
    const TransportStep T(m, transport(u, 3), 0.01);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(T.rows());
    Eigen::VectorXd y(T.rows());
    T.perform_op(zero.data(), y.data());
    CHECK(y.cwiseAbs().maxCoeff() == 0);
  }
}

TEST_CASE("the critical Fourier number is where full runs of the bar become unstable",
          "[stability][transport]") {
  // FMPM(4) transport of the insulated bar from a temperature with a checkerboard part: 400
  // steps at 0.97 F* (of this configuration) keep the temperatures bounded (max |T − 300| does
  // not grow), at 1.05 F* they grow past 10 times the start (ρ above 1 compounds: ρ^400).
  Model m = bar(10);
  m.temperature_bcs.conditions.clear();
  const StepOptions o = transport(TransportUpdate::FMPM, 4);
  const double Fs = critical_fourier(m, o).critical_fourier;
  auto growth = [&](double F) {
    Model run = m;
    run.particles.temperature.resize(run.particles.size());
    for (Index p = 0; p < run.particles.size(); ++p)
      run.particles.temperature[p] = 300 + (p % 2 ? 1.0 : -1.0) + std::sin(run.particles.X(p, 0));
    Stepper stepper(o);
    const double dt = F * diffusion_time(run.grid, run.materials, run.particles);
    double start = (run.particles.temperature.array() - 300).abs().maxCoeff();
    try {
      for (int s = 0; s < 400; ++s)
        stepper.step(run, dt);
    } catch (const NumericalError&) { // a temperature went negative: unbounded growth
      return 1e300;
    }
    return (run.particles.temperature.array() - 300).abs().maxCoeff() / start;
  };
  CAPTURE(Fs);
  CHECK(growth(0.97 * Fs) <= 1.0);
  CHECK(growth(1.05 * Fs) > 10);
}
