// SPDX-License-Identifier: BSD-3-Clause
#include "png_image.hpp"

#include <png.h>

#include <algorithm>
#include <stdexcept>

namespace smpm::detail {

GreyImage read_grey_png(const std::string& path,
                        const std::function<void(int width, int height)>& check) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    const std::string message = image.message;
    png_image_free(&image); // safe when libpng has freed it already
    throw std::runtime_error(message);
  }
  image.format = PNG_FORMAT_GRAY;
  try {
    check(int(std::min<png_uint_32>(image.width, 1u << 30)),
          int(std::min<png_uint_32>(image.height, 1u << 30)));
  } catch (...) {
    png_image_free(&image);
    throw;
  }
  GreyImage out;
  out.width = int(image.width);
  out.height = int(image.height);
  out.level.resize(PNG_IMAGE_SIZE(image));
  const png_color white{255, 255, 255}; // transparent pixels read as white (empty)
  if (!png_image_finish_read(&image, &white, out.level.data(), 0, nullptr)) {
    const std::string message = image.message;
    png_image_free(&image);
    throw std::runtime_error(message);
  }
  return out;
}

} // namespace smpm::detail
