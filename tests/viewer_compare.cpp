// tests/viewer_test.sh's judge: the sphere the viewer rendered in the browser (WebGL2, its float
// framebuffer, written as JSON into <pre id="result"> and dumped with --dump-dom) against the
// software rasterizer's image of the same scene (`ganzfeld render`, linear EXR), pixel by pixel.
//
//   viewer_compare REF.exr PAGE.html [--expect-mismatch] [--absolute A] [--srgb-lsb N]
//
// Both shade the same stored table values (the page fetches the cache file `render --cache`
// wrote, as JSON, and uploads it as R32F) with the same formulas, so they differ only by single-
// vs double-precision arithmetic: the GPU's float ray cast, axis mappings, interpolation weights
// and pow. The bound per pixel is that of tests/gl_shader_test.cpp's float part:
//   |page - render| <= kFloatRelative |render| + kFloatAbsolute.
// --absolute A replaces kFloatAbsolute by A (both sides integrated per pixel to a tolerance:
// their sum). --srgb-lsb N compares what the page shows instead: its canvas's 8-bit sRGB (the
// test mode's display=1) against `render`'s linear values encoded as its PNG files are
// (raster::srgb_byte), within N least significant bits.
// Pixels the page marks as near the silhouette (mask 0.5: j.n < 0.05, where the CPU's coverage
// test uses the tessellated sphere) and background pixels are not compared; at least
// kMinCompared pixels must be. Exit 0 when every compared pixel is within the bound (or, with
// --expect-mismatch, when more than kMinMismatchFraction of them are not: a parameter change
// must change the image), 1 otherwise; one summary line either way.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rasterizer/image.h"

namespace {

constexpr double kFloatRelative = 2e-4;  // float pipeline vs double, as tests/gl_shader_test.cpp
constexpr double kFloatAbsolute = 1e-6;
/// A 64 x 64 view of the figure's sphere covers ~1,500 pixels; far fewer means a wrong camera.
constexpr int kMinCompared = 1000;
/// A changed parameter must move a visible part of the sphere, not a stray pixel or two.
constexpr double kMinMismatchFraction = 0.05;

std::string read_file(const char* path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The JSON in <pre id="result">...</pre> of a dumped DOM, its HTML escapes undone.
nlohmann::json page_result(const std::string& dom) {
  const std::string open = "<pre id=\"result\">";
  const std::size_t begin = dom.find(open), end = dom.find("</pre>", begin);
  if (begin == std::string::npos || end == std::string::npos)
    throw std::runtime_error("no <pre id=\"result\"> in the page");
  std::string text = dom.substr(begin + open.size(), end - begin - open.size());
  for (const auto& [escape, c] : {std::pair{"&lt;", "<"}, std::pair{"&gt;", ">"}, std::pair{"&amp;", "&"}})
    for (std::size_t at; (at = text.find(escape)) != std::string::npos;)
      text.replace(at, std::string(escape).size(), c);
  return nlohmann::json::parse(text);
}

}  // namespace

int main(int argc, char** argv) {
  bool expect_mismatch = false, usage = argc < 3;
  double absolute = kFloatAbsolute;
  int lsb = -1;  // >= 0: compare the page's 8-bit sRGB within lsb
  for (int k = 3; k < argc && !usage; ++k) {
    const std::string flag = argv[k];
    if (flag == "--expect-mismatch") expect_mismatch = true;
    else if (flag == "--absolute" && k + 1 < argc) absolute = std::atof(argv[++k]);
    else if (flag == "--srgb-lsb" && k + 1 < argc) lsb = std::atoi(argv[++k]);
    else usage = true;
  }
  if (usage) {
    std::fprintf(stderr, "usage: viewer_compare REF.exr PAGE.html [--expect-mismatch] [--absolute A] [--srgb-lsb N]\n");
    return 2;
  }
  try {
    const ganzfeld::raster::Image reference = ganzfeld::raster::read_image(argv[1]);
    const nlohmann::json page = page_result(read_file(argv[2]));
    if (page.contains("error")) throw std::runtime_error("the page failed: " + page["error"].get<std::string>());
    if (!page.value("webgl2", false))
      throw std::runtime_error("the page reports no WebGL2: " + page.dump().substr(0, 200));
    const int w = page.at("width"), h = page.at("height");
    if (w != reference.width || h != reference.height)
      throw std::runtime_error("page " + std::to_string(w) + "x" + std::to_string(h) + " but reference " +
                               std::to_string(reference.width) + "x" + std::to_string(reference.height));
    const auto& value = page.at("value");
    const auto& mask = page.at("mask");
    if (lsb >= 0) {
      const auto& shown = page.at("srgb");
      int compared = 0, worst = 0, beyond = 0;
      std::vector<int> histogram(4, 0);  // |difference| 0, 1, 2, more
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t k = static_cast<std::size_t>(y) * w + x;
          if (mask[k].get<double>() != 1.0) continue;
          const int difference = std::abs(shown[k].get<int>() - ganzfeld::raster::srgb_byte(reference.at(x, y)[0]));
          ++compared;
          ++histogram[std::min(difference, 3)];
          worst = std::max(worst, difference);
          beyond += difference > lsb;
        }
      std::printf(
          "%s: %d pixels compared as shown (8-bit sRGB): largest difference %d LSB (%d at 0, %d at 1, %d at 2, "
          "%d beyond); allowed %d\n",
          argv[2], compared, worst, histogram[0], histogram[1], histogram[2], histogram[3], lsb);
      if (compared < kMinCompared) throw std::runtime_error("too few sphere pixels compared");
      return beyond == 0 ? 0 : 1;
    }
    int compared = 0, beyond = 0, worst_x = 0, worst_y = 0;
    double worst = 0.0, worst_relative = 0.0, worst_excess = 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t k = static_cast<std::size_t>(y) * w + x;
        if (mask[k].get<double>() != 1.0) continue;
        const double cpu = reference.at(x, y)[0], gpu = value[k].get<double>();
        const double difference = std::abs(gpu - cpu);
        ++compared;
        const double excess = difference / (kFloatRelative * std::abs(cpu) + absolute);
        if (excess > 1.0) ++beyond;
        if (excess > worst_excess) worst_excess = excess, worst_x = x, worst_y = y;
        worst = std::max(worst, difference);
        worst_relative = std::max(worst_relative, difference / std::max(std::abs(cpu), 1e-12));
      }
    std::printf(
        "%s: %d pixels compared, %d beyond %.0e relative + %.0e; max |page - render| %.3g (%.3g relative); "
        "nearest the bound: pixel (%d, %d), page %.9g, render %.9g (%.2f of the bound)\n",
        argv[2], compared, beyond, kFloatRelative, absolute, worst, worst_relative, worst_x, worst_y,
        value[static_cast<std::size_t>(worst_y) * w + worst_x].get<double>(), reference.at(worst_x, worst_y)[0],
        worst_excess);
    if (compared < kMinCompared) throw std::runtime_error("too few sphere pixels compared");
    const bool mismatch = beyond > kMinMismatchFraction * compared;
    return (expect_mismatch ? mismatch : beyond == 0) ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("%s: %s\n", argv[2], e.what());
    return 1;
  }
}
