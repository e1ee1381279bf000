// SPDX-License-Identifier: BSD-3-Clause
#include "info_command.hpp"

#include <sparsempm/errors.hpp>
#include <sparsempm/input.hpp>
#include <sparsempm/output.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace smpm::app {

namespace {

void print_layout() {
  std::printf("%-40s %-16s %s\n", "path", "shape", "what (the runs that write it)");
  for (const LayoutEntry& e : run_file_layout())
    std::printf("%-40s %-16s %s%s%s%s\n", e.path, e.shape, e.what, *e.when ? " (" : "", e.when,
                *e.when ? ")" : "");
}

void print_energies(const StoredRun& run) {
  if (run.series.empty())
    return;
  const SeriesRow& a = run.series.front();
  const SeriesRow& b = run.series.back();
  std::printf("steps:    %zu rows of series (step %ld ... %ld)\n", run.series.size(), a.step,
              b.step);
  std::printf("energy:   start t = %g: kinetic %.6g strain %.6g total %.6g\n", a.t, a.e.kinetic,
              a.e.strain, a.e.total);
  std::printf("          end   t = %g: kinetic %.6g strain %.6g total %.6g", b.t, b.e.kinetic,
              b.e.strain, b.e.total);
  if (a.e.total != 0) // a change relative to a zero start has no meaning
    std::printf(" (%+.4f%%)", 100 * (b.e.total - a.e.total) / std::abs(a.e.total));
  std::printf("\n");
}

} // namespace

int info_command(const std::string& path, bool layout, bool keys) {
  if (keys) {
    if (!path.empty() || layout)
      throw InputError("smpm info --keys takes no file and no --layout (it prints the input's "
                       "keys)");
    std::ostringstream text;
    write_input_keys(text);
    std::fputs(text.str().c_str(), stdout);
    return 0;
  }
  if (layout) {
    if (!path.empty())
      throw InputError("smpm info --layout takes no file (it prints the layout of every run file)");
    print_layout();
    return 0;
  }
  if (path.empty())
    throw InputError("smpm info: give a run file (or --layout)");
  const StoredRun run = read_stored_run(path);
  std::printf("file:     %s\nversion:  %s\nstatus:   %s\n", path.c_str(), run.version.c_str(),
              run.status.c_str());
  std::printf("frames:   %zu", run.frame_times.size());
  if (!run.frame_times.empty())
    std::printf(" (t = %.17g ... %.17g)", run.frame_times.front(), run.frame_times.back());
  std::printf("\n");
  print_energies(run);
  for (const auto& o : run.overrides)
    std::printf("override: %s\n", o.c_str());
  std::printf("contents: (of the last complete frame; every frame holds the same objects)\n");
  for (const FileObject& o : walk_run_file(path))
    std::printf("  %-44s %-14s %s\n", o.path.c_str(), o.shape.c_str(),
                o.entry ? o.entry->what : "(not of the sparsempm layout)");
  std::printf("input:\n%s\n", run.input.c_str());
  return 0;
}

} // namespace smpm::app
