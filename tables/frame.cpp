#include "tables/frame.h"

#include "integrate/laws.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ganzfeld::tables {

namespace {
double sign_of(PeakKind peak) noexcept { return peak == PeakKind::retro ? 1.0 : -1.0; }

/// Polar angles of the probes of lobe_frame_of (degrees): normal, oblique and near grazing.
constexpr double kProbeDegrees[] = {0.0, 30.0, 60.0, 85.0};
/// A hinted peak is "at" the mirror direction or at j when its direction is this close (cosine
/// distance 1 - cos: 1e-12 is ~1.4e-6 rad, far below any lobe width, far above rounding).
constexpr double kSameDirection = 1e-12;
}  // namespace

std::array<double, 3> lobe_coordinates(PeakKind peak, double cos_theta_i, double cos_theta_j, double phi) noexcept {
  const double s = sign_of(peak);
  const double ci = std::clamp(cos_theta_i, -1.0, 1.0), cj = std::clamp(cos_theta_j, 0.0, 1.0);
  const double si = std::sqrt(std::max(0.0, 1.0 - ci * ci)), sj = std::sqrt(std::max(0.0, 1.0 - cj * cj));
  const double cp = std::cos(phi), sp = std::abs(std::sin(phi));
  const double ip = s * si * sj * cp + ci * cj;
  const double ie1 = -s * si * cj * cp + ci * sj;
  const double ie2 = si * sp;
  const double beta = (ie1 == 0.0 && ie2 == 0.0) ? 0.0 : std::atan2(ie2, ie1);
  return {std::atan2(sj, cj), std::atan2(std::hypot(ie1, ie2), ip), beta};
}

std::pair<Vec3, Vec3> lobe_directions(PeakKind peak, double theta_j, double psi, double beta) noexcept {
  const double s = sign_of(peak);
  const double cj = std::cos(theta_j), sj = std::sin(theta_j);
  const Vec3 j{sj, 0.0, cj};
  const Vec3 p{s * sj, 0.0, cj}, e1{-s * cj, 0.0, sj}, e2{0.0, 1.0, 0.0};
  const Vec3 i = std::cos(psi) * p + std::sin(psi) * (std::cos(beta) * e1 + std::sin(beta) * e2);
  return {glm::normalize(i), j};
}

std::optional<LobeFrame> lobe_frame_of(const Model& model) {
  std::optional<LobeFrame> best;
  for (PeakKind kind : {PeakKind::mirror, PeakKind::retro}) {
    double width = HUGE_VAL;
    bool everywhere = true;
    for (double degrees : kProbeDegrees) {
      const Vec3 j = direction(degrees * std::numbers::pi / 180.0, 0.0);
      const Vec3 want = kind == PeakKind::mirror ? mirror(j) : j;
      bool found = false;
      for (const Peak& peak : model.mass_hints(j, Varying::incident).peaks) {
        if (1.0 - glm::dot(glm::normalize(peak.direction), want) > kSameDirection || !(peak.width > 0.0)) continue;
        found = true;
        width = std::min(width, peak.across > 0.0 ? std::min(peak.width, peak.across) : peak.width);
      }
      everywhere = everywhere && found;
    }
    if (everywhere && std::isfinite(width) && (!best || width < best->width)) best = LobeFrame{kind, width};
  }
  return best;
}

}  // namespace ganzfeld::tables
