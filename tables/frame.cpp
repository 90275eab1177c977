#include "tables/frame.h"

#include "integrate/laws.h"
#include "util/angles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <tbb/parallel_for.h>
#include <boost/math/tools/toms748_solve.hpp>

namespace ganzfeld::tables {

namespace {
double sign_of(PeakKind peak) noexcept { return peak == PeakKind::retro ? 1.0 : -1.0; }

/// Polar angles of the probes of lobe_frame_of (degrees): normal, oblique and near grazing.
constexpr double kProbeDegrees[] = {0.0, 30.0, 60.0, 85.0};
/// A hinted peak is "at" the mirror direction or at j when its direction is this close (cosine
/// distance 1 - cos: 1e-12 is ~1.4e-6 rad, far below any lobe width, far above rounding).
constexpr double kSameDirection = 1e-12;
}  // namespace

LobeComponents lobe_components(PeakKind peak, double cos_theta_i, double cos_theta_j, double cos_phi,
                               double sin_phi) noexcept {
  const double s = sign_of(peak);
  const double ci = std::clamp(cos_theta_i, -1.0, 1.0), cj = std::clamp(cos_theta_j, 0.0, 1.0);
  const double si = std::sqrt(std::max(0.0, 1.0 - ci * ci)), sj = std::sqrt(std::max(0.0, 1.0 - cj * cj));
  const double cp = cos_phi, sp = std::abs(sin_phi);
  const double ip = s * si * sj * cp + ci * cj;
  const double ie1 = -s * si * cj * cp + ci * sj;
  const double ie2 = si * sp;
  const double beta = (ie1 == 0.0 && ie2 == 0.0) ? 0.0 : util::atan2_fast(ie2, ie1);
  // |(i·e1, i·e2)| as the exported GLSL's length() takes it (export/glsl.cpp): the components are at
  // most 1, so the squares cannot overflow, and hypot's care would only cost time per lookup.
  return {util::atan2_fast(sj, cj), util::atan2_fast(std::sqrt(ie1 * ie1 + ie2 * ie2), ip), beta, ip, ie1, ie2, cj, sj};
}

namespace {
LobeComponents lobe_components(PeakKind peak, double cos_theta_i, double cos_theta_j, double phi) noexcept {
  return lobe_components(peak, cos_theta_i, cos_theta_j, std::cos(phi), std::sin(phi));
}
}  // namespace

std::array<double, 3> lobe_coordinates(PeakKind peak, double cos_theta_i, double cos_theta_j, double phi) noexcept {
  const LobeComponents c = lobe_components(peak, cos_theta_i, cos_theta_j, phi);
  return {c.theta_j, c.psi, c.beta};
}

std::pair<Vec3, Vec3> lobe_directions(PeakKind peak, double theta_j, double psi, double beta) noexcept {
  const double s = sign_of(peak);
  const double cj = std::cos(theta_j), sj = std::sin(theta_j);
  const Vec3 j{sj, 0.0, cj};
  const Vec3 p{s * sj, 0.0, cj}, e1{-s * cj, 0.0, sj}, e2{0.0, 1.0, 0.0};
  const Vec3 i = std::cos(psi) * p + std::sin(psi) * (std::cos(beta) * e1 + std::sin(beta) * e2);
  return {glm::normalize(i), j};
}

WarpSample warp_at(const Warp& warp, const Axis& theta_axis, double theta_j) noexcept {
  return warp_at_index(warp, theta_axis.index_coordinate(theta_j));
}

WarpSample warp_at_index(const Warp& warp, double u) noexcept {
  const int K = static_cast<int>(warp.samples.size());
  if (K == 0) return {};
  if (K == 1) return warp.samples[0];
  const double s = u * (K - 1);
  const int k = static_cast<int>(std::min(std::floor(s), static_cast<double>(K - 2)));
  const double t = s - k;
  const WarpSample &a = warp.samples[k], &b = warp.samples[k + 1];
  return {(1.0 - t) * a.shift + t * b.shift, (1.0 - t) * a.along + t * b.along, (1.0 - t) * a.across + t * b.across};
}

double warp_envelope(const Warp& warp, double theta_j) noexcept {
  return warp.envelope > 0.0 ? warp_envelope(warp, std::cos(theta_j), std::sin(theta_j)) : 1.0;
}

double warp_envelope(const Warp& warp, double cos_theta_j, double sin_theta_j) noexcept {
  if (!(warp.envelope > 0.0)) return 1.0;
  const double c = cos_theta_j, s = sin_theta_j, w = warp.envelope;
  return 0.5 * (c + std::sqrt(c * c + w * w * s * s));
}

double warped_offset(const WarpSample& at, double mix, double ip, double ie1, double ie2, double psi) noexcept {
  const double q = ip + at.shift * ie1;
  const double r2 = at.along * at.along * ie1 * ie1 + at.across * at.across * ie2 * ie2;
  const double d = std::sqrt(q * q + r2);
  const double lobe = d > 0.0 ? 0.5 * (1.0 + q / d) : 0.5;
  return mix * lobe + (1.0 - mix) * (1.0 - psi / std::numbers::pi);
}

double warped_beta(const WarpSample& at, double whitening, double ie1, double ie2, double beta) noexcept {
  if (whitening == 0.0) return beta;
  const double whitened = (ie1 == 0.0 && ie2 == 0.0) ? beta : util::atan2_fast(at.across * ie2, at.along * ie1);
  return (1.0 - whitening) * beta + whitening * whitened;
}

std::array<double, 3> warped_coordinates(PeakKind peak, const Warp& warp, const Axis& theta_axis, double cos_theta_i,
                                         double cos_theta_j, double phi) noexcept {
  const LobeComponents c = lobe_components(peak, cos_theta_i, cos_theta_j, phi);
  const WarpSample at = warp_at(warp, theta_axis, c.theta_j);
  return {c.theta_j, warped_offset(at, warp.mix, c.ip, c.ie1, c.ie2, c.psi),
          warped_beta(at, warp.beta_whitening, c.ie1, c.ie2, c.beta)};
}

std::pair<Vec3, Vec3> warped_directions(PeakKind peak, const Warp& warp, const Axis& theta_axis, double theta_j,
                                        double offset, double beta) noexcept {
  const WarpSample at = warp_at(warp, theta_axis, theta_j);
  if (warp.beta_whitening != 0.0) {  // the axis rises from 0 (beta = 0) to pi (beta = pi)
    const double axis = beta;
    double below = 0.0, above = std::numbers::pi;
    for (int it = 0; it < 64 && above - below > 1e-15; ++it) {
      const double b = 0.5 * (below + above);
      (warped_beta(at, warp.beta_whitening, std::cos(b), std::sin(b), b) < axis ? below : above) = b;
    }
    beta = 0.5 * (below + above);
  }
  const double cb = std::cos(beta), sb = std::sin(beta);
  double lo = 0.0, hi = std::numbers::pi;  // offset(lo) = 1 >= offset >= 0 = offset(hi)
  for (int it = 0; it < 64 && hi - lo > 1e-15; ++it) {
    const double psi = 0.5 * (lo + hi);
    const double sp = std::sin(psi);
    (warped_offset(at, warp.mix, std::cos(psi), sp * cb, sp * sb, psi) > offset ? lo : hi) = psi;
  }
  return lobe_directions(peak, theta_j, 0.5 * (lo + hi), beta);
}

namespace {
/// S(z) = 3/4 at z = 1/sqrt(3): the quartile spread of S is 2/sqrt(3) widths.
constexpr double kQuartileSpread = 2.0 / 1.7320508075688772;
/// A quartile is sought in m = asinh(cot psi) over [-asinh(kQuantileReach), asinh(kQuantileReach)]
/// to kQuantileTolerance in m (TOMS 748: the bracket's midpoint, also when kQuantileIterations run
/// out first). The warp interpolates its samples between theta_j nodes, so noise in them is noise
/// in g along theta_j that no interpolation follows: a narrow lobe (~0.08 wide in cot psi at
/// alpha = 1000) needs quartiles far finer than its width (2e-4 in m left 2-4e-4 in g); 1e-9 is
/// near what g at a tolerance of 1e-6 resolves (1e-6 over g's slope, ~1/width).
constexpr double kQuantileReach = 1e3;
constexpr double kQuantileTolerance = 1e-9;
constexpr std::uintmax_t kQuantileIterations = 100;
}  // namespace

Warp fit_warp(const Model& model, const LobeFrame& frame, const Axis& theta_axis, double tolerance) {
  using std::numbers::pi;
  CubatureOptions options;
  options.abs_tol = tolerance;
  const double w = frame.width;

  // One sample per theta_j node: the warp, linear between samples, then bends only where the
  // table's own linear interpolation does (samples between nodes put kinks inside cells).
  const int samples = std::max(theta_axis.count, 2);
  std::vector<WarpSample> fits(samples);
  tbb::parallel_for(0, samples, [&](int k) {
    const double theta_j = theta_axis.coordinate(static_cast<double>(k) / (samples - 1));
    auto g = [&](double x, double beta) {  // x = cot psi
      const auto [i, j] = lobe_directions(frame.peak, theta_j, std::atan2(1.0, x), beta);
      return vignetting(model, i, j, options).value;
    };
    const double bottom = g(-HUGE_VAL, 0.0), top = g(HUGE_VAL, 0.0);
    const double reach = std::asinh(kQuantileReach);
    struct Bracket {
      double beta, lo, hi;  // g at m = -reach and +reach
    };
    auto bracket = [&](double beta) { return Bracket{beta, g(std::sinh(-reach), beta), g(std::sinh(reach), beta)}; };
    auto quantile = [&](const Bracket& at, double q) {  // g rises with cot psi
      const double level = bottom + q * (top - bottom);
      if (!(at.lo < level)) return std::sinh(-reach);  // the level lies beyond the reach: its end
      if (!(at.hi > level)) return std::sinh(reach);
      std::uintmax_t iterations = kQuantileIterations;
      const auto [a, b] = boost::math::tools::toms748_solve(
          [&](double m) { return g(std::sinh(m), at.beta) - level; }, -reach, reach, at.lo - level, at.hi - level,
          [](double x, double y) { return std::abs(y - x) <= kQuantileTolerance; }, iterations);
      return std::sinh(0.5 * (a + b));
    };
    WarpSample s{0.0, w, w};
    if (top - bottom > 1e-6) {
      const Bracket a = bracket(0.0), b = bracket(pi), c = bracket(pi / 2);
      const double a25 = quantile(a, 0.25), a50 = quantile(a, 0.5), a75 = quantile(a, 0.75);
      const double b25 = quantile(b, 0.25), b50 = quantile(b, 0.5), b75 = quantile(b, 0.75);
      const double c25 = quantile(c, 0.25), c75 = quantile(c, 0.75);
      auto bounded = [&](double x) { return std::clamp(x, w / 8.0, 8.0 * w + 1.0); };
      s.shift = std::clamp(0.5 * (b50 - a50), -(8.0 * w + 1.0), 8.0 * w + 1.0);
      s.along = bounded(kWarpWidthFactor * 0.5 * ((a75 - a25) + (b75 - b25)) / kQuartileSpread);
      s.across = bounded(kWarpWidthFactor * (c75 - c25) / kQuartileSpread);
    }
    fits[k] = s;
  });
  // g(psi = 0) at kEnvelopeSamples theta_j uniform in the index coordinate, whatever the node count
  // (a choice made on the nodes flipped with it: specular alpha = 100 lost its envelope at 29 nodes).
  std::vector<double> tops(kEnvelopeSamples);
  tbb::parallel_for(0, kEnvelopeSamples, [&](int k) {
    const double theta_j = theta_axis.coordinate(static_cast<double>(k) / (kEnvelopeSamples - 1));
    const auto [i, j] = lobe_directions(frame.peak, theta_j, std::atan2(1.0, HUGE_VAL), 0.0);
    tops[k] = vignetting(model, i, j, options).value;
  });
  Warp warp;
  warp.mix = kWarpMix;
  warp.beta_whitening = kWarpBetaWhitening;
  warp.samples = fits;
  // The envelope: the one under which g(psi = 0) / A bends least over those theta_j.
  auto roughness = [&](double envelope) {
    Warp trial;
    trial.envelope = envelope;
    double worst = 0.0;
    for (int k = 1; k + 1 < kEnvelopeSamples; ++k) {
      auto at = [&](int m) {
        return tops[m] / warp_envelope(trial, theta_axis.coordinate(static_cast<double>(m) / (kEnvelopeSamples - 1)));
      };
      worst = std::max(worst, std::abs(at(k - 1) - 2.0 * at(k) + at(k + 1)));
    }
    return worst;
  };
  warp.envelope = roughness(w) < roughness(0.0) ? w : 0.0;
  return warp;
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
