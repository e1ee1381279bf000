// SPDX-License-Identifier: BSD-3-Clause
#include "sparsempm/diagnostics.hpp"

#include "kernels.hpp"
#include "parallel.hpp"

#include "sparsempm/errors.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace smpm {

namespace {
// Σ_p M_p |V_p|², max_p |V_p|² and Σ_p M_p V_p (d entries) in one pass, in the fixed order of
// ordered_reduce_blocks; each block sums in registers, the dimension a compile-time constant.
void velocity_sums(const Particles& P, double sums[5]) {
  auto pass = [&]<int D>() {
    detail::ordered_reduce_blocks(
        P.size(), 2 + D, 0.0, sums,
        [&](Index begin, Index end, double* out) {
          double kin = 0, vmax = 0, mom[D] = {};
          for (Index p = begin; p < end; ++p) {
            const double* V = P.V.data() + p * P.V.outerStride();
            const double M = P.mass[p];
            double v2 = 0;
            for (int a = 0; a < D; ++a)
              v2 += V[a] * V[a];
            for (int a = 0; a < D; ++a)
              mom[a] += M * V[a];
            kin += M * v2;
            vmax = std::max(vmax, v2);
          }
          out[0] = kin;
          out[1] = vmax;
          for (int a = 0; a < D; ++a)
            out[2 + a] = mom[a];
        },
        [](int c, double a, double b) { return c == 1 ? std::max(a, b) : a + b; });
  };
  detail::by_dim(P.dim, pass);
}
} // namespace

Energies energies(const Model& model, const Eigen::VectorXd* density) {
  const Particles& P = model.particles;
  double sums[5];
  velocity_sums(P, sums);
  Energies e;
  e.kinetic = 0.5 * sums[0];
  e.max_speed = std::sqrt(sums[1]);
  e.strain = strain_energy(model.materials, P, density);
  e.total = e.kinetic + e.strain;
  for (int a = 0; a < P.dim; ++a)
    e.momentum[a] = sums[2 + a];
  return e;
}

double max_particle_speed(const Particles& particles) {
  double sums[5];
  velocity_sums(particles, sums);
  return std::sqrt(sums[1]);
}

double signal_speed(const Model& model) {
  return std::max(max_wave_speed(model.materials, model.particles),
                  max_particle_speed(model.particles));
}

double stable_time_step(const Model& model, double courant, double speed) {
  if (!(courant > 0) || !std::isfinite(courant))
    throw InputError("courant number must be positive, got " + std::to_string(courant));
  if (!(speed > 0))
    throw InputError("cannot choose a time step: no wave speed and no particle velocity");
  return courant * model.grid.min_cell_size() / speed;
}

double stable_time_step(const Model& model, double courant) {
  return stable_time_step(model, courant, signal_speed(model));
}

double courant_of(const Model& model, double dt) {
  return dt * signal_speed(model) / model.grid.min_cell_size();
}

ThermalSums thermal_sums(const Model& model, double strain) {
  const Particles& P = model.particles;
  SMPM_VERIFY(P.temperature.size() == P.size(), "thermal_sums: the particles have no temperatures");
  std::vector<char> used(model.materials.size(), 0);
  for (Index p = 0; p < P.size(); ++p) {
    const int id = P.material[p];
    if (id < 0 || id >= int(model.materials.size()))
      throw InputError("particle " + std::to_string(p) + " has material id " + std::to_string(id) +
                       ", but there are " + std::to_string(model.materials.size()) + " materials");
    used[size_t(id)] = 1;
  }
  for (size_t k = 0; k < used.size(); ++k)
    if (used[k] && (!(model.materials[k].heat_capacity > 0) ||
                    !(model.materials[k].reference_temperature > 0)))
      throw InputError("material '" + model.materials[k].name +
                       "': the thermal sums need heat_capacity > 0 and reference_temperature > 0");
  // Σ M C, Σ M C T, Σ M C (T − T_ref), U − W, S, Σ T S (per particle: S_p = M C ln(T/T_ref) +
  // Ω c with c the coupling of thermal_coupling; U_p − Ω W_p = M C (T − T_ref) + T Ω c, but for a
  // Mie–Grüneisen particle, whose U (in the strain energy) holds its heat).
  double s[6];
  detail::ordered_reduce_blocks(
      P.size(), 6, 0.0, s,
      [&](Index begin, Index end, double* out) {
        for (Index p = begin; p < end; ++p) {
          const Material& m = model.materials[size_t(P.material[p])];
          const double T = P.temperature[p], C = P.mass[p] * m.heat_capacity;
          const bool shock = m.model == MaterialModel::MieGruneisen;
          const double c =
              shock || m.thermal_expansion != 0
                  ? P.volume0[p] * thermal_coupling(m, P.dim, embed_3d(P.F.row(p).data(), P.dim), T)
                  : 0.0;
          const double S = C * std::log(T / m.reference_temperature) + c;
          out[0] += C;
          out[1] += C * T;
          out[2] += C * (T - m.reference_temperature);
          out[3] += shock ? 0.0 : C * (T - m.reference_temperature) + T * c;
          out[4] += S;
          out[5] += T * S;
        }
      },
      [](double a, double b) { return a + b; });
  ThermalSums t;
  if (P.size() == 0)
    return t;
  t.temperature_min = P.temperature.minCoeff(); // min and max: the same in any order
  t.temperature_max = P.temperature.maxCoeff();
  t.temperature_mean = s[0] > 0 ? s[1] / s[0] : std::nan("");
  t.heat = s[2];
  t.internal = strain + s[3];
  t.entropy = s[4];
  t.helmholtz = t.internal - s[5];
  return t;
}

void material_sums(const Model& model, std::vector<double>& out) {
  const Particles& P = model.particles;
  const int d = P.dim, w = 1 + 2 * d, k = int(model.materials.size()) * w;
  out.assign(size_t(k), 0.0);
  if (k == 0)
    return;
  // (M, Σ M V, Σ M X) per material, in the fixed order of ordered_reduce_blocks: within a block,
  // one pass per material present, its sums in registers (the particles of a material in order).
  const int materials = int(model.materials.size());
  detail::by_dim(d, [&]<int D>() {
    detail::ordered_reduce_blocks(
        P.size(), k, 0.0, out.data(),
        [&](Index begin, Index end, double* acc) {
          const int* material = P.material.data();
          const double* V = P.V.data();
          const double* X = P.X.data();
          const Index sv = P.V.outerStride(), sx = P.X.outerStride();
          for (int m = 0; m < materials; ++m) {
            double M = 0, MV[D] = {}, MX[D] = {};
            bool present = false;
            for (Index p = begin; p < end; ++p) {
              if (material[p] != m)
                continue;
              present = true;
              const double mp = P.mass[p];
              M += mp;
              for (int a = 0; a < D; ++a) {
                MV[a] += mp * V[p * sv + a];
                MX[a] += mp * X[p * sx + a];
              }
            }
            if (!present)
              continue;
            double* o = acc + size_t(m) * size_t(w);
            o[0] += M;
            for (int a = 0; a < D; ++a) {
              o[1 + a] += MV[a];
              o[1 + D + a] += MX[a];
            }
          }
        },
        [](double a, double b) { return a + b; });
  });
  for (size_t m = 0; m < model.materials.size(); ++m)
    for (int a = 0; a < d; ++a) {
      double& c = out[m * size_t(w) + size_t(1 + d + a)];
      c = out[m * size_t(w)] > 0 ? c / out[m * size_t(w)] : std::nan("");
    }
}

double velocity_change(const Particles& P, const Field& V0) {
  SMPM_VERIFY(V0.rows() == P.size() && V0.cols() == P.dim,
              "velocity_change: V0 must have a row per particle and a column per axis");
  if (P.size() == 0)
    return 0.0;
  double sum = 0;
  detail::by_dim(P.dim, [&]<int D>() {
    const double* V = P.V.data();
    const double* W = V0.data();
    const Index sv = P.V.outerStride();
    sum = detail::ordered_sum(P.size(), [&](Index p) {
      double s = 0;
      for (int a = 0; a < D; ++a) {
        const double dv = V[p * sv + a] - W[p * D + a];
        s += dv * dv;
      }
      return s;
    });
  });
  return std::sqrt(sum / double(P.size()));
}

} // namespace smpm
