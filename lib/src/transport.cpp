// SPDX-License-Identifier: BSD-3-Clause
// Heat transport on the grid (transport.hpp): the capacities, the kernels of the transport step
// and the matrices c̃ and K for analysis. Every kernel is one pass over the CSR arrays of the
// step's S and G with the block columns of multimaterial mode folded onto the grid nodes.

#include "sparsempm/transport.hpp"

#include "enum_names.hpp"
#include "kernels.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace smpm {

namespace {
constexpr detail::EnumNames<TransportUpdate, 4> kTransportUpdates{
    {{TransportUpdate::Off, "off"},
     {TransportUpdate::Lumped, "lumped"},
     {TransportUpdate::FMPM, "FMPM"},
     {TransportUpdate::Exact, "exact"}}};
} // namespace

std::string_view to_string(TransportUpdate u) {
  return detail::enum_name(u, kTransportUpdates);
}
TransportUpdate transport_update_from_string(std::string_view name) {
  return detail::parse_enum(name, kTransportUpdates, "transport update");
}

namespace {
constexpr detail::EnumNames<TransportLimiter, 2> kTransportLimiters{
    {{TransportLimiter::None, "none"}, {TransportLimiter::FCT, "fct"}}};
} // namespace

std::string held_temperature_refusal(Shape shape) {
  if (shape != Shape::BSpline2 && shape != Shape::B2CPDI)
    return {};
  return "a held temperature needs shape functions whose nodal values interpolate: with "
         "step.shape = \"" +
         std::string(to_string(shape)) +
         "\" a held node is a quadratic B-spline's control point, not the temperature at its "
         "plane, and the error next to it does not converge (lumped) or converges at first order "
         "(FMPM, exact); use step.shape = \"linear\", \"gimp\" or \"cpdi\"";
}

std::string_view to_string(TransportLimiter l) {
  return detail::enum_name(l, kTransportLimiters);
}
TransportLimiter transport_limiter_from_string(std::string_view name) {
  return detail::parse_enum(name, kTransportLimiters, "transport limiter");
}

namespace {

// out_i = the terms add(p, k, out_i) adds for every entry of grid node i folded over the fields,
// the fields in order and each field's particles in ascending order, from out_i = 0: the same
// order for any number of threads. Several fields: a gather over the column lists of S; one
// field: its rows scattered by node ranges in particle order (kernels.hpp), the same order.
template <class Add>
void folded_sums(const Operators& ops, double* out, Add&& add) {
  const Index ng = ops.grid_node_count;
  const ColumnIndex& cols = ops.columns;
  if (!cols.lists) {
    SMPM_VERIFY(ops.fields == 1, "transport: the column lists of S are built for several fields");
    const int* inner = ops.S.innerIndexPtr();
    detail::scatter_to_nodes(
        ops.S.outerIndexPtr(), inner, cols.span.data(), ops.num_particles(), ng, cols.outer.data(),
        [&](Index r0, Index r1) { std::fill(out + r0, out + r1, 0.0); },
        [&](Index p, int k0, int k1) {
          for (int k = k0; k < k1; ++k)
            add(p, k, out[inner[k]]);
        });
    return;
  }
  detail::parallel_for(ng, [&](Index i) {
    double sum = 0;
    for (int f = 0; f < ops.fields; ++f) {
      const Index c = f * ng + i;
      for (int t = cols.outer[size_t(c)]; t < cols.outer[size_t(c + 1)]; ++t)
        add(Index(cols.row[size_t(t)]), cols.entry[size_t(t)], sum);
    }
    out[i] = sum;
  });
}

// The first column of particle p's field block (0 with one field): its entries minus this are
// grid nodes.
inline Index block_offset(const Operators& ops, Index p) {
  if (ops.fields == 1)
    return 0;
  const int k = ops.S.outerIndexPtr()[p];
  return ops.S.outerIndexPtr()[p + 1] > k
             ? (ops.S.innerIndexPtr()[k] / ops.grid_node_count) * ops.grid_node_count
             : 0;
}

[[noreturn]] void bad_temperature(Index p, double T) {
  std::ostringstream os;
  os << "particle " << p << " has temperature " << T
     << " (temperatures are absolute: positive and finite)";
  throw NumericalError(os.str());
}

void check_node_vector(const Operators& ops, const Field& x, const char* who) {
  SMPM_VERIFY(x.rows() == ops.grid_node_count && x.cols() == 1,
              std::string(who) + ": the nodal temperatures must be n_g x 1");
}

} // namespace

void prepare_transport(const Operators& ops, const Particles& P,
                       const std::vector<Material>& materials, TransportOperators& t,
                       double tolerance) {
  const Index N = ops.num_particles(), ng = ops.grid_node_count;
  SMPM_VERIFY(P.size() == N, "prepare_transport: the operators are not those of these particles");
  for (const Material& m : materials)
    if (!(m.heat_capacity > 0) || !std::isfinite(m.heat_capacity))
      throw InputError("material '" + m.name +
                       "': heat transport needs heat_capacity > 0 (C_V, per unit mass), got " +
                       number_text(m.heat_capacity));
  t.capacity.resize(N);
  t.conductance.resize(N);
  const bool sources = P.heat_source.size() == N;
  t.source.resize(sources ? N : 0);
  detail::parallel_for(N, [&](Index p) {
    const int id = P.material[p];
    if (id < 0 || id >= int(materials.size()))
      throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                       ", but there are " + std::to_string(materials.size()) + " materials");
    const Material& m = materials[size_t(id)];
    t.capacity[p] = P.mass[p] * m.heat_capacity;
    t.conductance[p] = P.det_F(p) * P.volume0[p] * m.conductivity;
    if (sources)
      t.source[p] = P.mass[p] * P.heat_source[p];
  });
  // The transport nodes: the lumped capacity in the place of the lumped mass.
  Operators& nodes = t.nodes;
  nodes.node_range = ops.node_range;
  nodes.grid = ops.grid;
  nodes.dim = ops.dim;
  nodes.fields = 1;
  nodes.grid_node_count = ng;
  nodes.grid_nodes = ops.grid_nodes;
  if (nodes.S.rows() != 0 || nodes.S.cols() != ng)
    nodes.S.resize(0, ng);
  nodes.m.resize(ng);
  const double* sv = ops.S.valuePtr();
  folded_sums(ops, nodes.m.data(), [&](Index p, int k, double& sum) { // c_i = Σ_p S_pi M_p C_V,p
    sum += sv[k] * t.capacity[p];
  });
  const double largest = ng ? nodes.m.maxCoeff() : 0.0;
  nodes.active = nodes.m.array() > tolerance * largest;
  nodes.m_inv = nodes.active.select(nodes.m.array().inverse(), 0.0).matrix();
}

void set_reference_temperatures(Particles& P, const std::vector<Material>& materials) {
  for (const Material& m : materials)
    if (!(m.reference_temperature > 0) || !std::isfinite(m.reference_temperature))
      throw InputError("material '" + m.name +
                       "': heat transport needs reference_temperature > 0 (absolute), got " +
                       number_text(m.reference_temperature));
  P.temperature.resize(P.size());
  for (Index p = 0; p < P.size(); ++p) {
    const int id = P.material[p];
    SMPM_VERIFY(id >= 0 && id < int(materials.size()),
                "set_reference_temperatures: particle " + std::to_string(p) + " has no material");
    P.temperature[p] = materials[size_t(id)].reference_temperature;
  }
}

void map_heat(const Operators& ops, const TransportOperators& t, const ConstVectorRef& T,
              Field& tau) {
  SMPM_VERIFY(T.size() == ops.num_particles() && t.capacity.size() == T.size(),
              "map_heat: one temperature and one capacity per particle");
  const Index ng = ops.grid_node_count;
  tau.resize(ng, 1);
  const double* sv = ops.S.valuePtr();
  folded_sums(ops, tau.data(), [&](Index p, int k, double& sum) { // τ_i = Σ_p S_pi M_p C_V,p T_p
    sum += sv[k] * (t.capacity[p] * T[p]);
  });
}

void temperature_gradient(const Operators& ops, const Field& T, Field& gradient) {
  check_node_vector(ops, T, "temperature_gradient");
  const Index N = ops.num_particles();
  const int d = ops.dim;
  gradient.resize(N, d);
  const int* outer = ops.S.outerIndexPtr();
  const int* inner = ops.S.innerIndexPtr();
  detail::parallel_for(N, [&](Index p) { // ∇T_p = Σ_i G_pi T_i
    const Index off = block_offset(ops, p);
    double g[3] = {0, 0, 0};
    for (int k = outer[p]; k < outer[p + 1]; ++k) {
      const double Ti = T(inner[k] - off, 0);
      for (int b = 0; b < d; ++b)
        g[b] += ops.G[size_t(b)].valuePtr()[k] * Ti;
    }
    for (int b = 0; b < d; ++b)
      gradient(p, b) = g[b];
  });
}

void heat_flow(const Operators& ops, const TransportOperators& t, const Field& gradient, Field& q) {
  const Index N = ops.num_particles(), ng = ops.grid_node_count;
  const int d = ops.dim;
  SMPM_VERIFY(gradient.rows() == N && gradient.cols() == d && t.conductance.size() == N,
              "heat_flow: one gradient (1 x d) and one conductance per particle");
  const bool sources = t.source.size() == N;
  q.resize(ng, 1);
  const double* sv = ops.S.valuePtr();
  // q_i = −Σ_p V_p κ_p G_pi · ∇T_p + Σ_p S_pi M_p r_p
  folded_sums(ops, q.data(), [&](Index p, int k, double& sum) {
    double flux = 0;
    for (int b = 0; b < d; ++b)
      flux += ops.G[size_t(b)].valuePtr()[k] * gradient(p, b);
    sum -= t.conductance[p] * flux;
    if (sources)
      sum += sv[k] * t.source[p];
  });
}

namespace {
// T_p ← T_p + Δt Σ_i S_pi x_i (FLIP) or T_p ← Σ_i S_pi x_i (grid), then the positivity check.
template <bool Flip>
void update_temperature(const Operators& ops, const Field& x, double dt,
                        Eigen::Ref<Eigen::VectorXd> T, bool absolute) {
  SMPM_VERIFY(T.size() == ops.num_particles(), "update_temperature: one temperature per particle");
  const int* outer = ops.S.outerIndexPtr();
  const int* inner = ops.S.innerIndexPtr();
  const double* sv = ops.S.valuePtr();
  detail::parallel_for(ops.num_particles(), [&](Index p) {
    const Index off = block_offset(ops, p);
    double sum = 0;
    for (int k = outer[p]; k < outer[p + 1]; ++k)
      sum += sv[k] * x(inner[k] - off, 0);
    const double value = Flip ? T[p] + dt * sum : sum;
    if (!std::isfinite(value) || (absolute && !(value > 0)))
      bad_temperature(p, value);
    T[p] = value;
  });
}
} // namespace

void update_temperature_flip(const Operators& ops, const Field& rate, double dt,
                             Eigen::Ref<Eigen::VectorXd> T, bool absolute) {
  check_node_vector(ops, rate, "update_temperature_flip");
  update_temperature<true>(ops, rate, dt, T, absolute);
}

void update_temperature_grid(const Operators& ops, const Field& theta,
                             Eigen::Ref<Eigen::VectorXd> T, bool absolute) {
  check_node_vector(ops, theta, "update_temperature_grid");
  update_temperature<false>(ops, theta, 0.0, T, absolute);
}

SparseMatrix folded_columns(const Operators& ops, const SparseRowMatrix& A) {
  SMPM_VERIFY(A.rows() == ops.num_particles() && A.cols() == ops.num_nodes(),
              "folded_columns: an N x n matrix of the step is needed");
  const Index ng = ops.grid_node_count;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(size_t(A.nonZeros()));
  for (Index p = 0; p < A.rows(); ++p)
    for (SparseRowMatrix::InnerIterator it(A, p); it; ++it)
      entries.emplace_back(int(p), int(it.col() % ng), it.value());
  SparseMatrix out(A.rows(), ng);
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

SparseMatrix consistent_capacity(const Operators& ops, const TransportOperators& t) {
  ConsistentMass ct;
  assemble_consistent_capacity(ops, t.capacity, ct);
  SparseMatrix out(ct.matrix);
  out.prune(0.0);
  return out;
}

SparseMatrix conductivity_matrix(const Operators& ops, const TransportOperators& t) {
  SparseMatrix K(ops.grid_node_count, ops.grid_node_count);
  for (int b = 0; b < ops.dim; ++b) {
    const SparseMatrix G = folded_columns(ops, ops.G[size_t(b)]);
    K += SparseMatrix(G.transpose() * t.conductance.asDiagonal() * G);
  }
  K.prune(0.0);
  return K;
}

double diffusion_time(const Grid& grid, const std::vector<Material>& materials,
                      const Particles& particles) {
  std::vector<char> used(materials.size(), 0);
  for (Index p = 0; p < particles.size(); ++p) {
    const int id = particles.material[p];
    if (id < 0 || id >= int(materials.size()))
      throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                       ", but there are " + std::to_string(materials.size()) + " materials");
    used[size_t(id)] = 1;
  }
  double D = 0;
  for (size_t k = 0; k < materials.size(); ++k)
    if (used[k] && materials[k].heat_capacity > 0)
      D = std::max(D,
                   materials[k].conductivity / (materials[k].density * materials[k].heat_capacity));
  if (!(D > 0))
    return std::numeric_limits<double>::infinity();
  const double h = grid.min_cell_size();
  return h * h / D;
}

double default_fourier(int) {
  return 0.1;
}

} // namespace smpm
