// SPDX-License-Identifier: BSD-3-Clause
// The [step] table: the update scheme, the velocity update, the shape functions, the F update,
// the transfer and the transport, and the FMPM family's options, checked against the library's
// limits.
#include "reader.hpp"

#include "sparsempm/exact.hpp"

#include <algorithm>
#include <limits>
#include <optional>

namespace smpm::detail {

namespace {

// An integer key (its range is checked by the library's validate).
std::optional<int> integer(const Reader& r, const toml::table& t, const char* key,
                           const std::string& name) {
  const toml::node* n = t.get(key);
  if (!n)
    return std::nullopt;
  const auto v = n->value<int64_t>();
  if (!v || !n->is_integer())
    r.fail(n, name, "expected an integer");
  return int(
      std::clamp<int64_t>(*v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

// FMPM(k), XPIC(m), blending, periodic and dynamic FMPM, BC method, exact solver options.
void read_fmpm(const Reader& r, const toml::table& t, StepOptions& step) {
  FmpmOptions& f = step.fmpm;
  if (const auto k = integer(r, t, "order", "step.order"))
    f.order = *k;
  else if (step.velocity == VelocityUpdate::FMPM || step.velocity == VelocityUpdate::XPIC)
    r.fail(nullptr, "step.order", "missing required key (the order k of FMPM or m of XPIC)");
  f.blend_alpha = r.number(t, "blend_alpha", "step.blend_alpha", 1.0);
  if (const auto m = integer(r, t, "blend_every", "step.blend_every"))
    f.blend_every = *m;
  step.periodic_cx = r.number(t, "periodic_cx", "step.periodic_cx", 0.0);
  f.metric =
      r.choice(t, "dynamic_metric", "step.dynamic_metric", "none", &convergence_metric_from_string);
  f.dynamic_limit = r.number(t, "dynamic_limit", "step.dynamic_limit", 0.0);
  if (f.metric != ConvergenceMetric::None && !t.get("dynamic_limit"))
    r.fail(t.get("dynamic_metric"), "step.dynamic_metric",
           "needs step.dynamic_limit (the convergence limit)");
  f.bc_method = r.choice(t, "bc_method", "step.bc_method", "incremental", &bc_method_from_string);
  f.interval_low = r.number(t, "interval_low", "step.interval_low", 0.0);
  step.exact.regularization = r.number(t, "exact_regularization", "step.exact_regularization", 0.0);
  step.exact.mass_cutoff = r.number(t, "exact_mass_cutoff", "step.exact_mass_cutoff", 0.0);
  step.exact.method =
      r.choice(t, "exact_method", "step.exact_method", "factor", exact_method_from_string);
  step.exact.tolerance = r.number(t, "exact_tolerance", "step.exact_tolerance", 1e-12);
  step.exact.preconditioner = r.choice(t, "exact_preconditioner", "step.exact_preconditioner",
                                       "diagonal", exact_preconditioner_from_string);
  // Always set, so that analyses adding an exact row (smpm stability) use these options.
  step.exact_solver = exact_solver_factory();
}

} // namespace

// [step]: update scheme, velocity update, shape functions, α, F update and the FMPM family.
void read_step(const Reader& r, const toml::table& root, StepOptions& step) {
  static const toml::table empty;
  const toml::table* table = r.table(root, "step", "[step]", false);
  const toml::table& t = table ? *table : empty;
  r.check_keys(t, "step");
  step.scheme = r.choice(t, "scheme", "step.scheme", "USL", &update_scheme_from_string);
  const VelocityChoice velocity =
      r.choice(t, "velocity", "step.velocity", "FLIP", &velocity_choice_from_string);
  step.velocity = velocity.velocity;
  step.fmpm.polynomial = velocity.polynomial;
  step.shape = r.choice(t, "shape", "step.shape", "cpdi", &shape_from_string);
  // α of Eqs. (8)–(9); unset: default_position_alpha (1 for FLIP, ½ otherwise).
  if (t.get("position_alpha"))
    step.position_alpha = r.number(t, "position_alpha", "step.position_alpha", 0.0);
  step.deformation =
      r.choice(t, "deformation", "step.deformation", "linear", &deformation_update_from_string);
  step.xpic_contact =
      r.choice(t, "xpic_contact", "step.xpic_contact", "increments", &xpic_contact_from_string);
  step.bc_ordering =
      r.choice(t, "bc_ordering", "step.bc_ordering", "correct", &bc_ordering_from_string);
  step.contact_corrections = r.choice(t, "contact_corrections", "step.contact_corrections", "twice",
                                      &contact_corrections_from_string);
  step.transfer = r.choice(t, "transfer", "step.transfer", "standard", &transfer_from_string);
  step.transport.update =
      r.choice(t, "transport", "step.transport", "off", &transport_update_from_string);
  if (const auto k = integer(r, t, "transport_order", "step.transport_order"))
    step.transport.order = *k;
  step.transport.limiter = r.choice(t, "transport_limiter", "step.transport_limiter", "none",
                                    &transport_limiter_from_string);
  read_fmpm(r, t, step);
  // The library's limits (validate of step_options.hpp), at the line of the key they name.
  try {
    validate(step);
  } catch (const OptionError& e) {
    r.fail(t.get(e.key()), "step." + e.key(), e.reason());
  }
}

} // namespace smpm::detail
