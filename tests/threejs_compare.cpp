// tests/threejs_test.sh's judge: what three.js with js/ganzfeld-three drew in the browser against
// ganzfeld's own code, from the same tables.
//
//   threejs_compare pixels REF.png PAGE.html [--expect-mismatch | --report]
//       the page's 8-bit sRGB canvas (examples/three/?test=1: RGBA, rows top first, base64 in
//       <pre id="result">) against `ganzfeld render`'s PNG (linear clamped to [0, 1], sRGB, 8-bit)
//       of the same scene file. Compared: every pixel either covers (page alpha > 0, or a reference
//       pixel other than the black background). Within: every channel within kLsb. Passes when at
//       least kTargetFraction of them are within (--expect-mismatch: when fewer than
//       kMismatchFraction are; --report: always, for a documented difference); lists every pixel
//       beyond, with its kind: "coverage" (one side covers it, the other not: the silhouette of
//       three.js's tessellated sphere against render's) or "shading".
//   threejs_compare lookups CACHE PAGE.html
//       the GPU lookups of js/ganzfeld-three/test/browser/lookup.js against tables::sample (the
//       function `ganzfeld sample` prints) of the same tables, read from the cache directory
//       `export-glsl --scene --cache CACHE` baked them into, at the page's points (local frame); for
//       a table whose bound covers the hardware filter, the closest of that and its 8-bit emulations.
//       Bound per value: kFloatRelative x the table's largest value + kFloatAbsolute (below).
//
// One summary line per comparison, then "json: {...}" with the numbers (scripts/gen-three-docs).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tables/exr_io.h"
#include "tables/sample.h"
#include "util/png.h"

namespace {

/// The target: 99% of the pixels within 2 of 255 in every channel.
constexpr int kLsb = 2;
constexpr double kTargetFraction = 0.99;
/// A changed picture (three.js without the module) must differ at many pixels, not a stray few.
constexpr double kMismatchFraction = 0.9;
/// GPU float against CPU double on the same stored values, relative to the table's scale (its
/// largest value), since the lobe-frame coordinates (two atan2, two asinh) move a lookup by a
/// fraction of the table's range, not of the value at the point: 2e-5, a tenth of the float part of
/// tests/gl_shader_test.cpp and ~30 x the largest difference measured on SwiftShader (7e-7 of a
/// range of 1: docs/three.md); plus an absolute floor for tables of tiny values.
constexpr double kFloatRelative = 2e-5;
constexpr double kFloatAbsolute = 1e-6;
/// The count: at least this many points per table.
constexpr std::size_t kMinPoints = 1000;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The JSON in <pre id="result">...</pre> of a dumped DOM, its HTML escapes undone.
nlohmann::json page_result(const std::string& path) {
  const std::string dom = read_file(path);
  const std::size_t open = dom.find("<pre id=\"result\"");
  const std::size_t begin = dom.find('>', open), end = dom.find("</pre>", begin);
  if (open == std::string::npos || begin == std::string::npos || end == std::string::npos)
    throw std::runtime_error("no <pre id=\"result\"> in the page");
  std::string text = dom.substr(begin + 1, end - begin - 1);
  for (const auto& [escape, c] : {std::pair{"&lt;", "<"}, std::pair{"&gt;", ">"}, std::pair{"&amp;", "&"}})
    for (std::size_t at; (at = text.find(escape)) != std::string::npos;)
      text.replace(at, std::string(escape).size(), c);
  nlohmann::json page = nlohmann::json::parse(text);
  if (page.contains("error")) throw std::runtime_error("the page failed: " + page["error"].get<std::string>());
  if (!page.value("webgl2", false))
    throw std::runtime_error("the page reports no WebGL2: " + page.dump().substr(0, 200));
  return page;
}

std::vector<std::uint8_t> base64(const std::string& text) {
  std::vector<std::uint8_t> out;
  int bits = 0, value = 0;
  for (char c : text) {
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(alphabet, c);
    if (c == '=' || at == nullptr || c == '\0') continue;
    value = (value << 6) | static_cast<int>(at - alphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((value >> bits) & 0xff));
    }
  }
  return out;
}

int compare_pixels(const std::string& reference_path, const std::string& page_path, const std::string& mode) {
  const ganzfeld::util::Rgb8Image reference = ganzfeld::util::read_png_rgb8(reference_path);
  const nlohmann::json page = page_result(page_path);
  const int w = page.at("width"), h = page.at("height");
  if (w != reference.width || h != reference.height)
    throw std::runtime_error("page " + std::to_string(w) + "x" + std::to_string(h) + " but reference " +
                             std::to_string(reference.width) + "x" + std::to_string(reference.height));
  const std::vector<std::uint8_t> rgba = base64(page.at("rgba").get<std::string>());
  if (rgba.size() != 4u * w * h)
    throw std::runtime_error("the page's pixels are not " + std::to_string(4 * w * h) + " bytes");
  int compared = 0, within = 0, coverage = 0, worst = 0;
  std::map<int, int> histogram;  // largest channel difference -> pixels
  std::vector<std::string> beyond;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgba[4 * (static_cast<std::size_t>(y) * w + x)];
      const std::uint8_t* r = &reference.rgb[3 * (static_cast<std::size_t>(y) * w + x)];
      const bool page_covers = p[3] > 0, reference_covers = r[0] || r[1] || r[2];
      if (!page_covers && !reference_covers) continue;
      ++compared;
      int difference = 0;
      for (int c = 0; c < 3; ++c) difference = std::max(difference, std::abs(int{p[c]} - int{r[c]}));
      ++histogram[difference <= kLsb ? difference
                  : difference <= 4  ? 4
                  : difference <= 8  ? 8
                  : difference <= 16 ? 16
                                     : 255];
      worst = std::max(worst, difference);
      if (difference <= kLsb) {
        ++within;
        continue;
      }
      const bool silhouette = page_covers != reference_covers;
      coverage += silhouette;
      char line[160];
      std::snprintf(line, sizeof line, "  (%d, %d) %s: page (%d, %d, %d, a %d), render (%d, %d, %d): %d LSB", x, y,
                    silhouette ? "coverage" : "shading", p[0], p[1], p[2], p[3], r[0], r[1], r[2], difference);
      beyond.push_back(line);
    }
  if (compared == 0) throw std::runtime_error("no pixel covered by either image");
  const double fraction = static_cast<double>(within) / compared;
  std::printf(
      "%s vs %s: %d pixels covered, %d (%.3f%%) within %d LSB in every channel, %d beyond (%d at the silhouette's "
      "coverage, %d shading), largest %d LSB\n",
      page_path.c_str(), reference_path.c_str(), compared, within, 100.0 * fraction, kLsb, compared - within, coverage,
      compared - within - coverage, worst);
  for (const std::string& line : beyond) std::printf("%s\n", line.c_str());
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [d, n] : histogram) counts[std::to_string(d)] = n;
  std::printf("json: %s\n", nlohmann::json{{"page", page_path},
                                           {"covered", compared},
                                           {"within", within},
                                           {"fraction", fraction},
                                           {"coverage", coverage},
                                           {"largest", worst},
                                           {"histogram", counts}}
                                .dump()
                                .c_str());
  if (mode == "--report") return 0;
  if (mode == "--expect-mismatch") return fraction < kMismatchFraction ? 0 : 1;
  return fraction >= kTargetFraction ? 0 : 1;
}

int compare_lookups(const std::string& cache, const std::string& page_path) {
  using namespace ganzfeld;
  std::map<std::string, tables::Table> by_model_law;  // "SPEC law" -> table
  for (const auto& entry : std::filesystem::directory_iterator(cache)) {
    if (entry.path().extension() != ".exr") continue;
    tables::Table table = tables::read_table(entry.path().string());
    by_model_law.emplace(table.model + " " + to_string(table.law), std::move(table));
  }
  const nlohmann::json page = page_result(page_path);
  const auto& points = page.at("points");
  if (points.size() < kMinPoints) throw std::runtime_error("fewer than " + std::to_string(kMinPoints) + " points");
  const char* keys[4] = {"g0", "g1", "h0", "h1"};
  int failures = 0;
  nlohmann::json summary = nlohmann::json::array();
  for (const auto& set : page.at("sets")) {
    const auto& values = set.at("values");
    for (int k = 0; k < 4; ++k) {
      const std::string model = set.at("models").at(keys[k]);
      const auto found = by_model_law.find(model + " " + (k < 2 ? "g" : "h"));
      if (found == by_model_law.end()) throw std::runtime_error("no table of " + model + " in " + cache);
      const tables::Table& table = found->second;
      const double scale = *std::max_element(table.value.begin(), table.value.end(),
                                             [](float a, float b) { return std::abs(a) < std::abs(b); });
      const double bound = kFloatRelative * std::abs(scale) + kFloatAbsolute;
      double worst = 0.0;
      std::size_t worst_at = 0, beyond = 0;
      for (std::size_t p = 0; p < points.size(); ++p) {
        const Vec3 i{points[p][0].get<double>(), points[p][1].get<double>(), points[p][2].get<double>()};
        const Vec3 j{points[p][3].get<double>(), points[p][4].get<double>(), points[p][5].get<double>()};
        const double gpu = values[4 * p + k].get<double>();
        double difference = std::abs(gpu - tables::sample(table, i, j).value);
        // A table whose bound covers the hardware filter is read with one texture(): the GPU's filter
        // does the full-precision blend or one of the two 8-bit emulations (`sample --hardware-filter`).
        if (table.filter == tables::Filter::hardware)
          for (tables::WeightRounding r : {tables::WeightRounding::nearest, tables::WeightRounding::truncate})
            difference = std::min(difference, std::abs(gpu - tables::sample(table, i, j, r).value));
        if (!(difference <= bound)) ++beyond;
        if (!(difference <= worst)) worst = difference, worst_at = p;
      }
      std::printf(
          "%s law %s: %zu points, max |GPU - sample| %.3g at point %zu (%.2f of the bound %.3g = %.0e x the "
          "table's largest value %.3g + %.0e; the table's lookup error %.3g), %zu beyond\n",
          model.c_str(), k < 2 ? "g" : "h", points.size(), worst, worst_at, worst / bound, bound, kFloatRelative, scale,
          kFloatAbsolute, table.lookup_error, beyond);
      summary.push_back({{"model", model},
                         {"law", k < 2 ? "g" : "h"},
                         {"points", points.size()},
                         {"max", worst},
                         {"bound", bound},
                         {"lookup_error", table.lookup_error},
                         {"beyond", beyond}});
      failures += beyond > 0;
    }
  }
  std::printf("json: %s\n", summary.dump().c_str());
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() >= 3 && args.size() <= 4 && args[0] == "pixels" &&
        (args.size() == 3 || args[3] == "--expect-mismatch" || args[3] == "--report"))
      return compare_pixels(args[1], args[2], args.size() == 4 ? args[3] : "");
    if (args.size() == 3 && args[0] == "lookups") return compare_lookups(args[1], args[2]);
    std::fprintf(stderr,
                 "usage: threejs_compare pixels REF.png PAGE.html [--expect-mismatch | --report]\n"
                 "       threejs_compare lookups CACHE_DIR PAGE.html\n");
    return 2;
  } catch (const std::exception& e) {
    std::printf("%s: %s\n", args.size() > 2 ? args[2].c_str() : "threejs_compare", e.what());
    return 1;
  }
}
