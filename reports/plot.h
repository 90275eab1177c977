// Minimal log-log plotting for generated reports (tradeoff, performance): an RGB canvas, a
// 5x7 bitmap font (upper case), decade axes and atomic PNG output via libpng. Enough for
// legible work-precision plots without another dependency.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace ganzfeld::plot {

struct Rgb {
  std::uint8_t r, g, b;
};
constexpr Rgb kWhite{255, 255, 255}, kBlack{0, 0, 0}, kGrid{225, 225, 225}, kGrey{110, 110, 110};
// Colour-blind-safe palette (Okabe & Ito, 2008): one colour per mapping set x encoding.
constexpr Rgb kPalette[] = {{0, 114, 178},   {230, 159, 0},  {0, 158, 115},  {213, 94, 0},
                            {204, 121, 167}, {86, 180, 233}, {240, 228, 66}, {0, 0, 0}};

// Each glyph: 7 rows of 5 columns, '#' = ink.
inline const std::map<char, const char*>& font() {
  static const std::map<char, const char*> glyphs = {
      {'0', ".###.#...##..###.#.###..##...#.###."}, {'1', "..#...##....#....#....#....#...###."},
      {'2', ".###.#...#....#...#...#...#...#####"}, {'3', "#####...#...#.....#.....##...#.###."},
      {'4', "...#...##..#.#.#..#.#####...#....#."}, {'5', "######....####.....#....##...#.###."},
      {'6', "..##..#...#....####.#...##...#.###."}, {'7', "#####....#...#...#...#....#....#..."},
      {'8', ".###.#...##...#.###.#...##...#.###."}, {'9', ".###.#...##...#.####....#...#..##.."},
      {'A', ".###.#...##...#######...##...##...#"}, {'B', "####.#...##...#####.#...##...#####."},
      {'C', ".###.#...##....#....#....#...#.###."}, {'D', "###..#..#.#...##...##...##..#.###.."},
      {'E', "######....#....####.#....#....#####"}, {'F', "######....#....####.#....#....#...."},
      {'G', ".###.#...##....#.####...##...#.####"}, {'H', "#...##...##...#######...##...##...#"},
      {'I', ".###...#....#....#....#....#...###."}, {'J', "..###...#....#....#....#.#..#..##.."},
      {'K', "#...##..#.#.#..##...#.#..#..#.#...#"}, {'L', "#....#....#....#....#....#....#####"},
      {'M', "#...###.###.#.##.#.##...##...##...#"}, {'N', "#...##...###..##.#.##..###...##...#"},
      {'O', ".###.#...##...##...##...##...#.###."}, {'P', "####.#...##...#####.#....#....#...."},
      {'Q', ".###.#...##...##...##.#.##..#..##.#"}, {'R', "####.#...##...#####.#.#..#..#.#...#"},
      {'S', ".#####....#.....###.....#....#####."}, {'T', "#####..#....#....#....#....#....#.."},
      {'U', "#...##...##...##...##...##...#.###."}, {'V', "#...##...##...##...##...#.#.#...#.."},
      {'W', "#...##...##...##.#.##.#.##.#.#.#.#."}, {'X', "#...##...#.#.#...#...#.#.#...##...#"},
      {'Y', "#...##...#.#.#...#....#....#....#.."}, {'Z', "#####....#...#...#...#...#....#####"},
      {' ', "..................................."}, {'.', "..........................##...##.."},
      {'-', "................###................"}, {'+', ".......#....#..#####..#....#......."},
      {',', "....................##....#...#...."}, {':', "......##...##.........##...##......"},
      {'(', "...#...#...#....#....#.....#.....#."}, {')', ".#.....#.....#....#....#...#...#..."},
      {'/', ".........#...#...#...#...#........."}, {'=', "..........#####.....#####.........."},
      {'_', "..............................#####"}, {'|', "..#....#....#....#....#....#....#.."},
      {'*', "......#..#.#.#.###.#.#.#..#........"}, {'?', ".###.#...#....#...#...#.........#.."},
      {'%', "##...##..#...#...#...#...#..##...##"}, {'<', "...#...#...#...#.....#.....#.....#."},
      {'>', ".#.....#.....#.....#...#...#...#..."}, {';', "......##...##.........##....#...#..."}};
  return glyphs;
}

class Canvas {
 public:
  Canvas(int width, int height) : w_(width), h_(height), rgb_(static_cast<std::size_t>(width) * height * 3, 255) {}
  int width() const { return w_; }
  int height() const { return h_; }
  const std::uint8_t* data() const { return rgb_.data(); }

  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    std::uint8_t* p = &rgb_[(static_cast<std::size_t>(y) * w_ + x) * 3];
    p[0] = c.r, p[1] = c.g, p[2] = c.b;
  }
  void fill(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) set(x, y, c);
  }
  void line(int x0, int y0, int x1, int y1, Rgb c, int thickness = 1) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    while (true) {
      fill(x0 - thickness / 2, y0 - thickness / 2, x0 + (thickness - 1) / 2, y0 + (thickness - 1) / 2, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) err += dy, x0 += sx;
      if (e2 <= dx) err += dx, y0 += sy;
    }
  }
  /// Marker shapes: 0 circle, 1 square, 2 diamond, 3 triangle; filled, with a dark outline.
  void marker(int cx, int cy, int shape, Rgb c, int r = 5) {
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x) {
        const bool in = inside(shape, x, y, r),
                   edge = in && (!inside(shape, x - 1, y, r) || !inside(shape, x + 1, y, r) ||
                                 !inside(shape, x, y - 1, r) || !inside(shape, x, y + 1, r));
        if (in) set(cx + x, cy + y, edge ? Rgb{40, 40, 40} : c);
      }
  }
  /// Text with its top-left corner at (x, y); `vertical` runs bottom to top (rotated 90° CCW).
  void text(int x, int y, const std::string& s, Rgb c, int scale = 2, bool vertical = false) {
    for (std::size_t k = 0; k < s.size(); ++k) {
      char ch = static_cast<char>(std::toupper(static_cast<unsigned char>(s[k])));
      auto it = font().find(ch);
      const char* g = it == font().end() ? font().at('?') : it->second;
      for (int row = 0; row < 7; ++row)
        for (int col = 0; col < 5; ++col) {
          if (g[row * 5 + col] != '#') continue;
          const int along = static_cast<int>(k) * 6 * scale + col * scale;
          for (int a = 0; a < scale; ++a)
            for (int b = 0; b < scale; ++b) {
              if (vertical) set(x + row * scale + b, y - along - a, c);
              else set(x + along + a, y + row * scale + b, c);
            }
        }
    }
  }
  static int text_width(const std::string& s, int scale = 2) { return static_cast<int>(s.size()) * 6 * scale - scale; }

 private:
  static bool inside(int shape, int x, int y, int r) {
    switch (shape % 4) {
      case 0: return x * x + y * y <= r * r;
      case 1: return std::abs(x) <= r - 1 && std::abs(y) <= r - 1;
      case 2: return std::abs(x) + std::abs(y) <= r;
      default: return y <= r - 1 && 2 * std::abs(x) <= y + r;
    }
  }
  int w_, h_;
  std::vector<std::uint8_t> rgb_;
};

inline std::string decade_label(int e) { return "1e" + std::to_string(e); }

struct LogAxis {
  int lo = 0, hi = 1;  // decades
  static LogAxis of(const std::vector<double>& values) {
    double mn = std::numeric_limits<double>::infinity(), mx = 0.0;
    for (double v : values)
      if (v > 0) mn = std::min(mn, v), mx = std::max(mx, v);
    if (!(mx > 0)) return {};
    LogAxis a{static_cast<int>(std::floor(std::log10(mn))), static_cast<int>(std::ceil(std::log10(mx)))};
    if (a.hi <= a.lo) a.hi = a.lo + 1;
    return a;
  }
  double t(double v) const {  // 0..1 along the axis; non-positive values sit at the low end
    if (!(v > 0)) return 0.0;
    return std::clamp((std::log10(v) - lo) / (hi - lo), 0.0, 1.0);
  }
};

struct Panel {
  int x0, y0, x1, y1;  // plot area, pixels (y0 top)
};

/// Grid, ticks, decade labels, frame and axis labels of one log-log panel; returns nothing, the
/// caller maps data with ax.t / ay.t into the panel.
void draw_log_axes(Canvas& cv, const Panel& p, const LogAxis& ax, const LogAxis& ay, const std::string& x_label,
                   const std::string& y_label);

/// Writes the canvas as an RGB PNG, atomically (util/atomic_file.h).
void write_png(const Canvas& cv, const std::string& path);

}  // namespace ganzfeld::plot
