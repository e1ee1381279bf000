// SPDX-License-Identifier: BSD-3-Clause
// Threads (threads.hpp, DESIGN.md "Threads"): the loops of the library give the same bits for
// any number of threads, rethrow the error a serial loop would throw first, and whole runs of
// the example problems with 1 and 2 threads end in identical particle states.

#include "support.hpp"

#include "kernels.hpp"  // lib/src: det, scatter_to_nodes
#include "parallel.hpp" // lib/src: the library's OpenMP loops

#include <sparsempm/input.hpp>
#include <sparsempm/stages.hpp>
#include <sparsempm/step_preparation.hpp>
#include <sparsempm/threads.hpp>

#include <omp.h>

#include <cstdlib>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace smpm;

namespace {

// Sets the thread count and the parallel threshold for a scope and restores them after.
struct ThreadScope {
  int saved_threads = threads();
  Index saved_threshold = parallel_threshold();
  ThreadScope(int count, Index threshold) {
    set_threads(count);
    set_parallel_threshold(threshold);
  }
  ~ThreadScope() {
    set_threads(saved_threads);
    set_parallel_threshold(saved_threshold);
  }
};

// The particle state after `steps` Courant steps of an example with `overrides`.
Particles run_example(const std::string& file, const std::vector<std::string>& overrides, int steps,
                      int thread_count) {
  const ThreadScope scope(thread_count, 0); // every kernel on all threads, even on the bar
  RunConfig cfg = read_input_file(std::string(SMPM_EXAMPLES_DIR) + "/" + file, overrides);
  Stepper stepper(cfg.step);
  for (int s = 0; s < steps; ++s)
    stepper.step(cfg.model, stable_time_step(cfg.model, cfg.time.courant));
  return cfg.model.particles;
}

} // namespace

TEST_CASE("parallel_for runs on the threads and rethrows the first failure", "[threads]") {
  const ThreadScope scope(2, 0);
  std::vector<int> thread_of(1000, -1);
  detail::parallel_for(1000, [&](Index i) { thread_of[size_t(i)] = omp_get_thread_num(); });
  CHECK(std::set<int>(thread_of.begin(), thread_of.end()) == std::set<int>{0, 1});
  // Indices 700 and 300 fail (in different halves, so on different threads): the exception of
  // 300 is the one a serial loop would meet first, whichever thread records first.
  for (int repeat = 0; repeat < 20; ++repeat)
    CHECK_THROWS_WITH(detail::parallel_for(1000,
                                           [&](Index i) {
                                             if (i == 700 || i == 300)
                                               throw std::runtime_error(std::to_string(i));
                                           }),
                      "300");
}

TEST_CASE("ordered sums do not depend on the number of threads", "[threads]") {
  // Terms of mixed sign and magnitude, whose sum depends on the order of the additions.
  std::mt19937 rng(5u);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> x(100003);
  for (double& v : x)
    v = u(rng) * std::pow(10.0, 8 * u(rng));
  auto sum_with = [&](int count) {
    const ThreadScope scope(count, 0);
    return detail::ordered_sum(Index(x.size()), [&](Index i) { return x[size_t(i)]; });
  };
  // The fixed order: blocks of kReductionBlock terms, then the block sums, serially.
  double blocks = 0;
  for (size_t b = 0; b < x.size(); b += size_t(detail::kReductionBlock)) {
    double s = 0;
    for (size_t i = b; i < std::min(x.size(), b + size_t(detail::kReductionBlock)); ++i)
      s += x[i];
    blocks += s;
  }
  CHECK(sum_with(1) == blocks);
  CHECK(sum_with(2) == blocks);
  CHECK(sum_with(3) == blocks);
}

TEST_CASE("SMPM_THREADS is applied and checked", "[threads]") {
  const ThreadScope scope(1, parallel_threshold());
  ::setenv("SMPM_THREADS", "3", 1);
  CHECK(threads_from_environment() == 3);
  CHECK(threads() == 3);
  for (const char* bad : {"0", "-2", "two", "", "2.5", "99999"}) {
    ::setenv("SMPM_THREADS", bad, 1);
    CHECK_THROWS_WITH(threads_from_environment(),
                      "SMPM_THREADS='" + std::string(bad) +
                          "': expected a positive integer (at most 4096), the number of threads");
  }
  ::unsetenv("SMPM_THREADS");
  CHECK(threads_from_environment() == 3); // unset: unchanged
  CHECK_THROWS_AS(set_threads(0), InputError);
}

TEST_CASE("1 and 2 threads give bit-identical runs of the examples", "[threads]") {
  // 50 steps of FLIP, FMPM(4), XPIC(3) and the exact update (C = 0.1, light nodes lumped) on the
  // vibrating bar (CPDI, 80 particles) and on the block impact (CPDI, neo-Hookean, 8000 particles):
  // X, V, F and the stress after the run are equal bit for bit.
  const std::vector<std::vector<std::string>> schemes = {
      {"step.velocity=FLIP"},
      {"step.velocity=FMPM", "step.order=4"},
      {"step.velocity=XPIC", "step.order=3"},
      {"step.velocity=exact", "time.courant=0.1", "step.exact_mass_cutoff=1e-2"}};
  for (const std::string file : {"vibrating_bar.toml", "block_impact.toml"})
    for (const auto& scheme : schemes) {
      INFO(file << " " << scheme.front() << (scheme.size() > 1 ? " " + scheme[1] : ""));
      const Particles one = run_example(file, scheme, 50, 1);
      const Particles two = run_example(file, scheme, 50, 2);
      CHECK(one.X == two.X);
      CHECK(one.V == two.V);
      CHECK(one.F == two.F);
      CHECK(one.stress == two.stress);
      // The runs did something: the particles moved and carry stress.
      const RunConfig start = read_input_file(std::string(SMPM_EXAMPLES_DIR) + "/" + file);
      CHECK((one.X - start.model.particles.X).cwiseAbs().maxCoeff() > 0);
      CHECK(one.stress.cwiseAbs().maxCoeff() > 0);
    }
}

TEST_CASE("1 and 2 threads give bit-identical heat transport", "[threads][transport]") {
  // 360 steps of the disk impact with heat (they touch at step 300; 2514 particles: every
  // transport kernel, the folded capacity's scatter, the friction heat, the isentropic heating
  // with α = 6e-5 and the thermal sums on threads) by FMPM(4) with FMPM(4) transport and FLIP
  // with the lumped one: X, the stress and the temperatures equal bit for bit, and so do the
  // thermal sums.
  for (const std::vector<std::string>& scheme :
       {std::vector<std::string>{"step.transport=FMPM"},
        std::vector<std::string>{"step.velocity=FLIP", "step.transport=lumped"}}) {
    std::vector<std::string> sets = scheme;
    sets.push_back("material.left.thermal_expansion=6e-5");
    sets.push_back("material.right.thermal_expansion=6e-5");
    const Particles one = run_example("disk_impact.toml", sets, 360, 1);
    const Particles two = run_example("disk_impact.toml", sets, 360, 2);
    CHECK(one.X == two.X);
    CHECK(one.stress == two.stress);
    CHECK(one.temperature == two.temperature);
    RunConfig cfg = read_input_file(std::string(SMPM_EXAMPLES_DIR) + "/disk_impact.toml", sets);
    cfg.model.particles = one;
    ThermalSums s1, s2;
    {
      const ThreadScope scope(1, 0);
      s1 = thermal_sums(cfg.model, 0.0);
    }
    {
      const ThreadScope scope(2, 0);
      s2 = thermal_sums(cfg.model, 0.0);
    }
    CHECK(s1.entropy == s2.entropy);
    CHECK(s1.helmholtz == s2.helmholtz);
    CHECK(one.temperature.maxCoeff() > 300.001); // the disks met: compression heated them
  }
}

TEST_CASE("parallel_ranges cover [0, n) in order, balanced by the counts given", "[threads]") {
  const ThreadScope scope(3, 0);
  // Counts with long runs of empty indices (nodes without particles) and one heavy index.
  std::vector<int> cumulative{0};
  for (int i = 0; i < 200; ++i)
    cumulative.push_back(cumulative.back() + (i < 50 || i > 180 ? 0 : (i == 100 ? 500 : 3)));
  const int* const balances[] = {nullptr, cumulative.data()};
  for (const int* counts : balances)
    for (Index n : {Index(1), Index(2), Index(200)}) {
      CAPTURE(n, counts != nullptr);
      std::vector<std::pair<Index, Index>> ranges(3, {-1, -1});
      detail::parallel_ranges(n, 1000, counts, [&](Index r0, Index r1) {
        ranges[size_t(omp_get_thread_num())] = {r0, r1};
      });
      std::sort(ranges.begin(), ranges.end());
      Index next = 0; // the ranges run that were called, in order, cover [0, n) once
      for (const auto& [r0, r1] : ranges)
        if (r0 >= 0) {
          CHECK(r0 == next);
          CHECK(r1 >= r0);
          next = r1;
        }
      CHECK(next == n);
      if (counts && n == 200) // the heavy index 100 (500 of 890 entries) ends the first range
        CHECK(ranges[0].second == 101);
    }
}

TEST_CASE("blocked prefix sums equal the serial exclusive prefix sum on 1, 2 and 3 threads",
          "[threads]") {
  // The row offsets of S and the column offsets of its index are built this way (shape.cpp,
  // operators.cpp): starts[b] = the counts before block b, and each block, given its start,
  // must rebuild the serial offsets exactly. n spans a partial last block.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> box(0, 27);
  for (Index n : {Index(0), Index(1), 3 * detail::kReductionBlock + 17}) {
    std::vector<Index> counts(static_cast<size_t>(n));
    for (Index& k : counts)
      k = box(rng);
    std::vector<Index> serial(size_t(n + 1), 0);
    for (Index i = 0; i < n; ++i)
      serial[size_t(i + 1)] = serial[size_t(i)] + counts[size_t(i)];
    for (int t : {1, 2, 3}) {
      CAPTURE(n, t);
      const ThreadScope scope(t, 0);
      std::vector<Index> starts, offsets(size_t(n + 1), -1);
      detail::prefix_block_starts(n, starts, [&](Index i) { return counts[size_t(i)]; });
      REQUIRE(starts.back() == serial.back());
      detail::for_prefix_blocks(n, starts, [&](Index begin, Index end, Index start) {
        for (Index i = begin; i < end; ++i) {
          offsets[size_t(i)] = start;
          start += counts[size_t(i)];
        }
      });
      offsets[size_t(n)] = starts.back();
      CHECK(offsets == serial);
    }
  }
}

TEST_CASE("a bad particle mass is reported at the first bad particle on any number of threads",
          "[threads]") {
  // prepare_step checks masses and initial volumes in parallel ranges: the message must name the
  // particle a serial scan stops at (here 700 on the first thread's half, 1500 on the second's).
  Model model(Grid(2, {0, 0, 0}, {1, 1, 1}, {40, 40, 1}));
  model.materials = {smpm::test::material("m", MaterialModel::Linear, 100, 0.3)};
  model.particles = smpm::test::random_cloud(model.grid, 2000, 5, 2.0, false);
  model.particles.mass[1500] = std::numeric_limits<double>::quiet_NaN();
  model.particles.volume0[1500] = -2;
  auto& P = model.particles;
  for (int t : {1, 2, 3}) {
    const ThreadScope scope(t, 0);
    StepPreparation prep;
    const auto reports = [&](const std::string& message) {
      CHECK_THROWS_WITH(prepare_step(model, Shape::GIMP, prep), message);
    };
    reports("particle 1500: mass nan must be positive and finite");
    P.mass[700] = 0;
    reports("particle 700: mass 0 must be positive and finite");
    P.mass[700] = 1;
    // Masses are checked before initial volumes (one region checks both): a bad volume0 at an
    // earlier particle does not hide a bad mass.
    P.volume0[700] = 0;
    reports("particle 1500: mass nan must be positive and finite");
    P.mass[1500] = 1;
    reports("particle 700: volume0 0 must be positive and finite");
    P.volume0[700] = 1;
    reports("particle 1500: volume0 -2 must be positive and finite");
    P.mass[1500] = std::numeric_limits<double>::quiet_NaN();
  }
  // Finite masses whose sum overflows a double are valid (the ranges' sums only flag them for
  // the scan, which finds nothing).
  model.particles.mass[1500] = 1;
  model.particles.volume0[1500] = 1;
  model.particles.mass[10] = model.particles.mass[11] = 1e308;
  for (int t : {1, 2}) {
    const ThreadScope scope(t, 0);
    StepPreparation prep;
    CHECK_NOTHROW(prepare_step(model, Shape::GIMP, prep));
  }
}

TEST_CASE("node sums have the bits of a serial sum over the particles on 1, 2 and 3 threads",
          "[threads]") {
  // p = Sᵀ M V (FMPM 2026 task 1), f = −Gᵀ(Ω J σ) (Buzzi Eq. 15) and g = Gᵀ Ω (contact 2020
  // Eq. 11), each node's terms in ascending particle order (scatter_to_nodes): equal (==) to a
  // loop over the nodes that adds the same terms in that order, on 1, 2 and 3 threads, for the
  // whole operators and for a block of rows (one material's particles), with two fields.
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::GIMP, Shape::CPDI})
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const Grid g = smpm::test::test_grid(dim, dim == 3 ? 7 : 12);
        Particles P = smpm::test::random_cloud(g, dim == 3 ? 400 : 300, 11u * dim, 2.0, true);
        std::mt19937 rng(3u);
        std::uniform_real_distribution<double> u(-1, 1);
        for (Index p = 0; p < P.size(); ++p) {
          for (int c = 0; c < dim * dim; ++c)
            P.stress(p, c) = u(rng) * std::pow(10.0, 3 * u(rng));
          for (int a = 0; a < dim; ++a)
            P.V(p, a) = u(rng);
        }
        Eigen::VectorXi field = Eigen::VectorXi::Zero(P.size());
        for (Index p = 0; p < P.size(); ++p)
          field[p] = int(p % fields);
        Operators ops;
        assemble(g, P, shape, ops, fields, &field);
        const ParticleOperators all = particle_operators(ops);
        const Index first = P.size() / 3, count = P.size() / 2;
        for (const ParticleOperators& op : {all, all.block(first, count)}) {
          const Index q0 = op.first, n = op.nodes;
          const Field V = P.V.middleRows(q0, op.rows);
          const Field F = P.F.middleRows(q0, op.rows), stress = P.stress.middleRows(q0, op.rows);
          const Eigen::VectorXd vol = P.volume0.segment(q0, op.rows);
          Field p_ref = Field::Zero(n, dim), f_ref = Field::Zero(n, dim),
                g_ref = Field::Zero(n, dim);
          for (Index i = 0; i < n; ++i) // node by node, particles in order: the reference sums
            for (Index q = 0; q < op.rows; ++q)
              for (int k = op.outer[q]; k < op.outer[q + 1]; ++k) {
                if (op.inner[k] != i)
                  continue;
                double J = dim == 1 ? detail::det<1>(F.row(q).data())
                                    : (dim == 2 ? detail::det<2>(F.row(q).data())
                                                : detail::det<3>(F.row(q).data()));
                const double tau = -vol[q] * J;
                for (int a = 0; a < dim; ++a) {
                  p_ref(i, a) += op.S[k] * (op.M[q] * V(q, a));
                  double sum = 0;
                  for (int b = 0; b < dim; ++b)
                    sum += tau * stress(q, a * dim + b) * op.G[size_t(b)][k];
                  f_ref(i, a) += sum;
                  g_ref(i, a) += op.G[size_t(a)][k] * vol[q];
                }
              }
          CHECK(p_ref.cwiseAbs().maxCoeff() > 0);
          CHECK(f_ref.cwiseAbs().maxCoeff() > 0);
          for (int count_threads : {1, 2, 3}) {
            CAPTURE(op.rows, count_threads);
            const ThreadScope scope(count_threads, 0);
            Field p, f, gv;
            map_momentum(op, V, p);
            internal_force(op, vol, F, stress, f);
            volume_gradient(op, vol, gv);
            CHECK(p == p_ref);
            CHECK(f == f_ref);
            CHECK(gv == g_ref);
          }
        }
      }
}

TEST_CASE("m~ equals S^T M S and has the same bits on 1, 2 and 3 threads", "[threads]") {
  // m̃_ij = Σ_p M_p S_pi S_pj (FMPM 2026 §2.1): the stencil scatter (a fixed-offset path for boxes
  // away from the grid's edges, a clipped one beside them) against Eigen's product Sᵀ diag(M) S,
  // to 1e-15 of the largest entry (the same terms, summed in another order); with one and with
  // two fields (blocks of columns, contact.hpp). Each entry sums its particles in ascending
  // order on any number of threads: the values are equal (==).
  for (int dim = 1; dim <= 3; ++dim)
    for (Shape shape : {Shape::Linear, Shape::GIMP, Shape::BSpline2, Shape::CPDI, Shape::B2CPDI})
      for (int fields : {1, 2}) {
        CAPTURE(dim, to_string(shape), fields);
        const Grid g = smpm::test::test_grid(dim, dim == 3 ? 7 : 12);
        const Particles P = smpm::test::random_cloud(g, dim == 3 ? 400 : 300, 7u * dim, 2.0, true);
        Eigen::VectorXi field = Eigen::VectorXi::Zero(P.size());
        for (Index p = 0; p < P.size(); ++p)
          field[p] = int(p % fields);
        auto assembled = [&](int count) {
          const ThreadScope scope(count, 0);
          Operators ops;
          assemble(g, P, shape, ops, fields, &field);
          ConsistentMass mt;
          assemble_consistent_mass(ops, mt);
          return std::make_pair(std::move(ops), std::move(mt));
        };
        const auto [ops, mt] = assembled(1);
        const SparseMatrix S(ops.S);
        const Eigen::MatrixXd ref = Eigen::MatrixXd(S.transpose() * ops.M.asDiagonal() * S);
        const Eigen::MatrixXd got(mt.matrix);
        CHECK((got - ref).cwiseAbs().maxCoeff() <= 1e-15 * ref.cwiseAbs().maxCoeff());
        for (int count : {2, 3}) {
          const auto [ops_t, mt_t] = assembled(count);
          REQUIRE(mt_t.matrix.nonZeros() == mt.matrix.nonZeros());
          CHECK(std::equal(mt.matrix.valuePtr(), mt.matrix.valuePtr() + mt.matrix.nonZeros(),
                           mt_t.matrix.valuePtr()));
        }
      }
}

TEST_CASE("m~ of CPDI particles stretched over many cells equals S^T M S", "[threads]") {
  // Boxes of up to 12 nodes on an axis (a CPDI column in large tension): 2 × 12 in 2D and
  // 2 × 2 × 11 in 3D, away from the grid's edges, beside ordinary particles; FMPM 2026 §2.1.
  for (int dim : {2, 3}) {
    CAPTURE(dim);
    const int cells = dim == 3 ? 16 : 40;
    const Grid g(dim, {0, 0, 0}, {1, 1, 1}, {cells, cells, cells});
    Particles P = smpm::test::random_cloud(g, 40, 3u, 4.0, true);
    const Index long_ones = 6;
    Particles stretched;
    stretched.resize(dim, long_ones);
    for (Index p = 0; p < long_ones; ++p) {
      for (int a = 0; a < dim; ++a) {
        stretched.X(p, a) = 0.5 * cells + 0.37 * double(p) + 0.11 * a;
        stretched.half_length(p, a) = 0.5;
      }
      stretched.F.row(p).setZero();
      for (int a = 0; a < dim; ++a) // thin across, long along the last axis (9-10 cells)
        stretched.F(p, a * dim + a) = a == dim - 1 ? (dim == 3 ? 9.2 : 9.9) : 0.2;
      stretched.mass[p] = 1 + 0.1 * double(p);
      stretched.volume0[p] = 1;
    }
    P.append(stretched);
    const Operators ops = assemble(g, P, Shape::CPDI);
    int longest = 0;
    for (const ShapeSupport& s : ops.support)
      longest = std::max(longest, s.count[size_t(dim - 1)]);
    CHECK(longest == 12);
    ConsistentMass mt;
    assemble_consistent_mass(ops, mt);
    const SparseMatrix S(ops.S);
    const Eigen::MatrixXd ref = Eigen::MatrixXd(S.transpose() * ops.M.asDiagonal() * S);
    CHECK((Eigen::MatrixXd(mt.matrix) - ref).cwiseAbs().maxCoeff() <=
          1e-15 * ref.cwiseAbs().maxCoeff());
  }
}
