// SPDX-License-Identifier: BSD-3-Clause
// smpm transport-stability: the critical Fourier number of heat transport by MPM for the lumped
// update, FMPM(k) on the capacity matrix and the exact capacity solve (FMPM 2026 §3.5 with the
// stability study of §3.3): the analogue of Fig. 12A for transport.

#include "transport_command.hpp"

#include "notes.hpp"
#include "option_checks.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/run_file.hpp>
#include <sparsempm/transport_stability.hpp>

#include <cstdio>
#include <sstream>

namespace smpm::app {

namespace {

struct Row {
  TransportUpdate update;
  int order;
  CriticalFourier fourier;   // the smallest F* over the configurations
  std::string configuration; // where it was found
  CriticalFourier lowest;    // the worst small F (SmallCourant's order, then stable_from)
  std::string lowest_configuration;
  std::string small_text() const {
    return small_courant_cell(lowest.small, lowest.stable_from, lowest.floor, lowest_configuration,
                              fourier.critical_fourier, "F");
  }
};

// F* of `options` at every configuration: the smallest, and where.
void search(const std::vector<Configuration>& configs, const StepOptions& options, Row& row,
            const std::atomic<int>* interrupt) {
  std::vector<CriticalFourier> found(configs.size());
  run_tasks(configs.size(), [&](size_t c) {
    found[c] = critical_fourier(configs[c].model, options, 1e-6, 4.0, 1e-3, 0, interrupt);
  });
  row.fourier = row.lowest = found[0];
  row.configuration = row.lowest_configuration = configs[0].name;
  for (size_t c = 1; c < configs.size(); ++c) {
    if (found[c].critical_fourier < row.fourier.critical_fourier) {
      row.fourier = found[c];
      row.configuration = configs[c].name;
    }
    if (worse_small(found[c].small, found[c].stable_from, row.lowest.small,
                    row.lowest.stable_from)) {
      row.lowest = found[c];
      row.lowest_configuration = configs[c].name;
    }
  }
}

} // namespace

int transport_stability_command(const TransportStabilityArgs& a) {
  check_list("--order", a.orders);
  for (int k : a.orders)
    check_int("--order", k, 1, kMaxListedOrder);
  check_int("--shifts", a.shifts, 1, kMaxLatticeShifts);
  check_table_output(a.output, {a.input}, "-o");
  check_regular_file(a.input, kMaxInputBytes, "input file");
  RunConfig cfg = read_input_file(a.input, a.sets);
  print_notes(cfg);
  const std::vector<Configuration> configs = lattice_configurations(cfg.model, a.shifts);
  std::vector<Row> rows;
  rows.push_back({TransportUpdate::Lumped, 1, {}, "", {}, ""});
  for (int k : a.orders)
    rows.push_back({TransportUpdate::FMPM, k, {}, "", {}, ""});
  if (!a.no_exact)
    rows.push_back({TransportUpdate::Exact, 0, {}, "", {}, ""});
  std::printf("%-8s %5s %10s %10s %-16s %s\n", "transport", "order", "F*", "rho(T)",
              "configuration", "below F*");
  std::ostringstream out;
  out << kTransportStabilityColumns << "\n";
  for (Row& r : rows) {
    StepOptions o = cfg.step;
    o.transport.update = r.update;
    o.transport.order = r.order;
    search(configs, o, r, nullptr);
    const std::string order = r.update == TransportUpdate::FMPM ? std::to_string(r.order) : "";
    std::printf("%-8s %5s %10s %10s %-16s %s\n", std::string(to_string(r.update)).c_str(),
                order.c_str(), cell(r.fourier.critical_fourier).c_str(),
                cell(r.fourier.rho_T, 8).c_str(), r.configuration.c_str(), r.small_text().c_str());
    std::fflush(stdout);
    out << to_string(r.update) << "," << order << "," << cell(r.fourier.critical_fourier) << ","
        << cell(r.fourier.rho_T, 10) << "," << r.configuration << "," << r.fourier.evaluations
        << "," << cell(r.lowest.stable_from) << "," << r.small_text() << "\n";
  }
  write_table_file(a.output, out.str(), {a.input}, "-o");
  std::printf("table in %s\n", a.output.c_str());
  return 0;
}

} // namespace smpm::app
