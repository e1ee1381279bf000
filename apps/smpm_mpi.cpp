// SPDX-License-Identifier: BSD-3-Clause
// smpm-mpi: the commands of smpm that run across MPI ranks with sparsempm::petsc.
//   mpiexec -n P smpm-mpi spectrum input.toml [--order ...] [--blend-alpha ...]
//                [--blend-every ...] [--courant C] [--exact-method M] [-o spectrum.csv]
//   mpiexec -n P smpm-mpi stability input.toml [smpm stability's options] [--exact-method M]
// spectrum: the same table as smpm spectrum (ρ(A), λ_min(m⁻¹m̃), cond(m̃) at t = 0, and for every
// FMPM order and blending the truncation error of FMPM(k) against the exact inverse, with
// --courant ρ(T(C))), computed on the distributed operators: SLEPc for the spectra, KSP (or
// MUMPS) for the exact inverse, the distributed FMPM loop and linearised step.
// stability: smpm stability's table by its spectral method (FMPM 2026 §3.3, Fig. 12A), every row's
// C* over the lattice shifts and frames found by the serial search on ρ(T(C)) across ranks; the
// simulation method runs whole time steps, which do not run across ranks yet, and is refused.
// Every rank reads the input; rank 0 prints and writes the table (with smpm's file safety). An
// input error is reported once, by rank 0, with exit status 2; a failure on any one rank stops
// every rank (MPI_Abort) with its message and exit status 3.

#include "command_options.hpp"
#include "notes.hpp"
#include "stability_command.hpp"

#include <sparsempm/diagnostics.hpp>
#include <sparsempm/errors.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/petsc.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/stages.hpp>

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace {

namespace sp = smpm::petsc;

// ‖m̃_k⁻¹ p − v_exact‖ / ‖v_exact‖ across ranks (smpm::truncation_error's definition).
double truncation(const sp::DistributedGrid& grid, const sp::DistributedOperators& ops,
                  const smpm::FmpmOptions& f, Vec p, Vec exact, sp::DistributedFmpmWorkspace& w) {
  sp::OwnedVec v;
  SMPM_PETSC_CALL(VecDuplicate(p, v.out()));
  SMPM_PETSC_CALL(VecPointwiseMult(v, ops.m_inv_d, p)); // v⁺(1) = m⁻¹ p
  sp::fmpm_velocity(grid, ops, f, {}, v, w);
  PetscReal scale = 0, error = 0;
  SMPM_PETSC_CALL(VecNorm(exact, NORM_2, &scale));
  SMPM_PETSC_CALL(VecAXPY(v, -1.0, exact));
  SMPM_PETSC_CALL(VecNorm(v, NORM_2, &error));
  if (!(scale > 0)) // a model at rest
    return error > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  return double(error / scale);
}

int spectrum(const smpm::app::SpectrumArgs& a, sp::ExactMethod method, int rank) {
  using namespace smpm;
  app::validate(a);
  RunConfig cfg = read_input_file(a.input, a.sets);
  if (rank == 0)
    app::print_notes(cfg);
  const Model& model = cfg.model;
  const sp::DistributedGrid grid(model.grid);
  sp::DistributedOperators ops;
  sp::assemble(grid, model.particles, cfg.step.shape, ops);
  const Particles own = sp::select_particles(model.particles, ops.particles);
  const MassSpectrum ms = sp::mass_spectrum(grid, ops);
  sp::OwnedVec p = sp::momentum(grid, ops, own.V), exact = sp::node_vector(grid, ops.dim);
  sp::exact_solve(grid, ops, {.exact = cfg.step.exact, .method = method}, {}, p, exact);
  sp::DistributedFmpmWorkspace w;
  const std::string table = app::spectrum_table(
      a, ms, [&](const FmpmOptions& f) { return truncation(grid, ops, f, p, exact, w); },
      [&](const FmpmOptions& f) { // ρ(T(C)) of FMPM(k) with this blending across ranks
        StepOptions opt = cfg.step;
        opt.velocity = VelocityUpdate::FMPM;
        opt.fmpm = f;
        opt.periodic_cx = 0;
        const SpectralRadius r =
            sp::spectral_radius(grid, model, opt, stable_time_step(model, a.courant));
        return r.status == SpectralStatus::NonFinite ? std::numeric_limits<double>::infinity()
                                                     : r.rho_T;
      },
      rank == 0);
  if (rank == 0) {
    write_table_file(a.output, table, {a.input}, "-o");
    std::printf("table in %s (%d ranks)\n", a.output.c_str(), grid.size());
  }
  return 0;
}

int stability(const smpm::app::StabilityArgs& a, sp::ExactMethod method, int rank) {
  using namespace smpm;
  if (a.method != "spectral")
    throw InputError("--method " + a.method +
                     ": smpm-mpi stability computes the spectral C* only (the simulation method "
                     "runs time steps, which run in one process: use smpm stability)");
  app::validate(a);
  const sp::DistributedGrid grid(read_input_file(a.input, a.sets).model.grid);
  app::StabilityEngine engine;
  engine.root = rank == 0;
  engine.search = [&](const Model& model, const StepOptions& options, double hint) {
    return sp::critical_courant(grid, model, options, 1e-6, 2.0, 1e-3, hint, method);
  };
  return app::stability_command(a, engine);
}

} // namespace

int main(int argc, char** argv) {
  sp::Session session(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  CLI::App app{"sparsempm across MPI ranks (PETSc, SLEPc): mpiexec -n P smpm-mpi COMMAND"};
  app.require_subcommand(1);
  smpm::app::SpectrumArgs args;
  std::string method = "cg-bjacobi-icc";
  CLI::App* spec = app.add_subcommand(
      "spectrum", "rho(A), cond(m~) and the truncation error of FMPM(k) against m~^-1");
  smpm::app::add_spectrum_options(*spec, args);
  spec->add_option("--exact-method", method,
                   "the exact inverse: cg-jacobi | cg-bjacobi-icc | cg-gamg | mumps-cholesky")
      ->capture_default_str();
  smpm::app::StabilityArgs stab_args;
  CLI::App* stab = app.add_subcommand(
      "stability", "critical Courant numbers of FLIP and FMPM(k) by the spectral method");
  smpm::app::add_stability_options(*stab, stab_args);
  stab->add_option("--exact-method", method,
                   "the exact row's m~^-1: cg-jacobi | cg-bjacobi-icc | cg-gamg | mumps-cholesky")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
    stab_args.position_alpha_given = stab->count("--position-alpha") > 0;
  } catch (const CLI::ParseError& e) {
    int code = 0;
    if (rank == 0)
      code = app.exit(e);
    else
      code = e.get_exit_code();
    return code == 0 ? 0 : 2;
  }
  int code = 0;
  try {
    const sp::ExactMethod exact = sp::exact_method_from_string(method);
    code = stab->parsed() ? stability(stab_args, exact, rank) : spectrum(args, exact, rank);
  } catch (const smpm::InputError& e) { // the same on every rank: said once
    if (rank == 0)
      std::fprintf(stderr, "smpm-mpi: error: %s\n", e.what());
    code = 2;
  } catch (const std::exception& e) { // possibly on this rank alone: stop them all
    std::fprintf(stderr, "smpm-mpi: numerical failure on rank %d: %s\n", rank, e.what());
    std::fflush(stderr);
    MPI_Abort(PETSC_COMM_WORLD, 3);
  }
  if (rank == 0 && (std::fflush(stdout) != 0 || std::ferror(stdout))) {
    std::fprintf(stderr, "smpm-mpi: error: cannot write to standard output\n");
    return code == 0 ? 1 : code;
  }
  return code;
}
