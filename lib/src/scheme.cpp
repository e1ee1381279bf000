// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/scheme.hpp"

#include "parallel.hpp"

#include "sparsempm/errors.hpp"

namespace smpm {

namespace {

// The stages of scheme_step over one context, with its scratch.
struct Stages {
  const StepContext& c;
  const StepOptions& opt;
  const ParticleOperators op;
  ParticleFields& fields;
  StrainUpdate& strain;
  StepBuffers& b;
  const bool full_mass; // this step uses m̃

  Stages(const StepContext& context, ParticleFields& f, StrainUpdate& s, StepBuffers& buffers)
      : c(context), opt(*context.options), op(particle_operators(*context.ops)), fields(f),
        strain(s), b(buffers), full_mass(uses_consistent_mass(opt, context.grid_update)) {}

  bool correct_bcs() const { return opt.bc_ordering == BCOrdering::Correct; }

  // Multimaterial contact on momenta p (contact 2020 §3.2): after each extrapolation to the
  // grid (Eq. 26, no force), and after the momentum update with the contact force
  // f^{αC,1} = Δp^{α+}/Δt added to f, so that a^α = (m^α)⁻¹(f^{α0} + f^{αC,1}) (Eqs. 32–34).
  void contact(Field& p, Field* force = nullptr) {
    if (c.contact_nodes)
      apply_contact(*c.ops, *c.contact_nodes, c.dt, p, force);
  }

  // The FMPM options of this step's grid-velocity solve: the order k on the full-mass steps of
  // FMPM(k), the lumped inverse (k = 1) on every other step.
  FmpmOptions solve_options() const {
    FmpmOptions f = opt.fmpm;
    if (!(full_mass && opt.velocity == VelocityUpdate::FMPM))
      f.order = 1;
    return f;
  }

  // v = m̃_k⁻¹ p with this step's mass inverse (tasks 1.c, 3.b, 4.c of Fig. 1). `lumped_bcs`
  // and `reaction` on the momentum update (task 3.b), whose lumped BCs (task 2.a, by the BC
  // method of §3.1) are applied here (updated_velocity) and whose contact corrections do
  // frictional work; the other momenta carry BC1 already.
  void grid_velocity(Field& p, Field& v, bool lumped_bcs = false, Field* reaction = nullptr) {
    const LoopConstraints bc{c.grid, c.bcs, c.time, c.sums};
    const bool heat = reaction != nullptr;
    if (full_mass && opt.velocity == VelocityUpdate::Exact) {
      if (lumped_bcs) // task 2.a; the solve imposes the BC values itself
        c.bcs->constrain_update(*c.grid, c.ops->m, c.time, c.dt, p, *reaction);
      c.solver->solve(*c.ops, *c.mt, bc, p, v);
      if (c.contact_nodes) { // each field's m̃^α with contact at the Net limit (§3.2)
        b.p_contact = p;
        exact_contact(
            *c.ops, *c.contact_nodes, c.dt,
            [this](const Field& r, Field& u) { c.solver->solve_again(r, u); }, b.p_contact, v,
            heat);
      }
      return;
    }
    // Multimaterial: one loop over the block-diagonal m̃ runs every field's loop, and contact
    // corrects each increment (FMPM 2026 §3.2), from the state of the lumped correction of p.
    std::function<void(int, Field&, const Field&)> hook;
    if (c.contact_nodes)
      hook = [this, heat](int, Field& dv, const Field&) {
        contact_increment(*c.ops, *c.contact_nodes, c.dt, dv, heat);
      };
    const FmpmOptions f = solve_options();
    const FmpmReport report =
        updated_velocity(*c.ops, c.mt, f, bc, lumped_bcs, c.dt, p, reaction, v, b.fmpm, hook);
    if (f.order > 1)
      b.report = report;
  }

  // Velocity gradient, F and stress from grid velocities v (Buzzi Fig. 7; FMPM 2026 task 5).
  void strain_update(const Field& v, double dt) {
    const Field* vs = &v;
    if (!correct_bcs()) { // BC3: the BC velocity only for the strains
      b.v_strain = v;
      c.bcs->constrain_velocity(*c.grid, c.time, b.v_strain, &c.ops->active);
      vs = &b.v_strain;
    }
    strain.update(op, *vs, dt, fields);
  }

  // Task 1: p = Sᵀ M V (with the transfer's affine term, c.affine), BC1, v = m⁻¹ p; task 1.c for
  // USF, USAVG and USAVG+.
  void momentum() {
    map_momentum(op, fields.V, b.g.p, c.affine);
    if (c.sums) // the totals over the processes
      c.sums->add(b.g.p);
    const bool once = opt.contact_corrections == ContactCorrections::Once;
    if (c.contact_nodes && opt.velocity == VelocityUpdate::XPIC &&
        opt.xpic_contact == XpicContact::Term) { // keep Δv^α (Eq. 37)
      b.contact_dv = b.g.p;
      if (!once)
        contact(b.g.p);
      b.contact_dv = c.ops->m_inv.asDiagonal() * (b.g.p - b.contact_dv);
    } else if (!once) {
      contact(b.g.p);
    }
    if (correct_bcs())
      c.bcs->constrain_momentum(*c.grid, c.ops->m, c.time, b.g.p);
    lumped_solve(c.ops->m_inv, b.g.p, b.g.v);
    const UpdateScheme s = opt.scheme;
    if (s == UpdateScheme::USF || s == UpdateScheme::USAVG || s == UpdateScheme::USAVGPlus) {
      grid_velocity(b.g.p, b.v_re);
      strain_update(b.v_re, s == UpdateScheme::USF ? c.dt : 0.5 * c.dt);
    }
  }

  // Tasks 2–3: forces, BC2 with reaction forces, p⁺ = p + f Δt, v⁺ = m̃_k⁻¹ p⁺ (task 3.b).
  void forces_and_velocity() {
    GridState& g = b.g;
    internal_force(op, fields.volume0, fields.F, fields.stress, g.f);
    if (c.sums) { // the particles' forces summed over the processes, then gravity on the total m
      if (c.external)
        add_external_forces(op, *c.grid, *c.external, g.f);
      c.sums->add(g.f);
      add_gravity(c.ops->m, c.gravity, g.f);
    } else {
      add_gravity(c.ops->m, c.gravity, g.f);
      if (c.external)
        add_external_forces(op, *c.grid, *c.external, g.f);
    }
    if (!correct_bcs())
      c.bcs->zero_directions(*c.grid, g.f); // BC2 alone: zero rate of momentum (Buzzi Eq. 28)
    // Node-wise, in node ranges (each thread mostly on the nodes it summed).
    g.p_plus.resize(g.p.rows(), g.p.cols());
    detail::parallel_segments(g.p.rows(), [&](Index r0, Index m) {
      g.p_plus.middleRows(r0, m).noalias() = g.p.middleRows(r0, m) + c.dt * g.f.middleRows(r0, m);
    });
    contact(g.p_plus, &g.f);
    // Task 2.a (correct ordering): p⁺ takes the BC velocity and f the reaction f^(BC) = Δp/Δt,
    // by the BC method of §3.1; then v⁺ (task 3.b). The reaction is f's change (storage reused).
    g.reaction.resize(g.f.rows(), g.f.cols());
    detail::parallel_segments(g.f.rows(), [&](Index r0, Index m) {
      g.reaction.middleRows(r0, m) = g.f.middleRows(r0, m);
    });
    grid_velocity(g.p_plus, g.v_plus, correct_bcs(), &g.f);
    detail::parallel_segments(g.f.rows(), [&](Index r0, Index m) {
      g.reaction.middleRows(r0, m) = g.f.middleRows(r0, m) - g.reaction.middleRows(r0, m);
    });
    lumped_solve(c.ops->m_inv, g.f, g.a);
  }

  // XPIC(m)'s m(v − v*) = Σ_{j<m} A^j v (contact 2020 Eqs. 41–43) as the loop of FMPM 2026
  // Table 1 run from the contact-corrected v of the extrapolation (task 1), unblended and to
  // order m, its increments corrected by the velocity BCs (Table 2's incremental method,
  // `bc_method`) and by contact (§3.2, each pair's Net or Evolving method) from the state of
  // the momentum update's lumped contact, so that the contact law holds on v⁺ plus the
  // increments, the velocity the particles take. NairnMPM's XPIC task does the same
  // (XPICExtrapolationTask: GetDeltaV zeroes the BC nodes of each increment and imposes incremental
  // contact).
  void xpic_loop_velocity() {
    FmpmOptions f = opt.fmpm;
    f.blend_alpha = 1;
    f.metric = ConvergenceMetric::None;
    std::function<void(int, Field&, const Field&)> hook;
    if (c.contact_nodes)
      hook = [this](int, Field& dv, const Field&) { // frictional work as the FMPM loop's
        contact_increment(*c.ops, *c.contact_nodes, c.dt, dv, true);
      };
    b.xpic = b.g.v;
    fmpm_velocity(*c.ops, *c.mt, f, LoopConstraints{c.grid, c.bcs, c.time}, b.xpic, b.fmpm, hook);
  }

  // Task 4: Eq. (8) on FLIP steps, Eq. (9) for PIC, FMPM(k) and exact, contact 2020 Eq. (35)
  // for XPIC(m). Returns the grid velocity the particles took.
  const Field& particle_update() {
    const double alpha = position_alpha(opt);
    if (!c.grid_update) { // FLIP, or a FLIP step of periodic FMPM
      update_particles_flip(op, b.g.v_plus, b.g.a, c.dt, alpha, fields.X, fields.V);
      return b.g.v_plus;
    }
    if (opt.velocity != VelocityUpdate::XPIC) {
      update_particles_pic(op, b.g.v_plus, c.dt, alpha, fields.X, fields.V);
      return b.g.v_plus;
    }
    if (full_mass && opt.xpic_contact == XpicContact::Increments) {
      xpic_loop_velocity();
      b.xpic.noalias() += c.dt * b.g.a; // V' = S (m (v − v*) + a Δt)
    } else if (full_mass) {
      const bool term = c.contact_nodes && opt.xpic_contact == XpicContact::Term;
      xpic_grid_velocity(*c.ops, *c.mt, opt.fmpm.order, b.g.v, b.xpic, b.fmpm,
                         term ? &b.contact_dv : nullptr);
      b.xpic.noalias() += c.dt * b.g.a; // V' = S (m (v − v*) + a Δt)
    } else {
      b.xpic = b.g.v_plus; // XPIC(1) = PIC
    }
    update_particles_pic(op, b.xpic, c.dt, alpha, fields.X, fields.V);
    return b.xpic;
  }

  // Task 5: stresses last (USL, USL+, USAVG, USAVG+); tasks 4.a–4.c re-extrapolate with the
  // same S for USL+ and USAVG+.
  void stresses_last() {
    const UpdateScheme s = opt.scheme;
    if (s == UpdateScheme::USF)
      return;
    const double dt_last =
        (s == UpdateScheme::USL || s == UpdateScheme::USLPlus) ? c.dt : 0.5 * c.dt;
    if (s == UpdateScheme::USLPlus || s == UpdateScheme::USAVGPlus) {
      map_momentum(op, fields.V, b.p_re, c.affine);
      if (c.sums)
        c.sums->add(b.p_re);
      contact(b.p_re);
      if (correct_bcs())
        c.bcs->constrain_momentum(*c.grid, c.ops->m, c.time, b.p_re);
      grid_velocity(b.p_re, b.v_re);
      strain_update(b.v_re, dt_last);
    } else {
      strain_update(b.g.v_plus, dt_last);
    }
  }
};

} // namespace

void scheme_step(const StepContext& context, ParticleFields& fields, StrainUpdate& strain,
                 StepBuffers& buffers) {
  SMPM_VERIFY(context.options && context.ops && context.grid && context.bcs,
              "scheme_step: the context needs options, operators, grid and BCs");
  Stages s(context, fields, strain, buffers);
  SMPM_VERIFY(!s.full_mass || context.mt, "scheme_step: this step needs m~ (context.mt)");
  SMPM_VERIFY(context.options->velocity != VelocityUpdate::Exact || context.solver,
              "scheme_step: the exact update needs a MassSolver (context.solver)");
  SMPM_VERIFY(!context.sums || (!context.contact_nodes && !context.affine &&
                                context.options->velocity != VelocityUpdate::XPIC),
              "scheme_step: across processes a step is FLIP, PIC, FMPM(k) or exact (with a "
              "MassSolver across them) in single material mode with the standard transfer (the "
              "parts answer for themselves: StepPart::not_distributed)");
  buffers.report = FmpmReport{};
  buffers.fmpm.metrics.clear(); // a step without a loop has no trace
  s.momentum();
  for (StageHooks* h : context.hooks)
    h->after_momentum(context, fields);
  s.forces_and_velocity();
  for (StageHooks* h : context.hooks)
    h->after_velocity(context, fields);
  const Field& u = s.particle_update();
  for (StageHooks* h : context.hooks)
    h->after_particles(context, u, fields);
  s.stresses_last();
}

} // namespace smpm
