#include "util/png.h"

#include <png.h>

#include <stdexcept>

namespace ganzfeld::util {

namespace {
[[noreturn]] void fail(png_image& image) {
  const std::string why = image.message;
  png_image_free(&image);
  throw std::runtime_error(why.empty() ? "libpng failed" : why);
}
}  // namespace

void write_png_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&image, path.c_str(), 0, rgb, width * 3, nullptr)) fail(image);
  png_image_free(&image);
}

Rgb8Image read_png_rgb8(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) fail(image);
  image.format = PNG_FORMAT_RGB;
  Rgb8Image out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr)) fail(image);
  return out;
}

}  // namespace ganzfeld::util
