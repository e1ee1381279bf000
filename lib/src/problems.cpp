// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/problems.hpp"

#include "sparsempm/errors.hpp"

#include <cmath>
#include <numbers>

namespace smpm {

Model vibrating_bar(const BarSetup& s) {
  const int bar_cells = int(std::lround(s.length / s.cell));
  if (bar_cells < 1 || std::abs(bar_cells * s.cell - s.length) > 1e-9 * s.length)
    throw InputError("bar length must be a whole number of cells");
  Model model(Grid(1, {-s.cells_left * s.cell, 0, 0}, {s.cell, 1, 1},
                   {bar_cells + s.cells_left + s.cells_right, 1, 1}));
  Material mat;
  mat.name = "bar";
  mat.model = MaterialModel::Linear;
  mat.density = s.density;
  mat.youngs = s.youngs;
  validate(mat);
  model.materials = {mat};
  model.particles =
      make_block(model.grid, {0, 0, 0}, {s.length, 0, 0}, {s.ppc, 1, 1}, s.density, 0);
  const double beta = std::numbers::pi / (2 * s.length);
  model.particles.V.col(0) = s.v0 * (beta * model.particles.X.col(0).array()).sin();
  fix_plane(model.grid, 0, 0.0, {true, false, false}, model.bcs);
  return model;
}

double bar_period(const BarSetup& s) {
  return 4 * s.length / std::sqrt(s.youngs / s.density);
}

} // namespace smpm
