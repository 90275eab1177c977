#include "reports/disk.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

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
/// Grid points per axis over the disk's bounding square for disk_spread.
constexpr int kSpreadGrid = 400;

Vec3 outgoing(double theta_o_deg) { return direction(theta_o_deg * pi / 180.0, 0.0); }

constexpr plot::Rgb kDataColour{215, 25, 28}, kFitColour{30, 80, 220};

/// `count` points drawn with the density p on the disk: p tabulated on the figure's pixels (the
/// mean of ss × ss supersamples each), a pixel drawn in proportion to its share, a point uniform in it.
std::vector<hvd::Uv> sample_disk(const Model& model, DiskProjection projection, const Vec3& j, int w, int h, int ppu,
                                 int ss, int count, std::mt19937_64& engine) {
  std::vector<double> cumulative(static_cast<std::size_t>(w) * h);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      double sum = 0.0;
      for (int a = 0; a < ss; ++a)
        for (int b = 0; b < ss; ++b)
          sum +=
              disk_density(model, projection, j, {kU0 + (x + (a + 0.5) / ss) / ppu, kV1 - (y + (b + 0.5) / ss) / ppu});
      cumulative[static_cast<std::size_t>(y) * w + x] = sum;
    }
  });
  for (std::size_t k = 1; k < cumulative.size(); ++k) cumulative[k] += cumulative[k - 1];
  std::vector<hvd::Uv> points;
  if (!(cumulative.back() > 0.0)) return points;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int n = 0; n < count; ++n) {
    const double target = uniform(engine) * cumulative.back();
    const auto pixel =
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
    const int x = static_cast<int>(std::min(pixel, cumulative.size() - 1) % w), y = static_cast<int>(pixel / w);
    points.push_back({kU0 + (x + uniform(engine)) / ppu, kV1 - (y + uniform(engine)) / ppu});
  }
  return points;
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
      throw InputError({Named{"theta_o", format_number(t)}, " is not allowed; allowed: angles in [0, 90) degrees"});
  const int ppu = options.pixels_per_unit, ss = std::max(1, options.samples_per_pixel_axis);
  const int w = static_cast<int>((kU1 - kU0) * ppu), h = static_cast<int>((kV1 - kV0) * ppu);
  const int panels = fit ? 3 : 1, columns = 2 * panels, rows = static_cast<int>(options.theta_o_deg.size());
  const int left = 150, top = 60, gap = 10;
  plot::Canvas cv(left + columns * (w + gap), top + rows * (h + gap));
  const char* headers_fit[] = {"ORTHO: DATA",   "ORTHO: FIT",   "ORTHO: BOTH",
                               "SCALING: DATA", "SCALING: FIT", "SCALING: BOTH"};
  const char* headers_data[] = {"ORTHOGONAL", "SCALING"};
  for (int c = 0; c < columns; ++c)
    cv.text(left + c * (w + gap) + 4, top - 24, fit ? headers_fit[c] : headers_data[c], plot::kBlack);
  cv.text(
      8, 8,
      std::to_string(options.points) + " HALFWAY VECTORS DRAWN FROM EACH DENSITY" + (fit ? ": RED DATA, BLUE FIT" : ""),
      plot::kGrey);
  std::mt19937_64 engine(options.seed);

  for (int r = 0; r < rows; ++r) {
    const Vec3 j = outgoing(options.theta_o_deg[r]);
    const int y0 = top + r * (h + gap);
    cv.text(8, y0 + h / 2 - 7, "THETA_O " + format_number(options.theta_o_deg[r]), plot::kBlack);
    for (int proj = 0; proj < 2; ++proj) {
      const DiskProjection projection = proj == 0 ? DiskProjection::orthogonal : DiskProjection::scaling;
      const std::vector<hvd::Uv> data_points = sample_disk(data, projection, j, w, h, ppu, ss, options.points, engine);
      const std::vector<hvd::Uv> fit_points =
          fit ? sample_disk(*fit, projection, j, w, h, ppu, ss, options.points, engine) : std::vector<hvd::Uv>{};
      for (int k = 0; k < panels; ++k) {
        const int x0 = left + (proj * panels + k) * (w + gap);
        // The disk's rim and the origin (the mirror direction's halfway vector).
        for (int s = 0; s < 720; ++s) {
          const double a = s * pi / 360.0;
          const double u = j.x + std::cos(a), v = std::sin(a);
          cv.set(x0 + static_cast<int>((u - kU0) * ppu), y0 + static_cast<int>((kV1 - v) * ppu), plot::kGrey);
        }
        auto dot = [&](const hvd::Uv& q, plot::Rgb c) {
          const int x = x0 + static_cast<int>((q.u - kU0) * ppu), y = y0 + static_cast<int>((kV1 - q.v) * ppu);
          cv.set(x, y, c);
        };
        // Interleaved, so that neither colour hides the other where both are dense.
        for (std::size_t n = 0; n < std::max(data_points.size(), fit_points.size()); ++n) {
          if (k != 1 && n < data_points.size()) dot(data_points[n], kDataColour);
          if (k != 0 && n < fit_points.size()) dot(fit_points[n], kFitColour);
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
