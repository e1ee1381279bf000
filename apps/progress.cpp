// SPDX-License-Identifier: BSD-3-Clause
#include "progress.hpp"

#include <algorithm>
#include <cmath>

namespace smpm::app {

Progress::Progress(std::FILE* out, bool terminal)
    : out_(out), terminal_(terminal), start_(std::chrono::steady_clock::now()), last_draw_(start_) {
}

void Progress::update(long step, double t, double t0, double end) {
  const auto now = std::chrono::steady_clock::now();
  if (first_step_ < 0)
    first_step_ = step - 1;
  const double fraction = std::clamp((t - t0) / std::max(end - t0, 1e-300), 0.0, 1.0);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? double(step - first_step_) / elapsed : 0.0;
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
  if (terminal_) {
    if (fraction < 1 && now - last_draw_ < std::chrono::milliseconds(100))
      return;
    last_draw_ = now;
    const int width = 30, filled = int(std::lround(fraction * width));
    std::fprintf(out_, "\r[%.*s%.*s] %5.1f%%  step %ld  t = %.6g  %.0f steps/s  ETA %.0f s   ",
                 filled, "##############################", width - filled,
                 "                              ", 100 * fraction, step, t, rate, eta);
    std::fflush(out_);
    return;
  }
  const int decile = int(std::floor(fraction * 10 + 1e-9));
  if (decile > last_decile_) {
    last_decile_ = decile;
    std::fprintf(out_, "%3d%%  step %ld  t = %.6g  %.0f steps/s  ETA %.0f s\n", 10 * decile, step,
                 t, rate, eta);
    std::fflush(out_);
  }
}

void Progress::finish() {
  if (terminal_)
    std::fprintf(out_, "\n");
}

} // namespace smpm::app
