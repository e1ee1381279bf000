// SPDX-License-Identifier: BSD-3-Clause
// What a frame of a run file holds (output.hpp): the particle fields, the grid fields of the
// frame's step preparation, the matrices when asked, the series rows and the restart state.

#include "output_format.hpp"

#include "sparsempm/material.hpp"
#include "sparsempm/particle_columns.hpp"
#include "sparsempm/stages.hpp"

#include <Eigen/LU> // Matrix3d::determinant

#include <cmath>
#include <string>
#include <vector>

namespace smpm::detail {

void write_csr(hid_t parent, const std::string& name, const SparseRowMatrix& A) {
  h5::Id g = h5::create_group(parent, name);
  h5::write_doubles(g.get(), "data", A.valuePtr(), hsize_t(A.nonZeros()), 0);
  h5::write_ints(g.get(), "indices", A.innerIndexPtr(), hsize_t(A.nonZeros()));
  h5::write_ints(g.get(), "indptr", A.outerIndexPtr(), hsize_t(A.rows() + 1));
  const int shape[2] = {int(A.rows()), int(A.cols())};
  h5::write_ints(g.get(), "shape", shape, 2);
}

void write_xyz(hid_t g, const std::string& name, const Field& X) {
  Field xyz = Field::Zero(X.rows(), 3);
  xyz.leftCols(X.cols()) = X;
  h5::write_doubles(g, name, xyz.data(), hsize_t(X.rows()), 3);
}

void write_vertices(hid_t file, Index n) {
  if (n == 0)
    return;
  if (!h5::exists(file, "vertices"))
    h5::create_group(file, "vertices");
  h5::Id g = h5::open_group(file, "vertices");
  const std::string name = std::to_string(n);
  if (h5::exists(g.get(), name))
    return;
  std::vector<int> ids(static_cast<size_t>(n));
  for (size_t k = 0; k < ids.size(); ++k)
    ids[k] = int(k);
  h5::write_ints(g.get(), name, ids.data(), hsize_t(n), 1);
}

// /particles/<name>: the particle fields of a frame.
void write_particles(hid_t file, const std::string& name, const Model& model) {
  const Particles& P = model.particles;
  h5::Id parts = h5::open_group(file, "particles");
  h5::Id g = h5::create_group(parts.get(), name);
  const hsize_t N = hsize_t(P.size()), d = hsize_t(P.dim);
  h5::write_doubles(g.get(), "X", P.X.data(), N, d);
  h5::write_doubles(g.get(), "V", P.V.data(), N, d);
  h5::write_doubles(g.get(), "stress", P.stress.data(), N, d * d);
  h5::write_doubles(g.get(), "F", P.F.data(), N, d * d);
  h5::write_doubles(g.get(), "mass", P.mass.data(), N, 0);
  const Eigen::VectorXd vol = P.volume();
  h5::write_doubles(g.get(), "volume", vol.data(), N, 0);
  h5::write_doubles(g.get(), "volume0", P.volume0.data(), N, 0);
  h5::write_doubles(g.get(), "half_length", P.half_length.data(), N, d);
  h5::write_ints(g.get(), "material", P.material.data(), N);
  for (const ParticleColumn& c : particle_columns()) // the columns the parts of the step carry
    if (c.in_frames && has_column(P, c)) {
      const Eigen::Map<const Field> v = column_values(P, c);
      h5::write_doubles(g.get(), std::string(c.name), v.data(), N,
                        c.width == ColumnWidth::One ? 0 : hsize_t(v.cols()));
    }
  Eigen::VectorXd J(P.size()); // det F, the volume ratio V/V₀
  for (Index k = 0; k < P.size(); ++k)
    J[k] = embed_3d(P.F.row(k).data(), P.dim).determinant();
  h5::write_doubles(g.get(), "J", J.data(), N, 0);
  if (P.dim == 1) // ParaView and meshio need at least two coordinates
    write_xyz(g.get(), "xyz", P.X);
  write_vertices(file, P.size());
  h5::set_attribute(g.get(), "time", model.time);
  h5::set_attribute(g.get(), "step", model.step);
}

namespace {
// The preparation a frame's grid fields come from: the step's (`prepared`), or the frame's own in
// `own` when there is none or when the matrices need the whole grid's numbering.
const StepPreparation& frame_preparation(const Model& model, Shape shape, bool matrices, bool heat,
                                         const StepPreparation* prepared, StepPreparation& own) {
  if (prepared && !(matrices && prepared->ops.node_range != NodeRange::Grid))
    return *prepared;
  // On the particles' window of the grid (storage and time follow the particles), or on the
  // whole grid when the matrices are written (their columns are the grid's nodes).
  own.ops.node_range = matrices ? NodeRange::Grid : NodeRange::Particles;
  prepare_step(model, shape, own);
  if (heat)
    prepare_heat_transport(model, own, TransportUpdate::Lumped);
  return own;
}

// The nodal fields of the nodes with mass only (active_nodes), with their indices in the grid
// (node α n_g + i of field α) and velocity fields: one row per node with mass.
struct ActiveNodeFields {
  Eigen::VectorXi nodes, field;
  Eigen::VectorXd m;
  Field p, v, x;
};

ActiveNodeFields active_node_fields(const Operators& ops, const Field& p, const Field& v, int dim) {
  ActiveNodeFields a;
  a.nodes = active_nodes(ops);
  const Index na = a.nodes.size(), ng = ops.grid_node_count;
  a.m.resize(na);
  a.field.resize(na);
  a.p.resize(na, dim);
  a.v.resize(na, dim);
  a.x.resize(na, dim);
  for (Index k = 0; k < na; ++k) {
    a.m[k] = ops.m[a.nodes[k]];
    a.p.row(k) = p.row(a.nodes[k]);
    a.v.row(k) = v.row(a.nodes[k]);
    a.x.row(k) = ops.grid.node_position(a.nodes[k] % ng).head(dim).transpose();
    a.field[k] = int(a.nodes[k] / ng);
    a.nodes[k] = int(ops.whole_node(a.nodes[k]));
  }
  return a;
}

// /grid/<name>: m, p = SᵀMV and v = m⁻¹p of the nodes with mass (a frame of a few particles on
// a large grid stays small), and with several velocity fields the contact nodes.
void write_nodal_fields(hid_t file, const std::string& name, const Model& model,
                        const StepPreparation& prepared) {
  const Particles& P = model.particles;
  const Operators& ops = prepared.ops;
  // Multimaterial: each velocity field's nodal fields (node i of field α is α n_g + i), the
  // extrapolation of contact 2020 Eq. (5) before contact.
  const int fields = ops.fields;
  Field p, v;
  map_momentum(particle_operators(ops), P.V, p);
  lumped_solve(ops.m_inv, p, v);
  const ActiveNodeFields a = active_node_fields(ops, p, v, P.dim);
  h5::Id grid = h5::open_group(file, "grid");
  h5::Id g = h5::create_group(grid.get(), name);
  const hsize_t n = hsize_t(a.nodes.size()), d = hsize_t(P.dim);
  h5::write_ints(g.get(), "nodes", a.nodes.data(), n);
  h5::write_doubles(g.get(), "m", a.m.data(), n, 0);
  h5::write_doubles(g.get(), "p", a.p.data(), n, d);
  h5::write_doubles(g.get(), "v", a.v.data(), n, d);
  h5::write_doubles(g.get(), "X", a.x.data(), n, d); // the nodes' positions
  if (P.dim == 1)
    write_xyz(g.get(), "xyz", a.x);
  if (fields > 1)
    h5::write_ints(g.get(), "field", a.field.data(), n); // the velocity field of each row
  write_vertices(file, a.nodes.size());
  h5::set_attribute(g.get(), "grid_nodes", long(model.grid.num_nodes()));
  h5::set_attribute(g.get(), "velocity_fields", long(fields));
  if (fields > 1) {
    detail::write_contact_nodes(g.get(), prepared, p);
    write_vertices(file, Index(prepared.contact.nodes.size()));
  }
}

// /matrices/<name>: S, G_a and m̃ in CSR, and with heat transport the n_g × n_g capacity and
// conductivity of transport.hpp.
void write_matrices(hid_t file, const std::string& name, int dim, const StepPreparation& prepared,
                    bool heat) {
  const Operators& ops = prepared.ops;
  if (!h5::exists(file, "matrices"))
    h5::create_group(file, "matrices");
  h5::Id mats = h5::open_group(file, "matrices");
  h5::Id g = h5::create_group(mats.get(), name);
  write_csr(g.get(), "S", ops.S);
  for (int a = 0; a < dim; ++a)
    write_csr(g.get(), "G" + std::to_string(a), ops.G[size_t(a)]);
  write_csr(g.get(), "consistent_mass", SparseRowMatrix(consistent_mass(ops)));
  if (heat) { // n_g × n_g: the capacity and conductivity of transport.hpp
    write_csr(g.get(), "consistent_capacity",
              SparseRowMatrix(consistent_capacity(ops, prepared.transport)));
    write_csr(g.get(), "conductivity",
              SparseRowMatrix(conductivity_matrix(ops, prepared.transport)));
  }
}
} // namespace

// /grid/<name> (m, p = SᵀMV, v = m⁻¹p) and, when asked, /matrices/<name> (S, G_a, m̃ in CSR),
// from the preparation of the step that starts at the frame (`prepared`, the Stepper's), or from
// the frame's own when there is none or when the matrices need the whole grid's numbering.
void write_grid(hid_t file, const std::string& name, const Model& model, Shape shape, bool matrices,
                const StepPreparation* prepared) {
  // Heat transport: its matrices c~ and K beside m~ (the preparation of the run's step has the
  // transport operators; the tolerance of the exact solve does not change the matrices).
  const bool heat = prepared && prepared->has_transport();
  StepPreparation own;
  const StepPreparation& prep = frame_preparation(model, shape, matrices, heat, prepared, own);
  write_nodal_fields(file, name, model, prep);
  if (matrices)
    write_matrices(file, name, model.particles.dim, prep, heat);
}

double frame_bytes(const Model& model, const StepPreparation* prepared, bool matrices,
                   size_t series_rows, size_t columns) {
  const double N = double(model.particles.size()), d = model.grid.dim();
  const double fields = model.contact.fields();
  // The particle fields: X, V, half-lengths (d each), σ, F (d² each), five scalars, the ids,
  // and in 1D the three coordinates of ParaView; the sidecar's vertex list of N.
  double bytes = 8 * N * (3 * d + 2 * d * d + 5 + (d == 1 ? 3 : 0)) + 8 * N;
  // The grid fields of the nodes with mass and the contact nodes (of the step's preparation when
  // given, else every node of every field).
  const double nodes =
      prepared ? double(prepared->ops.active.count()) : double(model.grid.num_nodes()) * fields;
  const double contact = prepared ? double(prepared->contact.nodes.size()) : nodes;
  // Their positions (and three coordinates in 1D), field numbers and vertex lists.
  bytes += 8 * nodes * (2 + 3 * d + (d == 1 ? 3 : 0)) + 8 * nodes +
           (fields > 1 ? 8 * contact * (5 + 2 * d + (d == 1 ? 3 : 0)) : 0.0);
  if (matrices) { // S and G_a (values, indices) and m̃, on the whole grid
    const double nnz = prepared ? double(prepared->ops.S.nonZeros()) : N * std::pow(4, d);
    bytes += 12 * nnz * (1 + d) + 12 * nnz * std::pow(3, d) + 8 * N * (2 + d) +
             8 * double(model.grid.num_nodes()) * fields;
  }
  // Heat transport: the temperatures, and with the matrices c̃ and K (n_g rows, a stencil each).
  const bool heat = model.particles.temperature.size() == model.particles.size();
  if (heat)
    bytes += 8 * N;
  if (model.particles.gradient.rows() == model.particles.size()) // the velocity gradients L_p
    bytes += 8 * N * d * d;
  if (heat && matrices)
    bytes += 2 * (12 * std::pow(5, d) + 4) * double(model.grid.num_nodes());
  // The series rows since the frame before.
  bytes += 8 * double(series_rows) * double(columns);
  // HDF5's metadata (under 1 kB an object, ~60 objects with the series) and the sidecar's frame.
  return bytes + 64 * 1024 + 8 * 1024;
}

// /state/<name>: what a restart continues (RunState).
void write_run_state(hid_t file, const std::string& name, const RunState& state) {
  h5::Id states = h5::open_group(file, "state");
  h5::Id g = h5::create_group(states.get(), name);
  h5::set_attribute(g.get(), "courant_budget", state.stepper.courant_budget);
  h5::set_attribute(g.get(), "friction_work", state.stepper.friction_work);
  h5::set_attribute(g.get(), "viscous_work", state.stepper.viscous_work);
  h5::set_attribute(g.get(), "plastic_work", state.stepper.plastic_work);
  h5::set_attribute(g.get(), "velocity_change_sum", state.velocity_change_sum);
}

} // namespace smpm::detail
