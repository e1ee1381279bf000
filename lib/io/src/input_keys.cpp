// SPDX-License-Identifier: BSD-3-Clause
// The keys of the input files (input.hpp, InputKey): the reader's schema and the input reference.
#include "sparsempm/input.hpp"

#include "toml_text.hpp"

namespace smpm {

const std::vector<InputKey>& input_keys() {
  // The model's tables here; the run's ([time], [step], [output]) and the loads in
  // input_keys_run.cpp.
  static const std::vector<InputKey> keys = [] {
    std::vector<InputKey> model = {
        // table, key, type, fallback, literal, values, unit, description, bad

        // The tables of the top level.
        {"", "grid", "table", "required", false, "", "",
         "The background grid: its dimension, origin, cell size and number of cells", ""},
        {"", "material", "array of tables", "required", false, "at least one, at most 1000", "",
         "The materials, one table each: name, stress law, density and the constants of the law",
         ""},
        {"", "body", "array of tables", "required", false, "at least one", "",
         "The bodies, one table each: a region filled with particles of one material, ppc per cell",
         ""},
        {"", "bc", "array of tables", "optional", false, "", "",
         "The conditions, one table each: fixed axes, a velocity or a temperature on a plane or "
         "box "
         "of nodes, or a moving wall",
         ""},
        {"", "contact", "array of tables", "optional", false, "", "",
         "The contact laws between the materials' velocity fields (contact 2020 §2–3); without "
         "them, "
         "single material mode",
         ""},
        {"", "time", "table", "required", false, "", "",
         "The clock of a run: Courant number, end time, frames landed on, Fourier number, step "
         "limit",
         ""},
        {"", "step", "table", "optional", false, "", "",
         "The options of every step: scheme, velocity update, shape functions and the FMPM family "
         "(FMPM 2026 Fig. 1)",
         ""},
        {"", "output", "table", "optional", false, "", "",
         "The run file: its path, the time between frames and the CSR matrices", ""},
        {"", "loads", "table", "optional", false, "", "",
         "The external forces on the particles: gravity, body forces and tractions (FMPM 2026 "
         "task 2)",
         ""},

        // [grid]
        {"grid", "dim", "integer", "required", false, "1, 2 or 3", "",
         "The number of space dimensions d of the grid and the particles (2D is plane strain)",
         "4"},
        {"grid", "origin", "array of d numbers", "required", false, "", "length",
         "The position of the grid's first node, its lowest corner", "[0.0, 0.0, 0.0, 0.0]"},
        {"grid", "cell_size", "array of d numbers", "required", false, "> 0 each", "length",
         "The cell size along each axis", "[0.0]"},
        {"grid", "cells", "array of d positive integers", "required", false,
         "1 to 10^8 each; at most 5·10^7 nodes (the build's limit)", "",
         "The number of cells along each axis (cells + 1 nodes)", "[0]"},

        // [[material]]
        {"material", "name", "string", "required", false, "unique among the materials", "",
         "The material's name, by which bodies, contact tables and --set material.<name>.key refer "
         "to it",
         "1"},
        {"material", "model", "string", "\"linear\"", true,
         "\"linear\" | \"linear-corotational\" | \"neo-hookean\" | \"hyperelastic\" | "
         "\"mie-gruneisen\" | \"rigid\"",
         "",
         "The stress law (material.hpp); a rigid material's particles move with a prescribed "
         "velocity instead",
         "\"bogus\""},
        {"material", "density", "number", "required", false, "> 0", "mass/length^3",
         "ρ₀, the density of the undeformed material", "0.0"},
        {"material", "youngs", "number", "required, except for mie-gruneisen and rigid (refused)",
         false, "> 0", "force/length^2", "E, Young's modulus of the elastic models", "0.0"},
        {"material", "poisson", "number", "0.0", true, "(-1, 0.5)", "",
         "ν, Poisson's ratio of the elastic models", "0.5"},
        // Mie–Grüneisen keys: the other models refuse them whatever their value; the bad values are
        // tried where an example sets them (mie-gruneisen), which refuses them too.
        {"material", "bulk", "number", "required with model = \"mie-gruneisen\" (its only model)",
         false, "> 0", "force/length^2",
         "K, the bulk modulus of the Mie–Grüneisen law (contact 2020 Eq. 51)", "0.0"},
        {"material", "shear", "number", "0.0 with model = \"mie-gruneisen\" (its only model)",
         false, "≥ 0", "force/length^2",
         "G, the shear modulus of the Mie–Grüneisen law (0: a fluid)", "-1.0"},
        {"material", "gruneisen", "number",
         "required with model = \"mie-gruneisen\" (its only model)", false, "≥ 0", "",
         "γ₀, the Grüneisen parameter of the Mie–Grüneisen pressure (contact 2020 Eq. 51)", "-1.0"},
        {"material", "s1", "number", "required with model = \"mie-gruneisen\" (its only model)",
         false, "≥ 0", "",
         "S₁, the slope of the linear Hugoniot U_s = c₀ + S₁ u_p (contact 2020 Eq. 51)", "-1.0"},
        {"material", "viscosity", "array of 2 numbers", "none (A₁ = A₂ = 0); mie-gruneisen only",
         false, "≥ 0 each", "",
         "[A₁, A₂], the linear and quadratic coefficients of the artificial viscosity q (contact "
         "2020 Eq. 52)",
         "1.0"},
        {"material", "heat_capacity", "number", "required with step.transport", false, "> 0",
         "energy/(mass temperature)", "C_V, the heat capacity per unit mass (FMPM 2026 §3.5)",
         "0.0"},
        {"material", "conductivity", "number", "0.0", true, "≥ 0", "power/(length temperature)",
         "κ, the isotropic thermal conductivity (0: no conduction)", "-1.0"},
        {"material", "reference_temperature", "number", "required with step.transport", false,
         "> 0", "temperature",
         "T_ref, the stress-free absolute temperature and the particles' initial temperature",
         "0.0"},
        {"material", "thermal_expansion", "number", "0.0", true,
         "finite; non-zero needs step.transport, and not mie-gruneisen", "1/temperature",
         "α, the linear coefficient of thermal expansion from T_ref", "\"x\""},
        // yield_stress and hardening: refused whatever their value by the models other than
        // hyperelastic and mie-gruneisen; the bad values are tried where an example sets them.
        {"material", "yield_stress", "number",
         "0.0 (elastic); only hyperelastic and mie-gruneisen take it", false, "≥ 0",
         "force/length^2",
         "σ_y, the initial yield stress in uniaxial tension of J2 plasticity (0: elastic)", "-1.0"},
        {"material", "hardening", "number", "0.0 (perfectly plastic); needs a yield_stress", false,
         "≥ 0", "force/length^2", "H, the linear isotropic hardening modulus dσ_y/dε̄ᵖ", "-1.0"},
        // velocity and free: refused whatever their value by the models other than rigid; the bad
        // values are tried where an example sets them.
        {"material", "velocity", "array of d numbers or expressions of t",
         "required with model = \"rigid\" (its only model)", false,
         "finite at t = 0; numbers with free = true", "length/time",
         "The rigid body's velocity per axis, numbers or expressions of t; with free = true its "
         "initial velocity",
         "1.0"},
        {"material", "free", "boolean", "false; only model = \"rigid\" takes it", false, "", "",
         "Whether the rigid body moves under its reactions, −Δt R / M a step, instead of as "
         "prescribed",
         "1"},

        // [[body]]
        {"body", "material", "name of a [[material]]", "required", false, "", "",
         "The material of the body's particles", "\"bogus\""},
        {"body", "region", "string", "\"box\"", true,
         "\"box\" | \"disk\" | \"ellipse\" | \"image\"", "",
         "The region the particles fill: a box, a disk (a sphere in 3D), an ellipse or an image's "
         "pixels",
         "\"bogus\""},
        {"body", "min", "array of d numbers", "required with region = \"box\"", false,
         "in the grid, below max", "length", "The lowest corner of a box region",
         "[0.0, 0.0, 0.0, 0.0]"},
        {"body", "max", "array of d numbers", "required with region = \"box\"", false,
         "in the grid, above min on every axis", "length", "The highest corner of a box region",
         "[0.0, 0.0, 0.0, 0.0]"},
        // center, radius, semi_axes, image, pixel_size, origin and levels: read only for a region
        // other than "box" and ignored by a box; the first example's first body is a box, where no
        // value of them is refused (no bad value).
        {"body", "center", "array of d numbers", "required with region = \"disk\" or \"ellipse\"",
         false, "the region in the grid", "length", "The centre of a disk or ellipse region", ""},
        {"body", "radius", "number", "required with region = \"disk\"", false, "> 0", "length",
         "The radius of a disk region (a sphere in 3D)", ""},
        {"body", "semi_axes", "array of d numbers", "required with region = \"ellipse\"", false,
         "> 0 each", "length", "The semi-axes of an ellipse region, along the grid's axes", ""},
        {"body", "image", "string", "required with region = \"image\"", false,
         "a PNG file of at most 2^28 pixels that lies in the grid (2D grids only)", "",
         "The image of an image region, relative to the input file (NairnMPM's BMPRegion)", ""},
        {"body", "pixel_size", "number", "required with region = \"image\"", false, "> 0", "length",
         "The side of the image's square pixels", ""},
        {"body", "origin", "array of 2 numbers", "the grid's origin (region = \"image\")", false,
         "in the grid", "length", "The position of the image's lower-left corner", ""},
        {"body", "levels", "array of 2 numbers", "[0.0, 127.0]", true, "0 ≤ lo ≤ hi ≤ 255", "",
         "[lo, hi], the grey levels of the image's pixels that are the body's (inclusive)", ""},
        {"body", "ppc", "array of d positive integers", "required", false,
         "≥ 1 each; at most 2·10^7 particles (the build's limit)", "",
         "The number of particles per cell along each axis", "[0]"},
        {"body", "velocity", "array of d numbers or expressions of X, Y, Z", "0 on every axis",
         false, "finite; not for a rigid material (it moves with the material's velocity)",
         "length/time",
         "The initial velocity per axis, numbers or expressions of the initial position X, Y, Z",
         "[0.0, 0.0, 0.0, 0.0]"},
        {"body", "temperature", "number or expression of X, Y, Z",
         "the material's reference_temperature; needs step.transport", false,
         "> 0 at every particle", "temperature",
         "The initial absolute temperature of the particles (heat transport, FMPM 2026 §3.5)",
         "-1.0"},
        {"body", "heat_source", "number", "none (0); needs step.transport", false, "", "power/mass",
         "The heat source per unit mass of the body's particles (heat transport)", "\"x\""},
        {"body", "name", "string", "none (loads take the body's index)", false,
         "unique among the bodies", "", "The body's name, by which loads find it", "1"},

        // [[bc]]
        {"bc", "plane", "inline table {axis, at}", "one of plane or box (neither with wall)", false,
         "", "", "The nodes of the condition: those on the grid plane axis = at", "1"},
        {"bc", "box", "inline table {min, max}", "one of plane or box (neither with wall)", false,
         "", "", "The nodes of the condition: those in the box from min to max", "1"},
        {"bc", "fixed", "array of strings", "one of fixed, velocity or temperature (or a wall)",
         false, "\"x\", \"y\", \"z\" (the grid's axes), at least one", "",
         "The axes along which the nodes' velocity is held at zero", "[\"w\"]"},
        {"bc", "velocity", "inline table {direction, value}",
         "one of fixed, velocity or temperature (or a wall)", false, "", "",
         "A prescribed velocity along a direction on the nodes (its reaction is in the series)",
         "1"},
        {"bc", "wall", "inline table {normal, position, velocity, gradient, depth | depth_cells}",
         "none (a wall is given alone)", false, "", "",
         "A moving wall, which selects its nodes and sets their velocity along its normal (FMPM "
         "2026 §3.1)",
         "1"},
        // With fixed = [...] in the first example's first [[bc]], any temperature is refused.
        {"bc", "temperature", "number or expression of t, x, y, z",
         "one of fixed, velocity or temperature; needs step.transport", false, "> 0 (a number)",
         "temperature",
         "A held absolute temperature on the nodes, one condition per node (heat transport)",
         "-1.0"},

        // bc.plane = {axis, at}
        {"bc.plane", "axis", "string", "required", false, "\"x\" | \"y\" | \"z\" (the grid's axes)",
         "", "The axis normal to the plane of nodes", "\"w\""},
        {"bc.plane", "at", "number", "required", false, "the coordinate of a plane of grid nodes",
         "length", "The position of the plane along its axis", "1.0e30"},

        // bc.box = {min, max}
        {"bc.box", "min", "array of d numbers", "required", false, "the box holds a grid node",
         "length", "The lowest corner of the box of nodes", "[0.0, 0.0, 0.0, 0.0]"},
        {"bc.box", "max", "array of d numbers", "required", false, "the box holds a grid node",
         "length", "The highest corner of the box of nodes", "[0.0, 0.0, 0.0, 0.0]"},

        // bc.velocity = {direction, value}
        {"bc.velocity", "direction", "array of d numbers", "required", false, "not all zero", "",
         "The direction along which the velocity is set (normalised)", "[0.0]"},
        {"bc.velocity", "value", "number or expression of t, x, y, z", "required", false, "finite",
         "length/time", "The velocity along the direction", "true"},

        // bc.wall = {normal, position, velocity, gradient, depth | depth_cells}
        {"bc.wall", "normal", "array of d numbers", "required", false, "not all zero", "",
         "n̂, the wall's normal, pointing out of the object (normalised)", "[0.0, 0.0]"},
        {"bc.wall", "position", "number or expression of t", "required", false, "finite", "length",
         "s_w(t) = x_wall · n̂, the wall's position along its normal", "true"},
        {"bc.wall", "velocity", "number or expression of t", "0.0", true, "finite", "length/time",
         "v(t), the velocity the wall sets along its normal", "true"},
        {"bc.wall", "gradient", "number or expression of t", "0.0", true, "finite", "1/time",
         "∇v(t): the wall sets v(t) + ∇v(t) (s_i − s_w(t)) on node i", "true"},
        {"bc.wall", "depth", "number", "0.0, or depth_cells cells (not both)", false, "≥ 0",
         "length",
         "d, the depth inside the wall within which the nodes with mass are constrained too",
         ""}, // every example's wall gives depth_cells, with which any depth is refused
        {"bc.wall", "depth_cells", "number", "none (depth)", false, "≥ 0", "",
         "The depth d in multiples of the smallest cell size, instead of depth", "true"},

        // [[contact]]
        {"contact", "materials", "array of 2 [[material]] names",
         "none: the law of every pair without a table of its own", false, "two different materials",
         "", "The two materials whose velocity fields the law is between", "[\"x\"]"},
        {"contact", "law", "string", "required", false,
         "\"stick\" | \"frictionless\" | \"coulomb\" | \"single-field\"", "",
         "The tangential law (FMPM 2026 Eq. 18); single-field: one shared velocity field, a "
         "perfect "
         "interface",
         "\"bogus\""},
        // friction, direction, critical_separation, df_exponent, df_reach: refused whatever their
        // value unless law, normal or detection selects them (the bad values are refused when it
        // does, too).
        {"contact", "friction", "number", "required with law = \"coulomb\" (its only law)", false,
         "≥ 0", "", "μ, the Coulomb friction coefficient", "-1.0"},
        {"contact", "normal", "string", "\"LR\"", true, "\"LR\" | \"AG\" | \"specified\"", "",
         "The contact normal n̂: logistic regression, average gradient (contact 2020 Eq. 13) or "
         "specified",
         "\"bogus\""},
        {"contact", "direction", "array of d numbers",
         "required with normal = \"specified\" (its only normal)", false, "not all zero", "",
         "The specified normal, from the first material to the second (normalised)", "[0.0, 0.0]"},
        {"contact", "detection", "string", "\"LR\"", true,
         "\"LR\" | \"approaching\" | \"CP\" | \"DF\" | \"always\"", "",
         "When approaching fields are in contact: LR separation, approaching alone, critical "
         "position, distance function, always (bonded)",
         "\"bogus\""},
        {"contact", "critical_separation", "number", "0.8 with detection = \"CP\" (its only one)",
         false, "[0, 4]", "",
         "δ_c of the critical-position detection, in cells along n̂ (contact 2020 Eq. 16)", "-1.0"},
        {"contact", "df_exponent", "number",
         "0.5757166424934449 (ln 2 / ln(10/3)) with detection = \"DF\" (its only one)", false,
         "(0, 10]", "",
         "r, the exponent of the distance function's fit of the edge (contact 2020 Eq. 15)", "0.0"},
        {"contact", "df_reach", "number", "1.25 with detection = \"DF\" (its only one)", false,
         "(0, 10]", "",
         "L, the reach of the distance function's fit, in cells along n̂ (contact 2020 Eq. 15)",
         "0.0"},
        {"contact", "fmpm_method", "string", "\"net\"", true, "\"net\" | \"evolving\"", "",
         "The contact correction of the increments of FMPM(k): the Net or Evolving method (FMPM "
         "2026 §3.2)",
         "\"bogus\""},

    };
    const std::vector<InputKey> run = detail::run_input_keys();
    model.insert(model.end(), run.begin(), run.end());
    return model;
  }();
  return keys;
}

} // namespace smpm
