// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Progress of a run: a bar on a terminal, a plain line every 10% otherwise.

#include <chrono>
#include <cstdio>

namespace smpm::app {

class Progress {
public:
  /// Writes to `out`; `terminal` selects the bar (redrawn at most 10 times a second).
  Progress(std::FILE* out, bool terminal);
  /// Reports step `step` at simulated time t of [t0, end].
  void update(long step, double t, double t0, double end);
  /// Ends the bar's line.
  void finish();

private:
  std::FILE* out_;
  bool terminal_;
  int last_decile_ = 0;
  long first_step_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

} // namespace smpm::app
