// Spectral stability of the linearised update (FMPM 2026 §3.3, Fig. 12) on the free-vibrating
// bar: Spectra against a dense eigensolver, and the critical Courant numbers.

#include "support.hpp"

#include <sparsempm/stability.hpp>

using namespace smpm;

namespace {
StepOptions fmpm(int k, double alpha = 1, int every = 1) {
  return {.shape = Shape::CPDI,
          .velocity = VelocityUpdate::FMPM,
          .fmpm = {.order = k, .blend_alpha = alpha, .blend_every = every}};
}
} // namespace

TEST_CASE("Spectra's spectral radius equals the dense eigensolver's", "[stability]") {
  // Arnoldi (Spectra GenEigsSolver, 60 vectors) against all eigenvalues of the dense T;
  // agreement to 1e-8.
  const Model bar = vibrating_bar({});
  for (const StepOptions& opt : {StepOptions{.shape = Shape::CPDI}, fmpm(4), fmpm(8, 0.8, 2)})
    for (double C : {0.2, 0.5}) {
      CAPTURE(to_string(opt.velocity), opt.fmpm.order, C);
      const LinearizedStep T(bar, opt, C / courant_of(bar, 1.0));
      const double dense = spectral_radius(T, 100000), arnoldi = spectral_radius(T, 0);
      CHECK(arnoldi == smpm::test::approx(dense, 1e-8, 1e-8));
    }
}

TEST_CASE("critical Courant numbers of the vibrating bar (FMPM 2026 Fig. 12A)", "[stability]") {
  // At the initial (undeformed) configuration of the §3.3 bar, CPDI, USL, α = 1. Measured:
  // FLIP 0.755; FMPM(k) 0.791, 0.641, 0.555, 0.514, 0.502, 0.500, 0.500 for k = 1, 2, 4, 8, 16,
  // 40, 80; blending α = 0.8 with FMPM(1) 0.570 and with FMPM(2) 0.531 (k = 40).
  const Model bar = vibrating_bar({});
  const double flip = critical_courant(bar, {.shape = Shape::CPDI}).courant;
  // Compare: the conservative bound 0.71–0.77 quoted in §3.3 (Yang & Sulsky).
  CHECK(flip >= 0.70);
  CHECK(flip <= 0.80);
  std::vector<double> cs;
  for (int k : {1, 2, 4, 8, 16, 40, 80})
    cs.push_back(critical_courant(bar, fmpm(k)).courant);
  for (size_t i = 1; i < cs.size(); ++i)
    CHECK(cs[i] <= cs[i - 1] + 1e-3);     // C* does not increase with k (bisection to 1e-3)
  CHECK(cs.back() >= 0.2);                // levels off: m̃ is not ill-conditioned here
  CHECK(std::abs(cs[6] - cs[5]) <= 0.05); // C*(80) within 0.05 of C*(40)
  CHECK(cs[2] == smpm::test::approx(0.539, 0.03)); // FMPM(4): the paper's 0.539
  // Blending with α < 1 raises the limit (§3.3).
  CHECK(critical_courant(bar, fmpm(40, 0.8, 1)).courant > cs[5] + 0.01);
  CHECK(critical_courant(bar, fmpm(40, 0.8, 2)).courant > cs[5] + 0.01);
}
