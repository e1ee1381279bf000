// SPDX-License-Identifier: BSD-3-Clause
// Heat and the mechanics (transport.hpp, material.hpp; FMPM 2026 §3.5, Nairn 2024): conduction
// alone leaves the mechanics unchanged bit for bit, the work of friction at contact nodes becomes
// heat, and thermoelasticity: free expansion without stress, the entropy and stress of one free
// energy, an adiabatic cycle on its isentrope, the thermoelastic vibrating bar.

#include "contact_support.hpp"
#include "support.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <tuple>
#include <vector>

using namespace smpm;
using smpm::test::approx;
using smpm::test::heat_content;

TEST_CASE("transport leaves the mechanics unchanged bit for bit (no thermal coupling)",
          "[transport]") {
  // The vibrating bar of FMPM 2026 §3.3 with conduction on (and a non-uniform temperature) and
  // off: positions, velocities and stresses are the same bits after 200 FMPM(4) steps.
  Model hot = vibrating_bar({});
  Model cold = hot;
  for (Material& mat : hot.materials) {
    mat.heat_capacity = 1.0;
    mat.conductivity = 0.5;
    mat.reference_temperature = 300;
  }
  hot.particles.temperature.resize(hot.particles.size());
  for (Index p = 0; p < hot.particles.size(); ++p)
    hot.particles.temperature[p] = 300 + hot.particles.X(p, 0);
  const Eigen::VectorXd initial = hot.particles.temperature;
  StepOptions o;
  o.velocity = VelocityUpdate::FMPM;
  o.fmpm.order = 4;
  Stepper plain(o);
  o.transport.update = TransportUpdate::FMPM;
  Stepper heated(o);
  const double dt = stable_time_step(cold, 0.4);
  for (int s = 0; s < 200; ++s) {
    plain.step(cold, dt);
    heated.step(hot, dt);
  }
  CHECK(hot.particles.X == cold.particles.X);
  CHECK(hot.particles.V == cold.particles.V);
  CHECK(hot.particles.stress == cold.particles.stress);
  // it conducted: the ends of the linear profile (insulated) moved toward its mean
  CHECK((hot.particles.temperature - initial).cwiseAbs().maxCoeff() > 1);
}

TEST_CASE("frictional work at contact nodes becomes heat: Q equals the work to round-off",
          "[transport][contact]") {
  // A block sliding on a base under gravity with Coulomb friction (μ = 0.3), adiabatic
  // (κ = 0): the heat the particles gain, Σ M C_V (T − T0), equals the work of friction the
  // contact laws did (Stepper::friction_work) to the round-off of the heat content Σ M C_V T
  // (1e-14 of it; the differences measured are below 1e-15 of it: a heat of 2.2 to 3.2 in a
  // content of 1.2e5, over 1000 steps of FLIP with the lumped transport, and of FMPM(4), Net
  // and Evolving, with the FMPM transport).
  for (const auto& [order, method] :
       {std::pair{1, ContactFmpmMethod::Net}, std::pair{4, ContactFmpmMethod::Net},
        std::pair{4, ContactFmpmMethod::Evolving}}) {
    Model m(Grid(2, {0, 0, 0}, {0.5, 0.5, 1}, {24, 14, 1}));
    m.materials = {smpm::test::elastic("base", 2e4, 2.0), smpm::test::elastic("block", 2e4, 1.0)};
    for (Material& mat : m.materials) {
      mat.heat_capacity = 10.0;
      mat.reference_temperature = 300;
    }
    m.particles = make_block(m.grid, {2, 1, 0}, {10, 3, 0}, {2, 2, 1}, 2.0, 0);
    Particles top = make_block(m.grid, {3, 3, 0}, {7, 5, 0}, {2, 2, 1}, 1.0, 1);
    top.V.col(0).setConstant(1.0);
    m.particles.append(top);
    fix_plane(m.grid, 1, 1.0, {true, true, false}, m.bcs);
    m.gravity = {0, -10, 0};
    ContactPair law = smpm::test::pair_law(ContactLaw::Coulomb, ContactDetection::Approaching, 0.3);
    law.normal = ContactNormal::Specified;
    law.direction = Eigen::Vector3d::UnitY();
    law.fmpm_method = method;
    m.contact.material_field = {0, 1};
    m.contact.pairs = {law};
    StepOptions o;
    o.shape = Shape::GIMP;
    o.transport.update = TransportUpdate::Lumped;
    if (order > 1) {
      o.velocity = VelocityUpdate::FMPM;
      o.fmpm.order = order;
      o.transport.update = TransportUpdate::FMPM;
    }
    Stepper stepper(o);
    set_reference_temperatures(m.particles, m.materials);
    const double q0 = heat_content(m);
    for (int s = 0; s < 1000; ++s)
      stepper.step(m, 2e-4);
    const double heat = heat_content(m) - q0;
    CAPTURE(order, method == ContactFmpmMethod::Net, heat, stepper.friction_work());
    CHECK(stepper.friction_work() > 0.1); // it slid
    CHECK(std::abs(heat - stepper.friction_work()) <= 1e-14 * q0);
  }
}

namespace {
Material thermoelastic(MaterialModel model, double alpha) {
  Material m = smpm::test::material("m", model, 1000.0, 0.3, 1.5);
  m.heat_capacity = 2.0;
  m.reference_temperature = 300;
  m.thermal_expansion = alpha;
  return m;
}
} // namespace

TEST_CASE("thermoelasticity: free expansion is stress-free, c = -dPsi_e/dT and tau = dPsi_e/dF F^T",
          "[transport][material]") {
  // For every model and dimension: σ = 0 at F = F_T = e^{αΔT} I (1 + αΔT for the linear law:
  // ε = αΔT); at T = T_ref the isothermal law; c = −∂Ψ_e/∂T and J σ = (∂Ψ_e/∂F) Fᵀ by central
  // differences (step 1e-6, agreement 1e-6 relative): the entropy and the stress of one Ψ.
  for (MaterialModel model :
       {MaterialModel::Linear, MaterialModel::NeoHookean, MaterialModel::Hyperelastic}) {
    for (int dim : {1, 2, 3}) {
      if (dim == 1 && model != MaterialModel::Linear)
        continue; // the 1D large-strain laws are uniaxial strain: covered by 2D and 3D
      CAPTURE(to_string(model), dim);
      const Material mat = thermoelastic(model, 6e-4);
      const double T = 390, dT = T - 300;
      double W, c;
      // The free thermal stretch: e^{αΔT} in every direction for the large-strain laws (their
      // 3 × 3 F), 1 + αΔT for the linear law, whose plane strain restrains ε₃₃ = 0: in-plane
      // ε = αΔT (3λ + 2G)/(2λ + 2G) then (σ₃₃ ≠ 0 carries the restraint).
      Eigen::Matrix3d free = Eigen::Matrix3d::Identity();
      const double lam = mat.lame_lambda(), G = mat.shear_modulus();
      const double stretch = model != MaterialModel::Linear ? std::exp(6e-4 * dT)
                             : dim == 2 ? 1 + 6e-4 * dT * (3 * lam + 2 * G) / (2 * lam + 2 * G)
                                        : 1 + 6e-4 * dT;
      for (int a = 0; a < (model == MaterialModel::Linear ? dim : 3); ++a)
        free(a, a) = stretch;
      const Eigen::Matrix3d s0 = thermoelastic_stress(mat, dim, free, T, W, c);
      CHECK(s0.topLeftCorner(dim, dim).cwiseAbs().maxCoeff() <= 1e-12 * mat.youngs);
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      F.topLeftCorner(dim, dim) += 0.1 * Eigen::Matrix3d::Random().topLeftCorner(dim, dim);
      CHECK((thermoelastic_stress(mat, dim, F, 300, W, c) - cauchy_stress(mat, dim, F))
                .cwiseAbs()
                .maxCoeff() == 0);
      const Eigen::Matrix3d sigma = thermoelastic_stress(mat, dim, F, T, W, c);
      double Wp, Wm, cc;
      const double h = 1e-6;
      (void)thermoelastic_stress(mat, dim, F, T + h, Wp, cc);
      (void)thermoelastic_stress(mat, dim, F, T - h, Wm, cc);
      CHECK(c == approx(-(Wp - Wm) / (2 * h), 1e-9, 1e-6));
      // τ = J σ = (∂W/∂F) Fᵀ over the d × d block (the linear law: W = ½ σ : ε_e, τ ≈ σ)
      Eigen::Matrix3d dW = Eigen::Matrix3d::Zero();
      for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b) {
          Eigen::Matrix3d Fp = F, Fm = F;
          Fp(a, b) += h;
          Fm(a, b) -= h;
          (void)thermoelastic_stress(mat, dim, Fp, T, Wp, cc);
          (void)thermoelastic_stress(mat, dim, Fm, T, Wm, cc);
          dW(a, b) = (Wp - Wm) / (2 * h);
        }
      const Eigen::MatrixXd tau = (dW * F.transpose()).topLeftCorner(dim, dim);
      const Eigen::MatrixXd Js = (F.determinant() * sigma).topLeftCorner(dim, dim);
      if (model != MaterialModel::Linear) // the linear law's τ is σ to first order only
        CHECK((tau - Js).cwiseAbs().maxCoeff() <= 1e-6 * Js.cwiseAbs().maxCoeff());
    }
  }
}

TEST_CASE("an adiabatic cycle of a thermoelastic particle keeps its entropy and turns work into "
          "internal energy",
          "[transport][material]") {
  // A neo-Hookean point (α = 6e-5, C_V = 2, ρ₀ = 1.5; γ = 3αK/(ρC) ≈ 0.05) compressed by 10%
  // and released in plane strain along F(t) = diag(1 − 0.1 sin πt, 1), Δt = 1/N, by the update
  // of the strain stage (the isentrope ρ₀ C ln(T₁/T₀) + c(F₁, T₁) − c(F₀, T₀) = 0 solved by
  // Newton's method): the entropy ρ₀ C ln(T/T_ref) + c stays constant to round-off (1e-12 of
  // ρ₀ C), the work Σ τ : D Δt (trapezoidal) up to peak compression equals the change of
  // U = Ψ + T S to second order in Δt (the difference falls by 4 when Δt halves; asserted
  // ≥ 3.5), the cycle returns T to T₀ to round-off (reversible), and the temperature at peak
  // compression is ≈ γ T ΔV/V (within 10%).
  const Material mat = thermoelastic(MaterialModel::NeoHookean, 6e-5);
  const double rhoC = mat.density * mat.heat_capacity;
  auto run = [&](int steps) {
    double T = 300, work = 0, peak = 300, dU_half = 0, work_half = 0;
    auto F_at = [&](int n) {
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      F(0, 0) = 1 - 0.1 * std::sin(M_PI * n / steps);
      return F;
    };
    auto entropy = [&](const Eigen::Matrix3d& F, double temp) {
      return rhoC * std::log(temp / 300) + thermal_coupling(mat, 2, F, temp);
    };
    auto internal = [&](const Eigen::Matrix3d& F, double temp) {
      double W, c;
      (void)thermoelastic_stress(mat, 2, F, temp, W, c);
      return W + rhoC * (temp - 300) + temp * c;
    };
    auto isentropic = [&](const Eigen::Matrix3d& F0, const Eigen::Matrix3d& F1, double temp) {
      Model m(Grid(2, {0, 0, 0}, {1, 1, 1}, {2, 2, 1}));
      m.materials = {mat};
      m.particles = make_block(m.grid, {0.5, 0.5, 0}, {1.0, 1.0, 0}, {1, 1, 1}, 1.5, 0);
      m.particles.temperature.setConstant(1, temp);
      for (int k = 0; k < 4; ++k)
        m.particles.F(0, k) = F0(k / 2, k % 2);
      // The strain update as a Stepper with heat transport runs it (the heat part's strain
      // hooks): c before the deformation, the isentropic temperature after it.
      struct Heating final : StageHooks {
        ThermalStrainState thermal;
        void before_deformation(StrainStep& s) override {
          thermal_couplings(s.materials, s.material, s.fields.F, *thermal.temperature,
                            thermal.coupling);
        }
        void after_deformation(StrainStep& s) override {
          isentropic_heating(s.materials, s.material, s.fields.F, thermal.coupling,
                             *thermal.temperature);
        }
      } heating;
      heating.thermal.temperature = &m.particles.temperature;
      StageHooks* const hooks[] = {&heating};
      MaterialStrainUpdate update(m.materials, m.particles.material, DeformationUpdate::Linear,
                                  nullptr, {.thermal = &heating.thermal}, hooks);
      // a uniform velocity gradient L with (I + L Δt) F0 = F1 on the grid of the particle
      Operators ops = assemble(m.grid, m.particles, Shape::Linear);
      const Eigen::Matrix2d L =
          F1.topLeftCorner(2, 2) * F0.topLeftCorner(2, 2).inverse() - Eigen::Matrix2d::Identity();
      Field v(ops.num_nodes(), 2);
      for (Index i = 0; i < ops.num_nodes(); ++i)
        v.row(i) = (L * m.grid.node_position(i).head(2)).transpose();
      ParticleFields fields{m.particles.X, m.particles.V, m.particles.F, m.particles.stress,
                            m.particles.volume0};
      update.update(particle_operators(ops), v, 1.0, fields);
      return m.particles.temperature[0];
    };
    const double S0 = entropy(F_at(0), T), U0 = internal(F_at(0), T);
    double drift = 0;
    for (int n = 0; n < steps; ++n) {
      const Eigen::Matrix3d F0 = F_at(n), F1 = F_at(n + 1);
      double W, c;
      const Eigen::Matrix3d s0 = thermoelastic_stress(mat, 2, F0, T, W, c);
      // The library's strain stage, applied to this one particle.
      T = isentropic(F0, F1, T);
      const Eigen::Matrix3d s1 = thermoelastic_stress(mat, 2, F1, T, W, c);
      // τ : D Δt with D Δt = sym(ΔF F̄⁻¹): the trapezoidal work per reference volume
      const Eigen::Matrix3d Fm = 0.5 * (F0 + F1), L = (F1 - F0) * Fm.inverse();
      const Eigen::Matrix3d tau = 0.5 * (F0.determinant() * s0 + F1.determinant() * s1);
      work += (tau.array() * (0.5 * (L + L.transpose())).array()).sum();
      peak = std::max(peak, T);
      drift = std::max(drift, std::abs(entropy(F1, T) - S0));
      if (n + 1 == steps / 2) // at peak compression: the work done so far against ΔU
        dU_half = internal(F1, T) - U0, work_half = work;
    }
    const double dU = dU_half;
    work = work_half;
    return std::tuple{T, work, dU, drift, peak};
  };
  const auto [T1, work1, dU1, drift1, peak1] = run(200);
  const auto [T2, work2, dU2, drift2, peak2] = run(400);
  CAPTURE(T1, T2, work1, dU1, drift1, drift2, peak2);
  const double gamma = 3 * 6e-5 * mat.bulk_modulus() / rhoC;
  CHECK(peak2 - 300 == approx(gamma * 300 * 0.1, 0, 0.1));
  CHECK(std::abs(T2 - 300) <= 1e-10 * 300);
  CHECK(drift1 <= 1e-12 * rhoC);
  CHECK(drift2 <= 1e-12 * rhoC);
  CHECK(std::abs(work1 - dU1) >= 3.5 * std::abs(work2 - dU2));
}

TEST_CASE("the thermoelastic vibrating bar: each particle on its isentrope, K + U conserved",
          "[transport][material]") {
  // The free-vibrating bar of FMPM 2026 §3.3 (1D linear, uniaxial stress) with thermal expansion
  // α = 0.01 (an exaggerated coupling: the adiabatic modulus is 12% above E), C_V = 1,
  // adiabatic (κ = 0): the strain stage keeps every particle on its isentrope
  // ρ C ln(T/T_ref) + α σ = 0 (Kelvin's thermoelastic effect; c = ασ for the bar) to
  // round-off, for FLIP and FMPM(4), and the temperatures swing with the stress (±1 K). K + U
  // over one period changes at first order in Δt through the coupling (the forces of a step use
  // the stress at its start): measured 3.6e-3 at C = 0.4 and 8.5e-4 at C = 0.1 for FLIP (the
  // isothermal bar: 2.2e-4 and 7e-6); asserted: the change falls by ≥ 3.5 from C = 0.4 to 0.1
  // and is below 1.5e-3 at C = 0.1.
  for (int order : {1, 4}) {
    std::vector<double> changes;
    for (double courant : {0.4, 0.1}) {
      Model m = vibrating_bar({});
      Material& mat = m.materials[0];
      mat.heat_capacity = 1.0;
      mat.reference_temperature = 300;
      mat.thermal_expansion = 0.01;
      StepOptions o;
      if (order > 1) {
        o.velocity = VelocityUpdate::FMPM;
        o.fmpm.order = order;
      }
      o.transport.update = TransportUpdate::Lumped;
      Stepper stepper(o);
      set_reference_temperatures(m.particles, m.materials);
      const double dt = stable_time_step(m, courant);
      const double rhoC = mat.density * mat.heat_capacity;
      auto energy = [&] {
        const Energies e = stepper.energies(m);
        return e.kinetic + thermal_sums(m, e.strain).internal;
      };
      const double e0 = energy();
      double worst = 0, swing = 0;
      for (int s = 0; s < int(std::lround(80 / courant)); ++s) { // one period (c = 1, h = 1)
        stepper.step(m, dt);
        for (Index p = 0; p < m.particles.size(); ++p) {
          const double T = m.particles.temperature[p];
          worst =
              std::max(worst, std::abs(rhoC * std::log(T / 300) + 0.01 * m.particles.stress(p, 0)));
          swing = std::max(swing, std::abs(T - 300));
        }
      }
      CAPTURE(order, courant, worst, swing);
      CHECK(worst <= 1e-12 * rhoC);
      // energies(model) evaluates the thermoelastic W(F, T) the stress update stores
      CHECK(smpm::energies(m).strain == approx(stepper.energies(m).strain, 0, 1e-14));
      // and so does a USF step's, whose stress update comes before the transport
      StepOptions usf = o;
      usf.scheme = UpdateScheme::USF;
      Stepper first(usf);
      Model m2 = m;
      first.step(m2, dt);
      CHECK(smpm::energies(m2).strain == approx(first.energies(m2).strain, 0, 1e-14));
      CHECK(swing > 0.5);
      changes.push_back(std::abs(energy() / e0 - 1));
    }
    CAPTURE(order, changes[0], changes[1]);
    CHECK(changes[0] >= 3.5 * changes[1]);
    CHECK(changes[1] < 1.5e-3);
  }
}
