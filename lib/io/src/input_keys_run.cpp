// SPDX-License-Identifier: BSD-3-Clause
// The keys of the run's tables ([time], [step], [output]) and of the loads: the second half of
// input_keys() (input_keys.cpp holds the model's tables).
#include "sparsempm/input.hpp"

#include "toml_text.hpp"

namespace smpm::detail {

std::vector<InputKey> run_input_keys() {
  return {
      // [time]
      {"time", "courant", "number", "0.5", true, "> 0", "",
       "C in Δt = C Δx_min / max(c_wave, max|V_p|) (FMPM 2026 §3.3)", "0.0"},
      {"time", "end", "number", "required", false, "> 0", "time", "The simulated end time", "0.0"},
      {"time", "land_on_frames", "boolean", "true", true, "", "",
       "Shorten the step before each frame to land on it; false: constant Courant steps", "1"},
      {"time", "fourier", "number", "0.1", true, "> 0", "",
       "F in Δt ≤ F Δx_min² / D_max, the Fourier number of conduction (heat transport)", "0.0"},
      {"time", "max_steps", "integer", "10000000", true, "1 to 10^15", "",
       "The most steps a run may take: a run whose first time step implies more is refused", "0"},

      // [step]
      {"step", "scheme", "string", "\"USL\"", true,
       "\"USL\" | \"USF\" | \"USL+\" | \"USAVG\" | \"USAVG+\"", "",
       "Where the stress update and the FMPM loop sit in the step (FMPM 2026 Fig. 1)", "\"bogus\""},
      {"step", "velocity", "string", "\"FLIP\"", true,
       "\"FLIP\" | \"PIC\" | \"FMPM\" | \"XPIC\" | \"exact\" | \"chebyshev\" | "
       "\"least_squares\" | \"chebyshev_squared\"",
       "",
       "How particle velocities follow the grid: FLIP (FMPM 2026 Eq. 8), PIC, FMPM(k), XPIC(m), "
       "the exact m̃⁻¹, or the Chebyshev, least-squares or squared Chebyshev polynomial in m⁻¹m̃ "
       "of the same k − 1 products (docs/studies/polynomials.md)",
       "\"bogus\""},
      {"step", "shape", "string", "\"cpdi\"", true,
       "\"linear\" | \"gimp\" | \"bspline2\" | \"cpdi\" | \"b2cpdi\"", "",
       "The shape functions: linear hats, uGIMP, quadratic B-splines, CPDI or B2CPDI", "\"bogus\""},
      {"step", "position_alpha", "number", "1 for FLIP, 1/2 otherwise", false, "[0, 1]", "",
       "α of FMPM 2026 Eqs. (8)–(9), the weight of the new grid velocity in the position update",
       "2.0"},
      {"step", "order", "integer",
       "required with velocity = \"FMPM\", \"XPIC\" or a polynomial (else unused, but checked)",
       false, "1 to 100000", "",
       "k of FMPM(k), the terms of the loop of FMPM 2026 Table 1, or m of XPIC(m)", "0"},
      {"step", "blend_alpha", "number", "1.0", true, "[0, 1]", "",
       "α of the blended recursion (FMPM 2026 §3.3), scaling Δv(ℓ) when ℓ mod m = 1 or m = 1",
       "2.0"},
      {"step", "blend_every", "integer", "1", true, "1 to 100000", "",
       "m of the blended recursion (FMPM 2026 §3.3): blend_alpha scales Δv(ℓ) when ℓ mod m = 1",
       "0"},
      {"step", "periodic_cx", "number", "0.0", true, "≥ 0", "",
       "C_X of periodic FMPM (FMPM 2026 §3.3): FMPM once the accumulated Courant number reaches "
       "it; 0: every step",
       "-1.0"},
      {"step", "dynamic_metric", "string", "\"none\"", true, "\"none\" | \"means\" | \"changes\"",
       "",
       "The metric of dynamic FMPM (FMPM 2026 §3.4), stopping the loop at the first ℓ below "
       "dynamic_limit",
       "\"bogus\""},
      {"step", "dynamic_limit", "number",
       "required with a dynamic_metric (else unused, but checked)", false, "≥ 0", "",
       "The convergence limit of dynamic FMPM (FMPM 2026 §3.4); order is then the maximum order",
       "-1.0"},
      {"step", "interval_low", "number", "0.0", true, "[0, 1); > 0 with the Chebyshev members", "",
       "λ_lo of the interval [λ_lo, 1] of the spectrum of m⁻¹m̃ on which the Chebyshev and "
       "least-squares polynomials are made (smpm spectrum prints min eig(m^-1 m~)); modes below "
       "it converge less",
       "1.0"},
      {"step", "bc_method", "string", "\"incremental\"", true,
       "\"incremental\" | \"lumped\" | \"velocity\" | \"combined\"", "",
       "How the velocity BCs enter the FMPM loop: FMPM 2026 §3.1's incremental method or an "
       "earlier one",
       "\"bogus\""},
      {"step", "exact_regularization", "number", "0.0", true, "[0, 1]", "",
       "ε: the exact update factors the blended mass (1 − ε) m̃ + ε m instead of m̃ (FMPM 2026 "
       "§3.3)",
       "2.0"},
      {"step", "exact_mass_cutoff", "number", "0.0", true, "[0, 1)", "",
       "τ: in the exact update, active nodes lighter than τ max m take their lumped velocity",
       "1.0"},
      {"step", "exact_method", "string", "\"factor\"", true, "\"factor\" | \"pcg\"", "",
       "How the exact update solves m̃ v = p: a factorisation (CHOLMOD, UMFPACK for m̃_L) or the "
       "preconditioned conjugate gradient (symmetric m̃)",
       "\"bogus\""},
      {"step", "exact_tolerance", "number", "1e-12", true, "(0, 1)", "",
       "pcg: the relative residual ‖b − m̃ v‖/‖b‖ at which the conjugate gradient stops", "0.0"},
      {"step", "exact_preconditioner", "string", "\"diagonal\"", true, "\"diagonal\" | \"ic\"", "",
       "pcg: the diagonal of m̃ (Jacobi) or its incomplete Cholesky factor", "\"bogus\""},
      {"step", "deformation", "string", "\"linear\"", true, "\"linear\" | \"exponential\"", "",
       "How F follows the velocity gradient: F ← (I + LΔt)F, or F ← exp(LΔt)F (FMPM 2026 task 5)",
       "\"bogus\""},
      {"step", "xpic_contact", "string", "\"increments\"", true,
       "\"increments\" | \"term\" | \"none\"", "",
       "Multimaterial XPIC(m): contact on every increment of the loop, contact 2020 Eq. (37)'s "
       "term, or neither",
       "\"bogus\""},
      {"step", "transport", "string", "\"off\"", true,
       "\"off\" | \"lumped\" | \"FMPM\" | \"exact\"", "",
       "Heat transport: off, lumped, FMPM(k) on the capacity matrix c̃ or the exact solve (FMPM "
       "2026 §3.5)",
       "\"bogus\""},
      {"step", "transport_order", "integer",
       "order (required with transport = \"FMPM\" unless velocity is FMPM or XPIC)", false,
       "1 to 100000 (0: unset)", "", "k of FMPM(k) heat transport on the capacity matrix c̃", "-1"},
      {"step", "transport_limiter", "string", "\"none\"", true, "\"none\" | \"fct\"", "",
       "A bound on FMPM(k) transport: flux-corrected transport (needs transport = \"FMPM\", "
       "blend_alpha = 1)",
       "\"bogus\""},
      {"step", "transfer", "string", "\"standard\"", true,
       "\"standard\" | \"velocity_gradient\" | \"apic\"", "",
       "P2G of the momenta: standard, with the particles' velocity gradients (Wallstedt & Guilkey "
       "2007) or APIC",
       "\"bogus\""},
      {"step", "contact_corrections", "string", "\"twice\"", true, "\"twice\" | \"once\"", "",
       "Contact after the extrapolation and the momentum update, or after the latter only "
       "(contact 2020 §3.2)",
       "\"bogus\""},
      {"step", "bc_ordering", "string", "\"correct\"", true, "\"correct\" | \"improper\"", "",
       "Where zero-velocity conditions act: BC1 and BC2, or Buzzi et al.'s improper BC2 and BC3 "
       "(Buzzi §5.5)",
       "\"bogus\""},

      // [output]
      {"output", "file", "string", "the input's name with .h5", false, "", "",
       "The path of the HDF5 run file", "1"},
      {"output", "every", "number", "end / 10", false, "> 0, at most 100000 frames to end", "time",
       "The simulated time between output frames", "0.0"},
      {"output", "matrices", "boolean", "false", true, "", "",
       "Also write S, G_d and m̃ of every frame in CSR form", "1"},
      {"output", "units", "string", "\"none\"", true, "\"none\" | \"SI\" | \"mm-ms-g\"", "",
       "The consistent unit system of the input's numbers, stored in the run file for the "
       "plotting scripts' labels; it changes no number",
       "\"bogus\""},

      // [loads]
      {"loads", "gravity", "array of d numbers", "0 on every axis", false, "", "length/time^2",
       "A uniform body acceleration per axis", "[0.0, 0.0, 0.0, 0.0]"},
      {"loads", "body_force", "array of tables", "none", false, "", "",
       "Forces per unit mass on a body's particles, one [[loads.body_force]] table each", "1"},
      {"loads", "traction", "array of tables", "none", false, "", "",
       "Forces per unit reference area on a face of a body, one [[loads.traction]] table each",
       "1"},

      // [[loads.body_force]]
      {"loads.body_force", "body", "name (string) or index (integer) of a [[body]]",
       "every particle", false, "a body's name, or 0 to the bodies' count − 1", "",
       "The body whose particles the force acts on", "-1"},
      {"loads.body_force", "value", "array of d numbers or expressions of t, x, y, z", "required",
       false, "finite", "force/mass",
       "b, the force per unit mass, evaluated once per step at the particles' positions",
       "[0.0, 0.0, 0.0, 0.0]"},

      // [[loads.traction]]
      {"loads.traction", "body", "name (string) or index (integer) of a [[body]]", "every particle",
       false, "a body's name, or 0 to the bodies' count − 1", "",
       "The body on whose boundary the traction acts", "-1"},
      {"loads.traction", "face", "string", "required", false,
       "\"+x\" | \"-x\" | \"+y\" | \"-y\" | \"+z\" | \"-z\" (the grid's axes)", "",
       "The side of the particles' domains the traction acts on, where that side is on the "
       "body's boundary",
       "\"x\""},
      {"loads.traction", "value", "array of d numbers or expressions of t, x, y, z", "required",
       false, "finite", "force/length^2",
       "The traction, a force per unit reference area on the face (a dead load)",
       "[0.0, 0.0, 0.0, 0.0]"},
      {"loads.traction", "box", "inline table {min, max}", "none (the whole face)", false, "", "",
       "Keep only the particles whose centres are in the box", "1"},

      // loads.traction.box = {min, max}: no example has one, so no bad value is tried (a wrong
      // length, [0.0, 0.0, 0.0, 0.0], is refused).
      {"loads.traction.box", "min", "array of d numbers", "required", false,
       "the box holds a particle with the face exposed", "length", "The lowest corner of the box",
       ""},
      {"loads.traction.box", "max", "array of d numbers", "required", false,
       "the box holds a particle with the face exposed", "length", "The highest corner of the box",
       ""},
  };
}

} // namespace smpm::detail
