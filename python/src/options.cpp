// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.StepOptions and sparsempm.Material: the options of a step and the materials, with
// the names of the input files ([step] and [[material]] keys). Each constructor takes its keyword
// arguments as the object's properties, so the constructor and the attributes have one list of
// names.

#include "bindings.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/exact.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <sstream>

namespace smpm::python {

namespace {

// The property names of a bound class (its `property` attributes), in the class's order.
std::vector<std::string> property_names(const py::handle& type) {
  const py::object property = py::module_::import("builtins").attr("property");
  std::vector<std::string> names;
  for (const auto& [key, value] : type.attr("__dict__").cast<py::dict>())
    if (py::isinstance(value, property))
      names.push_back(key.cast<std::string>());
  return names;
}

// A T with `defaults` and then every keyword argument set as its property: an unknown name is an
// InputError naming the valid ones.
template <class T>
T from_keywords(T defaults, const py::kwargs& keywords, const char* what) {
  py::object obj = py::cast(std::move(defaults));
  const std::vector<std::string> names = property_names(py::type::of(obj));
  for (const auto& [key, value] : keywords) {
    const std::string name = py::str(key);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string valid;
      for (const std::string& n : names)
        valid += (valid.empty() ? "" : ", ") + n;
      throw InputError(std::string(what) + ": unknown option '" + clip(name) +
                       "' (options: " + valid + ")");
    }
    obj.attr(name.c_str()) = value;
  }
  return obj.cast<T>();
}

// A string-valued property over the library's to_string/from_string pair.
template <class Class, class Get, class Set>
void name_property(py::class_<Class>& c, const char* name, Get get, Set set, const char* doc) {
  c.def_property(
      name, [get](const Class& o) { return std::string(to_string(get(o))); }, set, doc);
}

void bind_step_choices(py::class_<StepOptions>& c) {
  name_property(
      c, "shape", [](const StepOptions& o) { return o.shape; },
      [](StepOptions& o, const std::string& s) { o.shape = shape_from_string(s); },
      "linear | gimp | bspline2 | cpdi (default) | b2cpdi");
  name_property(
      c, "scheme", [](const StepOptions& o) { return o.scheme; },
      [](StepOptions& o, const std::string& s) { o.scheme = update_scheme_from_string(s); },
      "update scheme: USL (default) | USF | USL+ | USAVG | USAVG+");
  c.def_property(
      "update", [](const StepOptions& o) { return std::string(to_string(o.scheme)); },
      [](StepOptions& o, const std::string& s) {
        warn_earlier_name("update", "scheme");
        o.scheme = update_scheme_from_string(s);
      },
      "the earlier name of `scheme` (accepted in this release only)");
  c.def_property(
      "velocity", [](const StepOptions& o) { return std::string(velocity_name(o)); },
      [](StepOptions& o, const std::string& s) { set_velocity(o, s); },
      "FLIP (default) | PIC | FMPM | XPIC | exact | chebyshev | least_squares | chebyshev_squared "
      "(FMPM's loop with that polynomial on [interval_low, 1])");
  name_property(
      c, "deformation", [](const StepOptions& o) { return o.deformation; },
      [](StepOptions& o, const std::string& s) {
        o.deformation = deformation_update_from_string(s);
      },
      "linear: F <- (I + L dt) F (default) | exponential: F <- exp(L dt) F");
  name_property(
      c, "bc_method", [](const StepOptions& o) { return o.fmpm.bc_method; },
      [](StepOptions& o, const std::string& s) { o.fmpm.bc_method = bc_method_from_string(s); },
      "velocity BCs of the FMPM loop (FMPM 2026 §3.1): incremental | lumped | velocity | combined");
  name_property(
      c, "dynamic_metric", [](const StepOptions& o) { return o.fmpm.metric; },
      [](StepOptions& o, const std::string& s) {
        o.fmpm.metric = convergence_metric_from_string(s);
      },
      "dynamic FMPM (§3.4): none | means | changes");
  name_property(
      c, "nodes", [](const StepOptions& o) { return o.nodes; },
      [](StepOptions& o, const std::string& s) { o.nodes = node_range_from_string(s); },
      "the nodes of a step: 'particles', the window of the grid its particles reach (memory and "
      "time follow the particles), or 'grid', every node; the results are the same");
  name_property(
      c, "transport", [](const StepOptions& o) { return o.transport.update; },
      [](StepOptions& o, const std::string& s) {
        o.transport.update = transport_update_from_string(s);
      },
      "heat transport (transport.hpp): 'off' (isothermal, the default) | 'lumped': T_p += dt "
      "S c^-1 q (FLIP) | 'FMPM': T_p = S c~_k^-1 tau+ by the FMPM loop on c~ (k = "
      "transport_order) | 'exact': T_p = S c~^-1 tau+ (CHOLMOD)");
  name_property(
      c, "transport_limiter", [](const StepOptions& o) { return o.transport.limiter; },
      [](StepOptions& o, const std::string& s) {
        o.transport.limiter = transport_limiter_from_string(s);
      },
      "a bound on FMPM(k) transport: 'none' (the default) | 'fct': flux-corrected transport "
      "(Zalesak 1979) of FMPM(k)'s correction over FMPM(1), which keeps each nodal temperature "
      "between its neighbours' and its particles' (a positive source then lowers no "
      "temperature) and conserves heat");
  name_property(
      c, "transfer", [](const StepOptions& o) { return o.transfer; },
      [](StepOptions& o, const std::string& s) { o.transfer = transfer_from_string(s); },
      "P2G of the momenta: 'standard' (default): p = S^T M V | 'velocity_gradient': p_i = "
      "sum_p S_ip M_p (V_p + L_p (x_i - X_p)), L_p = G v of the particle update (Wallstedt & "
      "Guilkey 2007) | 'apic': the same P2G with L_p = C_p = B_p D_p^-1, B_p = sum_i v_i (x) "
      "S_pi (x_i - X_p) and D_p = sum_i S_pi (x_i - X_p)(x_i - X_p)^T of the particle update "
      "(Jiang et al. 2015)");
}

void bind_step_numbers(py::class_<StepOptions>& c) {
  c.def_property(
      "order", [](const StepOptions& o) { return o.fmpm.order; },
      [](StepOptions& o, int k) { o.fmpm.order = k; }, "k of FMPM(k), m of XPIC(m)");
  c.def_property(
      "transport_order", [](const StepOptions& o) { return o.transport.order; },
      [](StepOptions& o, int k) { o.transport.order = k; },
      "k of FMPM(k) on c~ (transport = 'FMPM'); 0: the mechanics' order (velocity FMPM or XPIC)");
  c.def_property(
      "blend_alpha", [](const StepOptions& o) { return o.fmpm.blend_alpha; },
      [](StepOptions& o, double a) { o.fmpm.blend_alpha = a; },
      "blending fraction α of §3.3 (1: none)");
  c.def_property(
      "interval_low", [](const StepOptions& o) { return o.fmpm.interval_low; },
      [](StepOptions& o, double v) { o.fmpm.interval_low = v; },
      "λ_lo of the interval [λ_lo, 1] of the Chebyshev and least-squares polynomials "
      "(mass_spectrum's min_eig_minv_mt covers the spectrum)");
  c.def_property(
      "blend_every", [](const StepOptions& o) { return o.fmpm.blend_every; },
      [](StepOptions& o, int e) { o.fmpm.blend_every = e; }, "blend every m-th pass (§3.3)");
  c.def_property(
      "dynamic_limit", [](const StepOptions& o) { return o.fmpm.dynamic_limit; },
      [](StepOptions& o, double v) { o.fmpm.dynamic_limit = v; },
      "dynamic FMPM: stop at the first pass whose metric is below this (0: run to the order)");
  c.def_readwrite("position_alpha", &StepOptions::position_alpha,
                  "α of FMPM 2026 Eqs. (8)-(9); None: 1 for FLIP, 1/2 otherwise");
  c.def_readwrite("periodic_cx", &StepOptions::periodic_cx,
                  "periodic FMPM's Courant budget C_X (§3.3; 0: FMPM on every step)");
  c.def_property(
      "xpic_contact_term", [](const StepOptions& o) { return o.xpic_contact == XpicContact::Term; },
      [](StepOptions& o, bool term) {
        warn_earlier_name("xpic_contact_term", "xpic_contact");
        o.xpic_contact = term ? XpicContact::Term : XpicContact::None;
      },
      "the earlier name of `xpic_contact` (True: 'term', False: 'none'; accepted in this "
      "release only)");
  name_property(
      c, "xpic_contact", [](const StepOptions& o) { return o.xpic_contact; },
      [](StepOptions& o, const std::string& s) { o.xpic_contact = xpic_contact_from_string(s); },
      "multimaterial XPIC(m): 'increments' (contact on every increment of the loop), 'term' "
      "(contact 2020 Eq. (37)'s term) or 'none'");
  name_property(
      c, "bc_ordering", [](const StepOptions& o) { return o.bc_ordering; },
      [](StepOptions& o, const std::string& s) { o.bc_ordering = bc_ordering_from_string(s); },
      "where velocity BCs act (Buzzi et al. §5.5): 'correct' (BC1 after the extrapolation and "
      "BC2 on the rates) or 'improper' (BC2 and BC3, the BC velocity only in the strain update, "
      "without BC1: his Fig. 22, kept for comparison)");
  name_property(
      c, "contact_corrections", [](const StepOptions& o) { return o.contact_corrections; },
      [](StepOptions& o, const std::string& s) {
        o.contact_corrections = contact_corrections_from_string(s);
      },
      "multimaterial contact: 'twice' (after the extrapolation and after the momentum update, "
      "contact 2020 §3.2) or 'once' (after the momentum update only: the paper's \"LR Once\")");
  c.def_property(
      "exact_regularization", [](const StepOptions& o) { return o.exact.regularization; },
      [](StepOptions& o, double eps) { o.exact.regularization = eps; },
      "exact: factor (1 - eps) m~ + eps m");
  c.def_property(
      "exact_mass_cutoff", [](const StepOptions& o) { return o.exact.mass_cutoff; },
      [](StepOptions& o, double tau) { o.exact.mass_cutoff = tau; },
      "exact: nodes below tau max m take p_i / m_i");
  c.def_property(
      "exact_method", [](const StepOptions& o) { return std::string(to_string(o.exact.method)); },
      [](StepOptions& o, const std::string& s) { o.exact.method = exact_method_from_string(s); },
      "exact: 'factor' (CHOLMOD, UMFPACK for m~_L) or 'pcg' (conjugate gradient, symmetric m~)");
  c.def_property(
      "exact_tolerance", [](const StepOptions& o) { return o.exact.tolerance; },
      [](StepOptions& o, double tol) { o.exact.tolerance = tol; },
      "exact, pcg: the relative residual at which the conjugate gradient stops");
  c.def_property(
      "exact_preconditioner",
      [](const StepOptions& o) { return std::string(to_string(o.exact.preconditioner)); },
      [](StepOptions& o, const std::string& s) {
        o.exact.preconditioner = exact_preconditioner_from_string(s);
      },
      "exact, pcg: 'diagonal' (Jacobi) or 'ic' (incomplete Cholesky)");
}

std::string repr(const StepOptions& o) {
  std::ostringstream os;
  os << "StepOptions(shape='" << to_string(o.shape) << "', scheme='" << to_string(o.scheme)
     << "', velocity='" << velocity_name(o) << "', order=" << o.fmpm.order
     << ", blend_alpha=" << o.fmpm.blend_alpha << ", blend_every=" << o.fmpm.blend_every
     << ", position_alpha=" << position_alpha(o) << ", transport='" << to_string(o.transport.update)
     << "', transport_order=" << o.transport.order;
  if (o.transport.limiter != TransportLimiter::None)
    os << ", transport_limiter='" << to_string(o.transport.limiter) << "'";
  os << ")";
  return os.str();
}

void bind_step_options(py::module_& m) {
  py::class_<StepOptions> c(m, "StepOptions",
                            "The options of a time step (step_options.hpp): StepOptions(**options) "
                            "with the keys and values of the [step] table of the input files, "
                            "each also an attribute.");
  c.def(py::init([](const py::kwargs& options) {
          StepOptions defaults;
          defaults.exact_solver = exact_solver_factory();
          StepOptions o = from_keywords(std::move(defaults), options, "StepOptions");
          validate(o);
          return o;
        }),
        "StepOptions(scheme='USL', velocity='FLIP', shape='cpdi', order=1, ...): every option "
        "of the [step] table by name; the rest keep their defaults.");
  bind_step_choices(c);
  bind_step_numbers(c);
  c.def(
      "validate", [](const StepOptions& o) { validate(o); },
      "Raises InputError for values outside their ranges (the limits of the input files).");
  c.def("copy", [](const StepOptions& o) { return o; });
  c.def("__repr__", &repr);
}

// The constants of the elastic and Mie–Grüneisen models.
void bind_material_constants(py::class_<Material>& c) {
  c.def_readwrite("density", &Material::density, "rho_0, the reference density");
  c.def_readwrite("youngs", &Material::youngs, "E (not mie-gruneisen)");
  c.def_readwrite("poisson", &Material::poisson, "ν (not mie-gruneisen)");
  c.def_readwrite("bulk", &Material::bulk, "mie-gruneisen: K");
  c.def_readwrite("shear", &Material::shear, "mie-gruneisen: G (0: a fluid)");
  c.def_readwrite("gruneisen", &Material::gruneisen, "mie-gruneisen: γ₀");
  c.def_readwrite("s1", &Material::hugoniot_slope, "mie-gruneisen: the Hugoniot slope S₁");
  c.def_property(
      "viscosity",
      [](const Material& mat) {
        return std::vector<double>{mat.av_linear, mat.av_quadratic};
      },
      [](Material& mat, const std::vector<double>& a) {
        if (a.size() != 2)
          throw InputError("Material.viscosity: expected [A1, A2]");
        mat.av_linear = a[0];
        mat.av_quadratic = a[1];
      },
      "mie-gruneisen: the artificial viscosity [A1, A2] (contact 2020 Eq. 52)");
}

// The heat properties and J2 plasticity.
void bind_material_heat_and_yield(py::class_<Material>& c) {
  c.def_readwrite("heat_capacity", &Material::heat_capacity,
                  "C_V, heat capacity per unit mass (> 0 with heat transport)");
  c.def_readwrite("conductivity", &Material::conductivity,
                  "kappa, isotropic thermal conductivity (0: none)");
  c.def_readwrite("reference_temperature", &Material::reference_temperature,
                  "T_ref, the stress-free absolute temperature: the particles' initial "
                  "temperature and the origin of Q, S and A (> 0 with heat transport)");
  c.def_readwrite("thermal_expansion", &Material::thermal_expansion,
                  "alpha, the linear coefficient of thermal expansion from T_ref (0: none; not "
                  "for mie-gruneisen)");
  c.def_readwrite("yield_stress", &Material::yield_stress,
                  "sigma_y, the initial yield stress of J2 plasticity (hyperelastic and "
                  "mie-gruneisen; 0: elastic)");
  c.def_readwrite("hardening", &Material::hardening,
                  "H, the linear isotropic hardening modulus of J2 plasticity (0: perfect)");
}

// Material(name=..., model=..., density=..., youngs=..., poisson=...), with the heat properties
// and the thermal expansion when they are set.
std::string material_repr(const Material& mat) {
  std::ostringstream os;
  os << "Material(name='" << mat.name << "', model='" << to_string(mat.model)
     << "', density=" << mat.density << ", youngs=" << mat.youngs << ", poisson=" << mat.poisson;
  if (mat.heat_capacity != 0 || mat.conductivity != 0 || mat.reference_temperature != 0)
    os << ", heat_capacity=" << mat.heat_capacity << ", conductivity=" << mat.conductivity
       << ", reference_temperature=" << mat.reference_temperature;
  if (mat.thermal_expansion != 0)
    os << ", thermal_expansion=" << mat.thermal_expansion;
  os << ")";
  return os.str();
}

void bind_material(py::module_& m) {
  py::class_<Material> c(m, "Material",
                         "A material (material.hpp): Material(name, model, density, youngs, "
                         "poisson, **parameters) with the keys of the [[material]] tables, each "
                         "also an attribute.");
  // density, youngs and poisson may also be given by position, as before the keyword form.
  c.def(py::init([](const std::string& name, const std::string& model,
                    std::optional<double> density, std::optional<double> youngs,
                    std::optional<double> poisson, const py::kwargs& kw) {
          Material mat{.name = name, .model = material_model_from_string(model)};
          if (density)
            mat.density = *density;
          if (youngs)
            mat.youngs = *youngs;
          if (poisson)
            mat.poisson = *poisson;
          mat = from_keywords(std::move(mat), kw, "Material");
          validate_material(mat);
          return mat;
        }),
        py::arg("name") = "material", py::arg("model") = "linear", py::arg("density") = py::none(),
        py::arg("youngs") = py::none(), py::arg("poisson") = py::none());
  c.def_readwrite("name", &Material::name, "the [[material]] name");
  name_property(
      c, "model", [](const Material& mat) { return mat.model; },
      [](Material& mat, const std::string& s) { mat.model = material_model_from_string(s); },
      "linear | linear-corotational | neo-hookean | hyperelastic | mie-gruneisen");
  bind_material_constants(c);
  bind_material_heat_and_yield(c);
  c.def("wave_speed", &Material::wave_speed, py::arg("dim"));
  c.def("__repr__", &material_repr);
}

} // namespace

void validate_material(const Material& mat) {
  validate(mat);
  // The heat keys: 0 is "not given" (the input reader's default); heat transport itself
  // requires C_V > 0 and T_ref > 0 of every material (prepare_transport).
  const std::pair<const char*, double> heat[] = {
      {"heat_capacity", mat.heat_capacity},
      {"conductivity", mat.conductivity},
      {"reference_temperature", mat.reference_temperature}};
  for (const auto& [key, value] : heat)
    if (!(value >= 0) || !std::isfinite(value))
      throw InputError("material '" + mat.name + "': " + key +
                       " must be non-negative and finite, got " + number_text(value));
}

void bind_options(py::module_& m) {
  bind_material(m);
  bind_step_options(m);
}

} // namespace smpm::python
