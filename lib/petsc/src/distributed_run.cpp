// SPDX-License-Identifier: BSD-3-Clause
// Simulations across ranks: each rank's share of the particles, the serial Stepper on it with the
// node sums over the ranks (WindowSums), the particles' migration by PETSc's DMSwarm and the
// whole particle set gathered in global id order.
#include "sparsempm/petsc_run.hpp"

#include "sparsempm/errors.hpp"
#include "sparsempm/particle_columns.hpp"

#include <petscdmswarm.h>

#include <algorithm>
#include <numeric>
#include <regex>
#include <string>

namespace smpm::petsc {

namespace {

using OwnedDMSwarm = Owned<DM, DMDestroy>;

// The values one particle carries from rank to rank, in this order: its global id, material,
// X, V, F, σ (d, d, d², d²), mass, volume0, half-lengths (d), then each optional column any
// rank's particles hold (particle_columns, in their order), column_width values each.
struct Layout {
  int d = 1;
  std::vector<const ParticleColumn*> columns; // the optional columns carried
  bool half_lengths = false;                  // whether the particles carry half-lengths
  Index width = 0;

  // The columns carried: those held by the particles of some rank that has particles, so that
  // every rank packs the same values (a rank without particles holds every column vacuously).
  Layout(const NodeSums& sums, const Particles& P) : d(P.dim) {
    const std::vector<ParticleColumn>& all = particle_columns();
    std::vector<double> held(all.size() + 1, 0.0);
    for (size_t c = 0; c < all.size(); ++c)
      held[c] = P.size() > 0 && has_column(P, all[c]) ? 1.0 : 0.0;
    held.back() = P.size() > 0 && P.half_length.rows() == P.size() ? 1.0 : 0.0;
    sums.sum(held.data(), int(held.size()));
    half_lengths = held.back() > 0;
    width = 2 + 2 * d + 2 * d * d + 2 + (half_lengths ? d : 0);
    for (size_t c = 0; c < all.size(); ++c)
      if (held[c] > 0) {
        columns.push_back(&all[c]);
        width += column_width(all[c], d);
      }
  }

  // Particle p of P (global id `id`) into `out` (width values).
  void pack(const Particles& P, Index p, Index id, double* out) const {
    *out++ = double(id);
    *out++ = double(P.material[p]);
    auto put = [&](const auto& row) {
      for (Index k = 0; k < row.size(); ++k)
        *out++ = row[k];
    };
    put(P.X.row(p));
    put(P.V.row(p));
    put(P.F.row(p));
    put(P.stress.row(p));
    *out++ = P.mass[p];
    *out++ = P.volume0[p];
    if (half_lengths)
      put(P.half_length.row(p));
    for (const ParticleColumn* c : columns) {
      const Index w = column_width(*c, d);
      if (has_column(P, *c))
        put(column_values(P, *c).row(p));
      else
        out = std::fill_n(out, w, 0.0);
    }
  }

  // n particles from `in` (width values each) into a new set, and their global ids.
  Particles unpack(const double* in, Index n, std::vector<Index>& ids) const {
    Particles P;
    P.resize(d, n);
    P.half_length.resize(half_lengths ? n : 0, d);
    std::vector<Field> values;
    for (const ParticleColumn* c : columns)
      values.emplace_back(n, column_width(*c, d));
    ids.resize(size_t(n));
    for (Index p = 0; p < n; ++p) {
      ids[size_t(p)] = Index(*in++);
      P.material[p] = int(*in++);
      auto take = [&](auto row) {
        for (Index k = 0; k < row.size(); ++k)
          row[k] = *in++;
      };
      take(P.X.row(p));
      take(P.V.row(p));
      take(P.F.row(p));
      take(P.stress.row(p));
      P.mass[p] = *in++;
      P.volume0[p] = *in++;
      if (half_lengths)
        take(P.half_length.row(p));
      for (Field& v : values)
        take(v.row(p));
    }
    for (size_t c = 0; c < columns.size(); ++c)
      set_column(P, *columns[c], values[c]);
    return P;
  }
};

// `P` with its particles in ascending order of `ids` (sorted too).
void sort_by_id(Particles& P, std::vector<Index>& ids) {
  std::vector<Index> order(ids.size());
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return ids[size_t(a)] < ids[size_t(b)]; });
  if (std::is_sorted(order.begin(), order.end()))
    return;
  P = select_particles(P, order);
  std::vector<Index> sorted(ids.size());
  for (size_t k = 0; k < order.size(); ++k)
    sorted[k] = ids[size_t(order[k])];
  ids = std::move(sorted);
}

// The model's loads on this rank's particles: each load of the whole model (local.loads) with
// the particles this rank holds, by their index here (local.ids is ascending), and their areas.
void name_loads(RankModel& local) {
  std::vector<ParticleLoad>& loads = local.model.loads;
  loads.resize(local.loads.size());
  for (size_t k = 0; k < loads.size(); ++k) {
    const ParticleLoad& whole = local.loads[k];
    ParticleLoad& here = loads[k];
    here = whole;
    here.particles.clear();
    std::vector<double> area;
    for (size_t j = 0; j < whole.particles.size(); ++j) {
      const auto at = std::lower_bound(local.ids.begin(), local.ids.end(), whole.particles[j]);
      if (at == local.ids.end() || *at != whole.particles[j])
        continue;
      here.particles.push_back(Index(at - local.ids.begin()));
      if (whole.area.size() > Index(j))
        area.push_back(whole.area[Index(j)]);
    }
    here.area = Eigen::Map<const Eigen::VectorXd>(area.data(), Index(area.size()));
  }
}

} // namespace

RankModel distribute(const DistributedGrid& grid, const Model& whole) {
  RankModel r;
  r.ids = grid.owned_particles(whole.particles);
  r.model = whole;
  r.model.particles = select_particles(whole.particles, r.ids);
  r.total = whole.particles.size();
  r.loads = whole.loads;
  name_loads(r);
  return r;
}

Index migrate(const DistributedGrid& grid, const NodeSums& sums, RankModel& local, double* bytes) {
  Particles& P = local.model.particles;
  const Index n = P.size();
  std::vector<Index> leaving; // the particles whose cell another rank owns, and that rank
  std::vector<int> target;
  for (Index p = 0; p < n; ++p) {
    const std::array<int, 3> cell = grid.cell_of(P.X.row(p).data());
    if (!grid.owns_cell(cell)) {
      leaving.push_back(p);
      target.push_back(grid.owner_of_cell(cell));
    }
  }
  double moved = double(leaving.size());
  sums.sum(&moved, 1); // meets a failure on another rank first
  if (moved == 0)
    return 0;
  std::vector<Index> staying;
  staying.reserve(size_t(n) - leaving.size());
  for (Index p = 0, k = 0; p < n; ++p)
    if (k < Index(leaving.size()) && leaving[size_t(k)] == p)
      ++k;
    else
      staying.push_back(p);
  const Layout layout(sums, P);
  const PetscInt bs = PetscInt(layout.width);
  // The leaving particles as the points of a swarm, each with the rank it goes to.
  OwnedDMSwarm swarm;
  SMPM_PETSC_CALL(DMCreate(grid.comm(), swarm.out()));
  SMPM_PETSC_CALL(DMSetType(swarm, DMSWARM));
  SMPM_PETSC_CALL(DMSwarmSetType(swarm, DMSWARM_BASIC));
  SMPM_PETSC_CALL(DMSwarmInitializeFieldRegister(swarm));
  SMPM_PETSC_CALL(DMSwarmRegisterPetscDatatypeField(swarm, "particle", bs, PETSC_REAL));
  SMPM_PETSC_CALL(DMSwarmFinalizeFieldRegister(swarm));
  SMPM_PETSC_CALL(DMSwarmSetLocalSizes(swarm, PetscInt(leaving.size()), 16));
  {
    PetscReal* values = nullptr;
    PetscInt* rank = nullptr;
    SMPM_PETSC_CALL(DMSwarmGetField(swarm, "particle", nullptr, nullptr, (void**)&values));
    SMPM_PETSC_CALL(DMSwarmGetField(swarm, DMSwarmField_rank, nullptr, nullptr, (void**)&rank));
    for (size_t k = 0; k < leaving.size(); ++k) {
      const Index p = leaving[k];
      layout.pack(P, p, local.ids[size_t(p)], values + Index(k) * layout.width);
      rank[k] = PetscInt(target[k]);
    }
    SMPM_PETSC_CALL(DMSwarmRestoreField(swarm, DMSwarmField_rank, nullptr, nullptr, (void**)&rank));
    SMPM_PETSC_CALL(DMSwarmRestoreField(swarm, "particle", nullptr, nullptr, (void**)&values));
  }
  SMPM_PETSC_CALL(DMSwarmMigrate(swarm, PETSC_TRUE)); // the sent points leave the swarm
  PetscInt arrived = 0;
  SMPM_PETSC_CALL(DMSwarmGetLocalSize(swarm, &arrived));
  if (bytes)
    *bytes += 8.0 * double(layout.width) * double(Index(leaving.size()) + Index(arrived));
  std::vector<Index> ids;
  Particles incoming;
  {
    PetscReal* values = nullptr;
    SMPM_PETSC_CALL(DMSwarmGetField(swarm, "particle", nullptr, nullptr, (void**)&values));
    incoming = layout.unpack(values, Index(arrived), ids);
    SMPM_PETSC_CALL(DMSwarmRestoreField(swarm, "particle", nullptr, nullptr, (void**)&values));
  }
  std::vector<Index> kept_ids(staying.size());
  for (size_t k = 0; k < staying.size(); ++k)
    kept_ids[k] = local.ids[size_t(staying[k])];
  Particles kept = select_particles(P, staying);
  kept.dim = P.dim;
  kept.append(incoming);
  kept_ids.insert(kept_ids.end(), ids.begin(), ids.end());
  sort_by_id(kept, kept_ids);
  P = std::move(kept);
  local.ids = std::move(kept_ids);
  name_loads(local);
  return Index(moved);
}

Particles gather_particles(const DistributedGrid& grid, const RankModel& local) {
  const Particles& P = local.model.particles;
  const WindowSums sums(grid); // the reductions of Layout only
  const Layout layout(sums, P);
  const Index w = layout.width;
  OwnedVec all;
  SMPM_PETSC_CALL(VecCreateMPI(grid.comm(), PETSC_DECIDE, PetscInt(local.total * w), all.out()));
  // Every particle's values at rows id · w ... id · w + w − 1, in one call.
  std::vector<double> values(static_cast<size_t>(P.size() * w));
  std::vector<PetscInt> index(values.size());
  for (Index p = 0; p < P.size(); ++p) {
    const Index id = local.ids[size_t(p)];
    layout.pack(P, p, id, values.data() + p * w);
    std::iota(index.begin() + p * w, index.begin() + (p + 1) * w, PetscInt(id * w));
  }
  SMPM_PETSC_CALL(
      VecSetValues(all, PetscInt(index.size()), index.data(), values.data(), INSERT_VALUES));
  SMPM_PETSC_CALL(VecAssemblyBegin(all));
  SMPM_PETSC_CALL(VecAssemblyEnd(all));
  OwnedScatter to_zero;
  OwnedVec whole;
  SMPM_PETSC_CALL(VecScatterCreateToZero(all, to_zero.out(), whole.out()));
  SMPM_PETSC_CALL(VecScatterBegin(to_zero, all, whole, INSERT_VALUES, SCATTER_FORWARD));
  SMPM_PETSC_CALL(VecScatterEnd(to_zero, all, whole, INSERT_VALUES, SCATTER_FORWARD));
  if (grid.rank() != 0)
    return Particles{};
  const PetscScalar* gathered = nullptr;
  SMPM_PETSC_CALL(VecGetArrayRead(whole, &gathered));
  std::vector<Index> ids;
  Particles out = layout.unpack(gathered, local.total, ids);
  SMPM_PETSC_CALL(VecRestoreArrayRead(whole, &gathered));
  return out;
}

namespace {
// The options with the exact update's m̃⁻¹ across the ranks of the step.
StepOptions across(const StepOptions& options, const DistributedGrid& grid, const WindowSums& sums,
                   ExactMethod exact) {
  StepOptions o = options;
  if (o.velocity == VelocityUpdate::Exact)
    o.exact_solver = step_mass_solver_factory(grid, sums, exact);
  return o;
}
} // namespace

DistributedStepper::DistributedStepper(const DistributedGrid& grid, const StepOptions& options,
                                       ExactMethod exact)
    : grid_(grid), sums_(grid), stepper_(across(options, grid, sums_, exact), sums_) {}

namespace {
// A message of the serial library with each "particle <p>" (an index into this rank's share)
// written as the particle's global id, so that it names the particle as the serial run does.
std::string global_names(const std::string& what, const std::vector<Index>& ids) {
  static const std::regex particle(R"(\bparticle (\d+)\b)");
  std::string out;
  auto last = what.cbegin();
  for (std::sregex_iterator m(what.begin(), what.end(), particle), end; m != end; ++m) {
    out.append(last, (*m)[0].first);
    const unsigned long p = std::stoul((*m)[1].str());
    out += "particle " + (p < ids.size() ? std::to_string(ids[p]) : (*m)[1].str());
    last = (*m)[0].second;
  }
  out.append(last, what.cend());
  return out;
}
} // namespace

Index DistributedStepper::step(RankModel& local, double dt) {
  try {
    stepper_.step(local.model, dt);
  } catch (const FailedElsewhere&) {
    throw;
  } catch (const NumericalError& e) {
    throw NumericalError(global_names(e.what(), local.ids), e.step());
  }
  moved_ = migrate(grid_, sums_, local, &migrated_bytes_);
  return moved_;
}

double DistributedStepper::stable_time_step(const RankModel& local, double courant) const {
  return smpm::stable_time_step(local.model, courant, sums_.maximum(signal_speed(local.model)));
}

Energies DistributedStepper::energies(const RankModel& local) const {
  // The step's stored densities W(F_p) are those of the particles before the migration: after
  // one that moved particles, W is evaluated again (the same bits).
  Energies e = moved_ == 0 ? stepper_.energies(local.model) : smpm::energies(local.model);
  double s[5] = {e.kinetic, e.strain, e.momentum[0], e.momentum[1], e.momentum[2]};
  sums_.sum(s, 5);
  e.kinetic = s[0];
  e.strain = s[1];
  e.total = s[0] + s[1];
  e.momentum = Eigen::Vector3d(s[2], s[3], s[4]);
  e.max_speed = sums_.maximum(e.max_speed);
  return e;
}

StepperState DistributedStepper::state() const {
  StepperState s = stepper_.state();
  double w[3] = {s.friction_work, s.viscous_work, s.plastic_work};
  sums_.sum(w, 3);
  s.friction_work = w[0];
  s.viscous_work = w[1];
  s.plastic_work = w[2];
  return s; // the periodic FMPM budget is the same on every rank
}

} // namespace smpm::petsc
