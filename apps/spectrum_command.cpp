// SPDX-License-Identifier: BSD-3-Clause
// smpm spectrum: ρ(A), λ_min(m⁻¹m̃) and cond(m̃) at t = 0, and for every FMPM order and blending
// the truncation error of FMPM(k) against the exact inverse and ρ(T(C)) (FMPM 2026 §2.2, §3.3).

#include "stability_command.hpp"

#include "notes.hpp"
#include "option_checks.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/spectrum.hpp>
#include <sparsempm/stability.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <sstream>

namespace smpm::app {

void validate(const SpectrumArgs& a) {
  check_fmpm_lists(a.orders, a.blend_alphas, a.blend_every);
  if (!(a.courant >= 0) || !std::isfinite(a.courant))
    throw InputError("--courant " + shown(a.courant) + ": must be positive (or 0: no rho(T))");
  check_table_output(a.output, {a.input}, "-o");
  check_regular_file(a.input, kMaxInputBytes, "input file");
}

std::string spectrum_table(const SpectrumArgs& a, const MassSpectrum& ms,
                           const std::function<double(const FmpmOptions&)>& truncation,
                           const std::function<double(const FmpmOptions&)>& rho, bool print) {
  if (print)
    std::printf("active nodes %ld: rho(A) = %.8f, min eig(m^-1 m~) = %.3e, cond(m~) = %.4g\n",
                long(ms.active), ms.rho_A, ms.min_eig_minv_mt, ms.cond_mt);
  std::ostringstream out;
  out.precision(10);
  out << kSpectrumColumns << "\n";
  std::ostringstream scalars; // the configuration's numbers, on every row
  scalars.precision(10);
  scalars << "," << ms.rho_A << "," << ms.min_eig_minv_mt << "," << ms.cond_mt << "," << ms.active;
  if (print)
    std::printf("%5s %11s %11s %16s %10s\n", "order", "blend_alpha", "blend_every",
                "truncation error", "rho(T)");
  for (int m : a.blend_every)
    for (double alpha : a.blend_alphas)
      for (int k : a.orders) {
        if (m > 1 && alpha == 1.0)
          continue; // no blending: the m = 1 rows already hold it
        const FmpmOptions f{.order = k, .blend_alpha = alpha, .blend_every = m};
        const double err = truncation(f);
        const double r = a.courant > 0 ? rho(f) : std::nan("");
        out << k << "," << alpha << "," << m << "," << err << ","
            << (a.courant > 0 ? std::to_string(a.courant) : "") << "," << cell(r, 10)
            << scalars.str() << "\n";
        if (print)
          std::printf("%5d %11.3g %11d %16.6e %10s\n", k, alpha, m, err, cell(r, 8).c_str());
      }
  return out.str();
}

namespace {

// ρ(T(C)) of FMPM with the blending `f` at Courant number C (+inf when it is not finite).
double fmpm_rho(const RunConfig& cfg, const FmpmOptions& f, double courant) {
  StepOptions opt = cfg.step;
  opt.velocity = VelocityUpdate::FMPM;
  opt.fmpm = f;
  opt.periodic_cx = 0;
  const LinearizedStep T(cfg.model, opt, stable_time_step(cfg.model, courant));
  const SpectralRadius r = spectral_radius(T);
  return r.status == SpectralStatus::NonFinite ? std::numeric_limits<double>::infinity() : r.rho_T;
}

} // namespace

int spectrum_command(const SpectrumArgs& a) {
  validate(a);
  RunConfig cfg = read_input_file(a.input, a.sets);
  print_notes(cfg);
  const Model& model = cfg.model;
  const Operators ops = assemble(model.grid, model.particles, cfg.step.shape);
  ConsistentMass mt;
  assemble_consistent_mass(ops, mt);
  const MassSpectrum ms = mass_spectrum(ops, mt.matrix);
  Field p, exact;
  map_momentum(particle_operators(ops), model.particles.V, p);
  cfg.step.exact_solver(cfg.step.exact)->solve(ops, mt.matrix, {}, p, exact);
  const std::string table = spectrum_table(
      a, ms, [&](const FmpmOptions& f) { return truncation_error(ops, mt.matrix, f, p, exact); },
      [&](const FmpmOptions& f) { return fmpm_rho(cfg, f, a.courant); }, true);
  write_table_file(a.output, table, {a.input}, "-o");
  std::printf("table in %s\n", a.output.c_str());
  return 0;
}

} // namespace smpm::app
