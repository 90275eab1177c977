#include "reports/disk.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "integrate/laws.h"
#include "models/registry.h"
#include "reports/plot.h"
#include "util/error.h"

namespace ganzfeld {

namespace {

using std::numbers::pi;

/// The (u, v) frame every disk is drawn in: it holds the disks of ω_o from 0 to 90°.
constexpr double kU0 = -1.1, kU1 = 2.1, kV0 = -1.1, kV1 = 1.1;
/// Tone scale: densities down to 10^-kDecades of the row's largest data density are visible.
constexpr double kDecades = 3.0;
/// Grid points per axis over the disk's bounding square for disk_spread.
constexpr int kSpreadGrid = 400;

Vec3 outgoing(double theta_o_deg) { return direction(theta_o_deg * pi / 180.0, 0.0); }

double tone(double p, double top) {
  if (!(p > 0.0) || !(top > 0.0)) return 0.0;
  return std::clamp(1.0 + std::log10(p / top) / kDecades, 0.0, 1.0);
}

}  // namespace

double disk_density(const Model& model, DiskProjection projection, const Vec3& j, const hvd::Uv& h) noexcept {
  if (projection == DiskProjection::orthogonal) {
    const auto i = hvd::incident_from_orthogonal(h, j);
    return i ? model.f(*i, j) : 0.0;
  }
  // The scaling disk is the same unit disk about j_uv: off it, no direction maps there.
  const double du = h.u - j.x, dv = h.v - j.y;
  if (du * du + dv * dv >= 1.0) return 0.0;
  const auto i = hvd::incident_from_scaling(h, j);
  if (!i) return 0.0;
  const double J = hvd::scaling_jacobian(*i, j);
  return J > 0.0 ? model.f(*i, j) * i->z / J : 0.0;
}

void write_disk_figure(const Model& data, const Model* fit, const DiskOptions& options, const std::string& path) {
  if (options.theta_o_deg.empty()) throw InputError("the disk view needs at least one outgoing angle");
  for (double t : options.theta_o_deg)
    if (!(t >= 0.0 && t < 90.0))
      throw InputError("--theta-o " + format_number(t) + " is not allowed; allowed: angles in [0, 90) degrees");
  const int ppu = options.pixels_per_unit, ss = std::max(1, options.samples_per_pixel_axis);
  const int w = static_cast<int>((kU1 - kU0) * ppu), h = static_cast<int>((kV1 - kV0) * ppu);
  const int columns = fit ? 6 : 2, rows = static_cast<int>(options.theta_o_deg.size());
  const int left = 150, top = 60, gap = 10;
  plot::Canvas cv(left + columns * (w + gap), top + rows * (h + gap));
  const char* headers_fit[] = {"ORTHOGONAL: DATA", "FIT", "BOTH", "SCALING: DATA", "FIT", "BOTH"};
  const char* headers_data[] = {"ORTHOGONAL", "SCALING"};
  for (int c = 0; c < columns; ++c)
    cv.text(left + c * (w + gap) + 4, top - 24, fit ? headers_fit[c] : headers_data[c], plot::kBlack);
  cv.text(8, 8, fit ? "RED: DATA  BLUE: FIT  (LOG SCALE, 3 DECADES)" : "DENSITY ON THE DISK (LOG SCALE, 3 DECADES)",
          plot::kGrey);

  for (int r = 0; r < rows; ++r) {
    const Vec3 j = outgoing(options.theta_o_deg[r]);
    const int y0 = top + r * (h + gap);
    cv.text(8, y0 + h / 2 - 7, "THETA_O " + format_number(options.theta_o_deg[r]), plot::kBlack);
    for (int proj = 0; proj < 2; ++proj) {
      const DiskProjection projection = proj == 0 ? DiskProjection::orthogonal : DiskProjection::scaling;
      // Densities per pixel (mean of the supersamples), data and fit.
      std::vector<double> pd(static_cast<std::size_t>(w) * h), pf(pd.size());
      tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
          double sd = 0.0, sf = 0.0;
          for (int a = 0; a < ss; ++a)
            for (int b = 0; b < ss; ++b) {
              const hvd::Uv q{kU0 + (x + (a + 0.5) / ss) / ppu, kV1 - (y + (b + 0.5) / ss) / ppu};
              sd += disk_density(data, projection, j, q);
              if (fit) sf += disk_density(*fit, projection, j, q);
            }
          pd[static_cast<std::size_t>(y) * w + x] = sd / (ss * ss);
          pf[static_cast<std::size_t>(y) * w + x] = sf / (ss * ss);
        }
      });
      const double top_density = *std::max_element(pd.begin(), pd.end());
      const int panels = fit ? 3 : 1;
      for (int k = 0; k < panels; ++k) {
        const int x0 = left + (proj * panels + k) * (w + gap);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const double td = tone(pd[static_cast<std::size_t>(y) * w + x], top_density);
            const double tf = tone(pf[static_cast<std::size_t>(y) * w + x], top_density);
            // Red for the data, blue for the fit, multiplied where both are drawn (purple).
            const double red_d = k == 1 ? 0.0 : td, blue_f = k == 0 ? 0.0 : tf;
            const double r_ch = 1.0 - blue_f, g_ch = (1.0 - red_d) * (1.0 - blue_f), b_ch = 1.0 - red_d;
            cv.set(x0 + x, y0 + y,
                   {static_cast<std::uint8_t>(std::lround(255 * r_ch)), static_cast<std::uint8_t>(std::lround(255 * g_ch)),
                    static_cast<std::uint8_t>(std::lround(255 * b_ch))});
          }
        // The disk's rim and the origin (the mirror direction's halfway vector).
        for (int s = 0; s < 720; ++s) {
          const double a = s * pi / 360.0;
          const double u = j.x + std::cos(a), v = std::sin(a);
          cv.set(x0 + static_cast<int>((u - kU0) * ppu), y0 + static_cast<int>((kV1 - v) * ppu), plot::kGrey);
        }
        const int ox = x0 + static_cast<int>(-kU0 * ppu), oy = y0 + static_cast<int>(kV1 * ppu);
        cv.line(ox - 4, oy, ox + 4, oy, plot::kBlack);
        cv.line(ox, oy - 4, ox, oy + 4, plot::kBlack);
      }
    }
  }
  plot::write_png(cv, path);
}

double disk_spread(const Model& model, double theta_o_deg) {
  const Vec3 j = outgoing(theta_o_deg);
  const double step = 2.0 / kSpreadGrid;
  std::vector<double> p, r2;
  for (int a = 0; a < kSpreadGrid; ++a)
    for (int b = 0; b < kSpreadGrid; ++b) {
      const hvd::Uv q{j.x - 1.0 + (a + 0.5) * step, -1.0 + (b + 0.5) * step};
      const double du = q.u - j.x, dv = q.v;
      if (du * du + dv * dv >= 1.0) continue;
      p.push_back(disk_density(model, DiskProjection::orthogonal, j, q));
      r2.push_back(q.u * q.u + q.v * q.v);
    }
  std::vector<double> sorted = p;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double floor = sorted[sorted.size() / 2];
  double mass = 0.0, moment = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double q = std::max(0.0, p[k] - floor);
    mass += q;
    moment += q * r2[k];
  }
  return mass > 0.0 ? std::sqrt(moment / mass) : 0.0;
}

}  // namespace ganzfeld
