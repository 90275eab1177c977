// Linear RGB float images and their files: OpenEXR (linear radiance, RGB FLOAT) and PNG (8-bit
// sRGB: the linear value clamped to [0, 1] through the sRGB transfer function, nothing else). The format is chosen by
// the file extension; writes are atomic.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace ganzfeld::raster {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< row-major, top row first, 3 floats per pixel, linear radiance

  Image() = default;
  /// Throws InputError unless 1 <= width, height <= 16384.
  Image(int width, int height, const Rgb& fill = {0, 0, 0});
  float* at(int x, int y) { return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
  const float* at(int x, int y) const { return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
};

/// Copies `src` into `dst` with its top-left corner at (x0, y0) (must fit).
void blit(const Image& src, Image& dst, int x0, int y0);

/// sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
double srgb_encode(double linear) noexcept;
/// 8-bit code of srgb_encode(linear), rounded to nearest.
unsigned char srgb_byte(double linear) noexcept;

enum class ImageFormat { png, exr };
/// From the extension (.png, .exr; case-insensitive); InputError naming the path otherwise.
ImageFormat image_format(const std::string& path);

/// Writes a temporary file beside `path` and renames it over `path`; on any failure nothing is
/// left at `path` or beside it and an InputError names the path and the reason. Refuses an
/// empty image and an unknown extension before touching the file system.
void write_image(const Image& image, const std::string& path);

/// Reads an image written by write_image (PNG: decoded back to linear through the inverse
/// sRGB curve; EXR: R, G, B channels). For tests and tools; InputError on failure.
Image read_image(const std::string& path);

}  // namespace ganzfeld::raster
