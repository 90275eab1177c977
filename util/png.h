// The one PNG codec of ganzfeld (libpng's simplified API): 8-bit RGB, rows top to bottom.
// Plots (reports/plot.h) and rendered images (rasterizer/image.h) both go through it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ganzfeld::util {

/// Writes `width`×`height` RGB bytes (3 per pixel, rows top to bottom) to `path` as it is (not
/// atomically: callers wrap it in write_atomically). Throws std::runtime_error with libpng's message.
void write_png_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb);

struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 bytes per pixel, rows top to bottom
};
/// Reads any PNG as 8-bit RGB. Throws std::runtime_error with libpng's message.
Rgb8Image read_png_rgb8(const std::string& path);

}  // namespace ganzfeld::util
