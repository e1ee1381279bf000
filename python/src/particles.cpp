// SPDX-License-Identifier: BSD-3-Clause
// sparsempm.Grid and Particles: numpy views of the library's grid and particle arrays, the
// columns of the parts of the step (particle_columns) among them by one rule.

#include "bindings.hpp"
#include "convert.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/particle_columns.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <string>

namespace smpm::python {

using DoubleArray = py::array_t<double, py::array::forcecast>;

// Column `col` of the particles (particle_columns) from a number or the particles' values (N,
// or N × width), each in the column's range (positive temperatures, non-negative plastic
// strains, finite values), as the input reader holds [[body]] temperature and heat_source. The
// particles' storage is kept when it has the column already (numpy views stay valid).
void set_part_column(Particles& P, const ParticleColumn& col, const DoubleArray& a) {
  const std::string name(col.name);
  Field v(P.size(), column_width(col, P.dim));
  if (col.vector) // a number or shape (N,)
    v.col(0) = particle_vector(a, P.size(), name.c_str());
  else if (a.ndim() == 0)
    v.setConstant(*a.data());
  else
    assign_field(v, a, name.c_str());
  for (Index k = 0; k < v.size(); ++k) {
    const double x = v.data()[k];
    const bool ok = std::isfinite(x) && (col.range == ColumnRange::Positive      ? x > 0
                                         : col.range == ColumnRange::NonNegative ? x >= 0
                                                                                 : true);
    if (!ok)
      throw InputError(name + ": particle " + std::to_string(k / v.cols()) + " has " +
                       number_text(x) + range_message(col));
  }
  if (has_column(P, col))
    column_values(P, col) = v; // copied into the same storage: numpy views of it stay valid
  else
    set_column(P, col, v); // was empty: no view holds any of it
}

void bind_grid(py::module_& m) {
  py::class_<Grid>(m, "Grid", "A structured grid in 1, 2 or 3 dimensions (grid.hpp).")
      .def(py::init([](const std::vector<int>& cells, const std::vector<double>& cell_size,
                       const std::vector<double>& origin) {
             if (cells.empty() || cells.size() > 3)
               throw InputError("cells: give 1 to 3 cell counts (one per axis)");
             const auto h =
                 triple(cell_size.empty() ? std::vector<double>(cells.size(), 1.0) : cell_size, 1.0,
                        "cell_size");
             std::array<int, 3> n{1, 1, 1};
             std::copy(cells.begin(), cells.end(), n.begin());
             return Grid(int(cells.size()), triple(origin, 0.0, "origin"), h, n);
           }),
           py::arg("cells"), py::arg("cell_size") = std::vector<double>{},
           py::arg("origin") = std::vector<double>{},
           "Grid(cells, cell_size=[1, ...], origin=[0, ...]); the dimension is len(cells).")
      .def_property_readonly("dim", &Grid::dim, "dimension d (1, 2 or 3)")
      .def_property_readonly("num_nodes", &Grid::num_nodes, "number of grid nodes")
      .def_property_readonly(
          "cells",
          [](const Grid& g) {
            std::vector<int> c;
            for (int a = 0; a < g.dim(); ++a)
              c.push_back(g.cells(a));
            return c;
          },
          "cells along each axis")
      .def_property_readonly(
          "cell_size",
          [](const Grid& g) {
            std::vector<double> h;
            for (int a = 0; a < g.dim(); ++a)
              h.push_back(g.cell_size(a));
            return h;
          },
          "cell size along each axis")
      .def_property_readonly(
          "origin",
          [](const Grid& g) {
            std::vector<double> o;
            for (int a = 0; a < g.dim(); ++a)
              o.push_back(g.origin(a));
            return o;
          },
          "position of node (0, 0, 0)")
      .def(
          "node_positions", [](const Grid& g) { return from_field(g.node_positions(), false); },
          "n × d node positions, one row per node (node i + nx (j + ny k)).");
}

namespace {

// A field property of Particles: a numpy view of the C++ storage (read and write in place);
// assigning an array copies into it (same shape).
template <class Member>
void field_property(py::class_<Particles>& c, const char* name, Member member, const char* doc) {
  c.def_property(
      name, [member](py::object self) { return field_view(self.cast<Particles&>().*member, self); },
      [member, name](Particles& P, const DoubleArray& a) { assign_field(P.*member, a, name); },
      doc);
}

// A column a part of the step adds to the particles (particle_columns): a numpy view of the C++
// storage, empty when absent; assigning a number or the particles' values (N, or N × width)
// sets it (set_part_column).
void column_property(py::class_<Particles>& c, const ParticleColumn& col) {
  const std::string doc = // pybind11 copies it
      std::string(col.shape) + " " + std::string(col.meaning) +
      (col.always ? "; zeros where no part sets them" : "; empty: none") +
      (col.needs.empty() ? "" : " (" + std::string(col.needs) + " brings it)") +
      ". Assign a number or the particles' values to set them";
  c.def_property(
      std::string(col.name).c_str(),
      [col](py::object self) {
        Particles& P = self.cast<Particles&>();
        if (col.vector)
          return vector_view(P.*col.vector, self);
        if (col.field)
          return field_view(P.*col.field, self);
        // A program's part (Particles::columns): a view of its storage, (N,) when it has one
        // value per particle as the library's vector columns; empty when absent.
        const auto it = P.columns.find(col.name);
        if (it == P.columns.end())
          return py::array(py::array_t<double>(0));
        Field& f = it->second;
        if (col.width != ColumnWidth::One)
          return field_view(f, self);
        return py::array(
            py::array_t<double>({f.rows()}, {py::ssize_t(sizeof(double))}, f.data(), self));
      },
      [col](Particles& P, const DoubleArray& a) { set_part_column(P, col, a); }, doc.c_str());
}

} // namespace

void bind_particles(py::module_& m) {
  py::class_<Particles> c(m, "Particles",
                          "Material points as numpy views of the library's arrays (one row per "
                          "particle; tensors row-major, d² columns).");
  field_property(c, "X", &Particles::X, "N × d positions");
  field_property(c, "V", &Particles::V, "N × d velocities");
  field_property(c, "F", &Particles::F, "N × d² deformation gradients");
  field_property(c, "stress", &Particles::stress, "N × d² Cauchy stresses");
  field_property(c, "half_length", &Particles::half_length, "N × d initial half-lengths r⁰");
  c.def_property(
      "mass", [](py::object self) { return vector_view(self.cast<Particles&>().mass, self); },
      [](Particles& P, const DoubleArray& a) { assign_vector(P.mass, a, "mass"); }, "N masses");
  c.def_property(
      "volume0", [](py::object self) { return vector_view(self.cast<Particles&>().volume0, self); },
      [](Particles& P, const DoubleArray& a) { assign_vector(P.volume0, a, "volume0"); },
      "N initial volumes");
  for (const ParticleColumn& col : particle_columns()) // the parts' columns, one rule
    column_property(c, col);
  c.def_property_readonly(
      "material",
      [](py::object self) { return vector_view(self.cast<Particles&>().material, self); },
      "N material ids");
  c.def_readonly("dim", &Particles::dim, "dimension d of the positions");
  c.def("__len__", &Particles::size);
  // Copies as numpy arrays (the module does not convert Eigen types itself).
  c.def(
      "volume",
      [](const Particles& P) {
        const Eigen::VectorXd v = P.volume();
        return py::array_t<double>(v.size(), v.data());
      },
      "Current volumes det(F) V⁰, N.");
  c.def(
      "jacobian",
      [](const Particles& P) {
        const Eigen::VectorXd J = P.jacobian();
        return py::array_t<double>(J.size(), J.data());
      },
      "det F per particle, N.");
}

} // namespace smpm::python
