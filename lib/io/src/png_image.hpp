// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Grey-level images read with libpng (bitmap bodies, [[body]] region = "image").

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace smpm::detail {

/// An 8-bit grey image: `width` × `height` levels, row 0 at the top (as stored in the file).
struct GreyImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> level; ///< row-major, level[row * width + col]
  std::uint8_t at(int col, int row) const {
    return level[size_t(row) * size_t(width) + size_t(col)];
  }
};

/// Reads a PNG of any colour type and bit depth as 8-bit grey levels (libpng's simplified API
/// converts colour to grey and composes transparency on white). `check` sees the size its header
/// claims before any pixel buffer is made, and throws to refuse it. Throws std::runtime_error
/// with libpng's message when the file cannot be read or is not a PNG.
GreyImage read_grey_png(const std::string& path,
                        const std::function<void(int width, int height)>& check);

} // namespace smpm::detail
