#include "reports/plot.h"

#include <stdexcept>

#include "util/atomic_file.h"
#include "util/png.h"

namespace ganzfeld::plot {

void draw_log_axes(Canvas& cv, const Panel& p, const LogAxis& ax, const LogAxis& ay, const std::string& x_label,
                   const std::string& y_label) {
  auto px = [&](double v) { return p.x0 + static_cast<int>(std::lround(ax.t(v) * (p.x1 - p.x0))); };
  auto py = [&](double v) { return p.y1 - static_cast<int>(std::lround(ay.t(v) * (p.y1 - p.y0))); };
  // Grid, minor ticks, decade labels.
  const int x_step = (ax.hi - ax.lo) > 8 ? 2 : 1, y_step = (ay.hi - ay.lo) > 8 ? 2 : 1;
  for (int e = ax.lo; e <= ax.hi; ++e) {
    const int x = px(std::pow(10.0, e));
    cv.line(x, p.y0, x, p.y1, kGrid);
    cv.line(x, p.y1, x, p.y1 + 6, kBlack);
    if ((e - ax.lo) % x_step == 0) {
      const std::string l = decade_label(e);
      cv.text(x - Canvas::text_width(l) / 2, p.y1 + 12, l, kBlack);
    }
    if (e < ax.hi)
      for (int m = 2; m <= 9; ++m)
        cv.line(px(m * std::pow(10.0, e)), p.y1, px(m * std::pow(10.0, e)), p.y1 + 3, kBlack);
  }
  for (int e = ay.lo; e <= ay.hi; ++e) {
    const int y = py(std::pow(10.0, e));
    cv.line(p.x0, y, p.x1, y, kGrid);
    cv.line(p.x0 - 6, y, p.x0, y, kBlack);
    if ((e - ay.lo) % y_step == 0) {
      const std::string l = decade_label(e);
      cv.text(p.x0 - 10 - Canvas::text_width(l), y - 7, l, kBlack);
    }
    if (e < ay.hi)
      for (int m = 2; m <= 9; ++m)
        cv.line(p.x0 - 3, py(m * std::pow(10.0, e)), p.x0, py(m * std::pow(10.0, e)), kBlack);
  }
  cv.line(p.x0, p.y0, p.x0, p.y1, kBlack);
  cv.line(p.x0, p.y1, p.x1, p.y1, kBlack);
  cv.line(p.x1, p.y0, p.x1, p.y1, kBlack);
  cv.line(p.x0, p.y0, p.x1, p.y0, kBlack);
  cv.text((p.x0 + p.x1 - Canvas::text_width(x_label)) / 2, p.y1 + 36, x_label, kBlack);
  cv.text(p.x0 - 78, (p.y0 + p.y1 + Canvas::text_width(y_label)) / 2, y_label, kBlack, 2, true);
}

void write_png(const Canvas& cv, const std::string& path) {
  write_atomically(path,
                   [&](const std::string& temp) { util::write_png_rgb8(temp, cv.width(), cv.height(), cv.data()); });
}

}  // namespace ganzfeld::plot
