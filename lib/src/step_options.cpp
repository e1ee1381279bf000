// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/step_options.hpp"

#include "enum_names.hpp"
#include "sparsempm/errors.hpp"

#include <cmath>

namespace smpm {

namespace {
constexpr detail::EnumNames<UpdateScheme, 5> kSchemes{{{UpdateScheme::USL, "USL"},
                                                       {UpdateScheme::USF, "USF"},
                                                       {UpdateScheme::USLPlus, "USL+"},
                                                       {UpdateScheme::USAVG, "USAVG"},
                                                       {UpdateScheme::USAVGPlus, "USAVG+"}}};
constexpr detail::EnumNames<VelocityUpdate, 5> kVelocities{{{VelocityUpdate::FLIP, "FLIP"},
                                                            {VelocityUpdate::PIC, "PIC"},
                                                            {VelocityUpdate::FMPM, "FMPM"},
                                                            {VelocityUpdate::XPIC, "XPIC"},
                                                            {VelocityUpdate::Exact, "exact"}}};
constexpr detail::EnumNames<Transfer, 3> kTransfers{
    {{Transfer::Standard, "standard"},
     {Transfer::VelocityGradient, "velocity_gradient"},
     {Transfer::Apic, "apic"}}};
constexpr detail::EnumNames<XpicContact, 3> kXpicContacts{{{XpicContact::Increments, "increments"},
                                                           {XpicContact::Term, "term"},
                                                           {XpicContact::None, "none"}}};
constexpr detail::EnumNames<DeformationUpdate, 2> kDeformations{
    {{DeformationUpdate::Linear, "linear"}, {DeformationUpdate::Exponential, "exponential"}}};
} // namespace

std::string_view to_string(DeformationUpdate u) {
  return detail::enum_name(u, kDeformations);
}
DeformationUpdate deformation_update_from_string(std::string_view name) {
  return detail::parse_enum(name, kDeformations, "deformation update");
}

constexpr detail::EnumNames<BCOrdering, 2> kBCOrderings{
    {{BCOrdering::Correct, "correct"}, {BCOrdering::Improper, "improper"}}};

std::string_view to_string(BCOrdering o) {
  return detail::enum_name(o, kBCOrderings);
}
BCOrdering bc_ordering_from_string(std::string_view name) {
  return detail::parse_enum(name, kBCOrderings, "BC ordering");
}

constexpr detail::EnumNames<ContactCorrections, 2> kContactCorrections{
    {{ContactCorrections::Twice, "twice"}, {ContactCorrections::Once, "once"}}};

std::string_view to_string(ContactCorrections c) {
  return detail::enum_name(c, kContactCorrections);
}
ContactCorrections contact_corrections_from_string(std::string_view name) {
  return detail::parse_enum(name, kContactCorrections, "number of contact corrections");
}

std::string_view to_string(XpicContact c) {
  return detail::enum_name(c, kXpicContacts);
}
XpicContact xpic_contact_from_string(std::string_view name) {
  return detail::parse_enum(name, kXpicContacts, "XPIC contact method");
}

std::string_view to_string(Transfer t) {
  return detail::enum_name(t, kTransfers);
}
Transfer transfer_from_string(std::string_view name) {
  return detail::parse_enum(name, kTransfers, "transfer");
}

std::string_view to_string(UpdateScheme s) {
  return detail::enum_name(s, kSchemes);
}
std::string_view to_string(VelocityUpdate v) {
  return detail::enum_name(v, kVelocities);
}
UpdateScheme update_scheme_from_string(std::string_view name) {
  return detail::parse_enum(name, kSchemes, "update scheme");
}
VelocityUpdate velocity_update_from_string(std::string_view name) {
  return detail::parse_enum(name, kVelocities, "velocity update");
}

namespace {
constexpr detail::EnumNames<VelocityChoice, 8> kVelocityChoices{
    {{{VelocityUpdate::FLIP, Polynomial::Series}, "FLIP"},
     {{VelocityUpdate::PIC, Polynomial::Series}, "PIC"},
     {{VelocityUpdate::FMPM, Polynomial::Series}, "FMPM"},
     {{VelocityUpdate::XPIC, Polynomial::Series}, "XPIC"},
     {{VelocityUpdate::Exact, Polynomial::Series}, "exact"},
     {{VelocityUpdate::FMPM, Polynomial::Chebyshev}, "chebyshev"},
     {{VelocityUpdate::FMPM, Polynomial::LeastSquares}, "least_squares"},
     {{VelocityUpdate::FMPM, Polynomial::ChebyshevSquared}, "chebyshev_squared"}}};
} // namespace

VelocityChoice velocity_choice_from_string(std::string_view name) {
  return detail::parse_enum(name, kVelocityChoices, "velocity update");
}
void set_velocity(StepOptions& options, std::string_view name) {
  const VelocityChoice c = velocity_choice_from_string(name);
  options.velocity = c.velocity;
  options.fmpm.polynomial = c.polynomial;
}
std::string_view velocity_name(const StepOptions& options) {
  if (options.velocity == VelocityUpdate::FMPM && options.fmpm.polynomial != Polynomial::Series)
    return to_string(options.fmpm.polynomial);
  return to_string(options.velocity);
}

double default_position_alpha(VelocityUpdate velocity) {
  return velocity == VelocityUpdate::FLIP ? 1.0 : 0.5;
}

double position_alpha(const StepOptions& options) {
  return options.position_alpha.value_or(default_position_alpha(options.velocity));
}

constexpr detail::EnumNames<ExactMethod, 2> kExactMethods{
    {{ExactMethod::Factor, "factor"}, {ExactMethod::PCG, "pcg"}}};
std::string_view to_string(ExactMethod m) {
  return detail::enum_name(m, kExactMethods);
}
ExactMethod exact_method_from_string(std::string_view name) {
  return detail::parse_enum(name, kExactMethods, "exact method");
}
constexpr detail::EnumNames<ExactPreconditioner, 2> kExactPreconditioners{
    {{ExactPreconditioner::Diagonal, "diagonal"}, {ExactPreconditioner::IncompleteCholesky, "ic"}}};
std::string_view to_string(ExactPreconditioner p) {
  return detail::enum_name(p, kExactPreconditioners);
}
ExactPreconditioner exact_preconditioner_from_string(std::string_view name) {
  return detail::parse_enum(name, kExactPreconditioners, "preconditioner");
}

void validate(const ExactOptions& o) {
  if (!(o.regularization >= 0 && o.regularization <= 1))
    throw OptionError("exact_regularization", number_text(o.regularization), "must lie in [0, 1]");
  if (!(o.mass_cutoff >= 0 && o.mass_cutoff < 1))
    throw OptionError("exact_mass_cutoff", number_text(o.mass_cutoff), "must lie in [0, 1)");
  if (!(o.tolerance > 0 && o.tolerance < 1))
    throw OptionError("exact_tolerance", number_text(o.tolerance), "must lie in (0, 1)");
  if (o.method == ExactMethod::PCG && !is_symmetric(o.system))
    throw OptionError("exact_method", "pcg",
                      "the conjugate gradient needs a symmetric matrix, and the " +
                          std::string(to_string(o.system)) + " is not (use \"factor\")");
}

std::string_view to_string(NodalSystem s) {
  switch (s) {
  case NodalSystem::ConsistentMass:
    return "consistent mass matrix m~";
  case NodalSystem::GradientMass:
    return "mass matrix m~_L of the velocity-gradient transfer";
  case NodalSystem::ApicMass:
    return "mass matrix m~_A of the APIC transfer";
  case NodalSystem::ConsistentCapacity:
    return "consistent capacity matrix c~";
  }
  return "nodal matrix";
}

bool is_symmetric(NodalSystem s) {
  return s != NodalSystem::GradientMass;
}

ExactOptions velocity_solver_options(const StepOptions& opt) {
  ExactOptions o = opt.exact;
  switch (opt.transfer) {
  case Transfer::Standard:
    o.system = NodalSystem::ConsistentMass;
    break;
  case Transfer::VelocityGradient:
    o.system = NodalSystem::GradientMass;
    break;
  case Transfer::Apic:
    o.system = NodalSystem::ApicMass;
    break;
  }
  return o;
}

ExactOptions transport_solver_options(const StepOptions& opt) {
  ExactOptions o = opt.exact;
  o.system = NodalSystem::ConsistentCapacity;
  return o;
}

void validate(const StepOptions& opt) {
  validate(opt.fmpm);
  validate(opt.exact);
  validate(velocity_solver_options(opt)); // PCG needs the symmetric m~ or m~_A
  if (!(opt.periodic_cx >= 0) || !std::isfinite(opt.periodic_cx))
    throw OptionError("periodic_cx", number_text(opt.periodic_cx),
                      "must be non-negative and finite (0: FMPM on every step)");
  if (const double alpha = position_alpha(opt); !(alpha >= 0 && alpha <= 1))
    throw OptionError("position_alpha", number_text(alpha), "must lie in [0, 1]");
  SMPM_VERIFY(opt.velocity != VelocityUpdate::Exact || opt.exact_solver,
              "the exact velocity update needs StepOptions::exact_solver (see exact.hpp)");
  const TransportOptions& t = opt.transport;
  if (t.order < 0 || t.order > kMaxFmpmOrder)
    throw OptionError("transport_order", std::to_string(t.order),
                      "must be an integer from 1 to " + std::to_string(kMaxFmpmOrder) +
                          " (0: the order of the velocity update)");
  const bool has_order =
      opt.velocity == VelocityUpdate::FMPM || opt.velocity == VelocityUpdate::XPIC;
  if (t.update == TransportUpdate::FMPM && t.order == 0 && !has_order)
    throw OptionError("transport_order", "0 (unset)",
                      "give the order k of FMPM(k) on the capacity (1 to " +
                          std::to_string(kMaxFmpmOrder) +
                          ") with transport = FMPM, or a velocity update FMPM or XPIC, whose "
                          "order it takes");
  if (t.limiter == TransportLimiter::FCT &&
      (t.update != TransportUpdate::FMPM || opt.fmpm.blend_alpha != 1))
    throw OptionError("transport_limiter", std::string(to_string(t.limiter)),
                      "bounds FMPM(k) transport without blending: needs transport = \"FMPM\" "
                      "and blend_alpha = 1");
  SMPM_VERIFY(t.update != TransportUpdate::Exact || opt.exact_solver,
              "the exact transport update needs StepOptions::exact_solver (see exact.hpp)");
}

FmpmOptions transport_fmpm_options(const StepOptions& opt) {
  FmpmOptions f = opt.fmpm;
  f.order = opt.transport.update != TransportUpdate::FMPM ? 1
            : opt.transport.order > 0                     ? opt.transport.order
                                                          : opt.fmpm.order;
  f.metric = ConvergenceMetric::None;
  f.dynamic_limit = 0;
  // The series on c̃ whatever the velocity update's member: the interval polynomials change
  // sign (their temperatures undershoot) and λ_lo is the mechanics' (docs/studies/polynomials.md).
  f.polynomial = Polynomial::Series;
  f.interval_low = 0;
  return f;
}

bool uses_consistent_capacity(const StepOptions& opt) {
  return opt.transport.update == TransportUpdate::Exact ||
         (opt.transport.update == TransportUpdate::FMPM && transport_fmpm_options(opt).order > 1);
}

bool uses_consistent_mass(const StepOptions& opt, bool grid_update) {
  if (!grid_update)
    return false;
  const bool series = opt.velocity == VelocityUpdate::FMPM || opt.velocity == VelocityUpdate::XPIC;
  return opt.velocity == VelocityUpdate::Exact || (series && opt.fmpm.order > 1);
}

bool periodic_fmpm_step(double periodic_cx, double courant, double& budget) {
  budget += courant;
  const bool due = budget >= periodic_cx * (1 - 1e-12); // round-off of the accumulated budget
  if (due)
    budget = 0;
  return due;
}

int periodic_fmpm_period(double periodic_cx, double courant) {
  SMPM_VERIFY(courant > 0 && periodic_cx >= 0,
              "periodic_fmpm_period: needs a positive Courant number and C_X >= 0");
  if (periodic_cx / courant > 1e8)
    throw InputError("periodic FMPM: C_X / C = " + number_text(periodic_cx / courant) +
                     " steps in a period, more than 1e8");
  double budget = 0;
  int steps = 1;
  while (!periodic_fmpm_step(periodic_cx, courant, budget))
    ++steps;
  return steps;
}

void MassSolver::solve_again(const Field&, Field&) {
  throw InputError("this mass solver cannot solve again with its last matrix (needed by the "
                   "exact update with contact)");
}

} // namespace smpm
