#include "rasterizer/image.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include "rasterizer/raster.h"
#include "tables/exr_io.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/png.h"

namespace ganzfeld::raster {

namespace fs = std::filesystem;

Image::Image(int w, int h, const Rgb& fill) : width(w), height(h) {
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    throw InputError("image size " + std::to_string(w) + "x" + std::to_string(h) +
                     " is invalid; allowed: width and height in 1.." + std::to_string(kMaxImageSide));
  rgb.resize(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t p = 0; p < rgb.size(); p += 3)
    for (int c = 0; c < 3; ++c) rgb[p + c] = static_cast<float>(fill[c]);
}

void blit(const Image& src, Image& dst, int x0, int y0) {
  for (int y = 0; y < src.height; ++y) std::copy_n(src.at(0, y), 3 * src.width, dst.at(x0, y0 + y));
}

double srgb_encode(double linear) noexcept {
  const double x = std::clamp(std::isnan(linear) ? 0.0 : linear, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

unsigned char srgb_byte(double linear) noexcept {
  return static_cast<unsigned char>(std::lround(255.0 * srgb_encode(linear)));
}

namespace {

double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

void write_png(const Image& image, const std::string& file) {
  std::vector<std::uint8_t> bytes(image.rgb.size());
  for (std::size_t k = 0; k < bytes.size(); ++k) bytes[k] = srgb_byte(image.rgb[k]);
  util::write_png_rgb8(file, image.width, image.height, bytes.data());
}

void write_exr(const Image& image, const std::string& file) {
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  const char* names[3] = {"R", "G", "B"};
  Imf::FrameBuffer frame;
  const std::size_t pixel = 3 * sizeof(float);
  // OpenEXR's Slice takes a non-const pointer but only reads from it when writing.
  char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
    frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), pixel, pixel * image.width));
  }
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(image.height);
}

}  // namespace

ImageFormat image_format(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return ImageFormat::png;
  if (ext == ".exr") return ImageFormat::exr;
  throw InputError("cannot write image '" + path + "': unknown extension '" + ext + "'; allowed: .png, .exr");
}

void write_image(const Image& image, const std::string& path) {
  const ImageFormat format = image_format(path);
  if (image.width < 1 || image.height < 1 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw InputError("cannot write image '" + path + "': the image is empty (" + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + ")");
  check_writable(path);
  write_atomically(
      path,
      [&](const std::string& temp) {
        if (format == ImageFormat::png) write_png(image, temp);
        else write_exr(image, temp);
      },
      "image");
}

Image read_image(const std::string& path) {
  const ImageFormat format = image_format(path);
  try {
    if (format == ImageFormat::png) {
      const util::Rgb8Image png = util::read_png_rgb8(path);
      Image image(png.width, png.height);
      for (std::size_t k = 0; k < png.rgb.size(); ++k)
        image.rgb[k] = static_cast<float>(srgb_decode(png.rgb[k] / 255.0));
      return image;
    }
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    Image image(dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1);
    const char* names[3] = {"R", "G", "B"};
    Imf::FrameBuffer frame;
    const std::size_t pixel = 3 * sizeof(float);
    char* base = reinterpret_cast<char*>(image.rgb.data()) -
                 (static_cast<std::ptrdiff_t>(dw.min.y) * image.width + dw.min.x) * static_cast<std::ptrdiff_t>(pixel);
    for (int c = 0; c < 3; ++c)
      frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), pixel, pixel * image.width));
    in.setFrameBuffer(frame);
    in.readPixels(dw.min.y, dw.max.y);
    return image;
  } catch (const InputError&) { throw; } catch (const std::exception& e) {
    throw InputError("cannot read image '" + path + "': " + one_line(e.what()));
  }
}

}  // namespace ganzfeld::raster
