#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "integrate/laws.h"
#include "util/error.h"
#include "util/names.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {
constexpr std::array kLaws{util::EnumName<Law>{Law::f, "f"}, util::EnumName<Law>{Law::g, "g"},
                           util::EnumName<Law>{Law::h, "h"}, util::EnumName<Law>{Law::a, "a"},
                           util::EnumName<Law>{Law::r, "r"}};
}  // namespace

const char* to_string(Law law) { return util::name_of(kLaws, law); }
Law parse_law(const std::string& text) { return util::parse_name(kLaws, "law", text); }

Vec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Vec3 direction_from_cos(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

namespace {

const Vec3 kNormal{0.0, 0.0, 1.0};
// The rules by which hints become lines, stated once with their reasons (models/mass_hints.h).
using hint_rules::kBroadLobe;
using hint_rules::kCentreLineOnly;
using hint_rules::kFlankWidths;
using hint_rules::kGradedLayer;
using hint_rules::kLadderFirst;
using hint_rules::kLadderRatio;
using hint_rules::kLayerLines;
using hint_rules::kNarrowestWidth;
using hint_rules::kPoleLadderEnd;
using hint_rules::kReachWidths;
using hint_rules::kThinLayer;
constexpr double kNearHorizonEdge = 0.1;  // a sky edge this close to the horizon is graded too

}  // namespace

Vec3 Lune::direction(double t, double phi) const {
  return std::cos(t) * (std::cos(phi) * kNormal + std::sin(phi) * u) + std::sin(t) * e;
}

Lune lune(const Vec3& pole, const Vec3& fixed) {
  Lune frame;
  const Vec3 n_x_pole = glm::cross(kNormal, pole);
  const double s = glm::length(n_x_pole);
  if (s > 0.0) {
    frame.e = n_x_pole / s;
  } else {
    if (pole.z < 0.0) {  // sky pole at the nadir: the lune is empty
      frame.empty = true;
      return frame;
    }
    // The hemisphere: put the plane of n and the fixed direction at t = 0, where the specular
    // and backscatter lobes of isotropic models then lie.
    const Vec3 n_x_fixed = glm::cross(kNormal, fixed);
    const double sf = glm::length(n_x_fixed);
    frame.e = sf > 0.0 ? n_x_fixed / sf : Vec3{0.0, 1.0, 0.0};
  }
  frame.u = glm::cross(frame.e, kNormal);
  frame.phi_lo = std::atan2(s, pole.z) - pi / 2;
  frame.empty = !(frame.phi_lo < pi / 2);
  return frame;
}

namespace {

/// Adds lines to sorted cuts as exact lines (after tidy_cuts, which could otherwise drop one next
/// to a hint line): crease longitudes, a pole's ladder.
void add_exact_lines(std::vector<double>& cuts, const std::vector<double>& lines) {
  constexpr double kSameLine = 1e-12;
  for (double c : lines) {
    if (!(c > cuts.front() + kSameLine && c < cuts.back() - kSameLine)) continue;
    const auto at = std::lower_bound(cuts.begin(), cuts.end(), c);
    if (std::abs(*at - c) > kSameLine && std::abs(*(at - 1) - c) > kSameLine) cuts.insert(at, c);
  }
}

/// Initial cut lines from the model's mass hints (the rules: models/mass_hints.h): each peak
/// (clamped into the rectangle) gets lines at its centre and, when sharper than kCentreLineOnly,
/// at ±kFlankWidths widths, and a ladder outwards, per scale when the lobe is elongated
/// (Peak::across); a lobe at a coordinate pole t = ±pi/2 gets ladders of latitudes towards the pole
/// and of longitudes about its own; each horizon layer of thickness delta (MassHints::horizon_layer
/// and thicker_layers) gets lines at kLayerLines deltas from the horizon (phi = pi/2, phi = -pi/2
/// for the hemisphere, and the caps t = ±pi/2) and, beside a lobe at a pole, a ladder of longitudes
/// from the horizon inwards.
/// `first_axis(t, phi)` maps a line at latitude t, placed for longitude phi, to the first
/// coordinate of the rectangle (t itself on a lune; the clipped crease frame's s).
template <typename FirstAxis>
std::array<std::vector<double>, 2> cuts_from_hints(const MassHints& hints, const Lune& fr, FirstAxis first_axis,
                                                   double first_lo, double first_hi) {
  std::vector<double> t_lines{first_axis(0.0, 0.0)},
      phi_lines{0.5 * (fr.phi_lo + pi / 2)};  // 2x2 at least: a 1x1 start
  // misses asperity horizon layers below the hint threshold (measured: 6% dishonest estimates)
  double min_scale = 1.0;
  bool lobe_at_pole = false;
  std::vector<double> pole_ladder;  // exact lines towards a coordinate pole (added after tidy_cuts)
  for (const Peak& peak : hints.peaks) {
    const double across = peak.across > 0.0 ? peak.across : peak.width;
    if (!(std::min(peak.width, across) < kBroadLobe)) continue;
    const Vec3 d = glm::normalize(peak.direction);
    const double t_d = std::asin(std::clamp(glm::dot(d, fr.e), -1.0, 1.0));
    const double phi_d = std::clamp(std::atan2(glm::dot(d, fr.u), d.z), fr.phi_lo, pi / 2);
    // An elongated lobe's two scales need not align with t and phi (the lune of g is tilted
    // against the plane of the peak), so both get lines at both scales.
    for (double scale : {peak.width, across}) {
      if (!(scale < kBroadLobe)) continue;
      const double w = std::max(scale, kNarrowestWidth);
      const double w_phi = w / std::max(std::cos(t_d), w);  // longitude shrinks towards the poles
      // Within a few widths of a pole t = ±pi/2 of the coordinates (the lune's tip: a thin lune
      // of g with the lobe at its end) the lobe's centre lies on the rectangle's edge, where no
      // panels meet around it: it needs its ±2w lines whatever its width (tests/extremes_test.cpp,
      // SharpLobeAtTheTipOfAThinLuneIsHonest).
      const bool at_pole = std::abs(t_d) + kReachWidths * w > pi / 2;
      // A lobe at a pole t = ±pi/2 of the coordinates: every longitude meets there, so the part
      // of the lobe inside the domain can be far smaller than the lobe (a thin lune's tip cuts a
      // sliver 1e-8 wide from a lobe 1e-2 wide, which the ±2w lines leave to one panel whose nodes
      // all miss it: tests/extremes_test.cpp, SliverOfALobeAtTheTipIsHonest). A geometric ladder of
      // lines towards the pole, w/8, w/64, ... down to kPoleLadderEnd, gives the refinement a panel
      // at every scale there.
      if (at_pole) {
        lobe_at_pole = true;
        for (double offset = w / kLadderRatio; offset > kPoleLadderEnd; offset /= kLadderRatio)
          pole_ladder.push_back(first_axis((t_d < 0.0 ? -1.0 : 1.0) * (pi / 2 - offset), phi_d));
        // There a lobe w wide spans the longitudes within w / x of its own at a distance x from
        // the pole: a sliver of the panels beside it whose width changes with x, which the nodes
        // of a panel pi/4 wide miss (hvd-fit's lump 1e-7 across at a view 1e-9 above the horizon,
        // tests/extremes_test.cpp, LobeAtThePoleSpansEveryLongitudeScale). A geometric ladder of
        // longitudes about the lobe's, down to w, meets the sliver at every x.
        for (double offset = 1.0 / kLadderRatio; offset > std::max(w, kPoleLadderEnd); offset /= kLadderRatio) {
          phi_lines.push_back(phi_d - offset);
          phi_lines.push_back(phi_d + offset);
        }
      }
      for (double m : {-kFlankWidths, 0.0, kFlankWidths}) {
        if (m != 0.0 && w >= kCentreLineOnly && !at_pole) continue;
        t_lines.push_back(first_axis(t_d + m * w, phi_d));
        phi_lines.push_back(phi_d + m * w_phi);
      }
      for (double m = kLadderFirst; m * w < kBroadLobe; m *= kLadderRatio)
        for (double sign : {-1.0, 1.0}) {
          t_lines.push_back(first_axis(t_d + sign * m * w, phi_d));
          phi_lines.push_back(phi_d + sign * m * w_phi);
        }
      min_scale = std::min(min_scale, w);
    }
  }
  std::vector<double> layers{hints.horizon_layer};
  layers.insert(layers.end(), hints.thicker_layers.begin(), hints.thicker_layers.end());
  for (double delta : layers) {
    if (!(delta > 0.0 && delta < kThinLayer)) continue;
    for (double m : kLayerLines) {
      phi_lines.push_back(pi / 2 - m * delta);
      if (fr.phi_lo <= -pi / 2) phi_lines.push_back(-pi / 2 + m * delta);  // the hemisphere: both ends
      t_lines.push_back(first_axis(pi / 2 - m * delta, 0.0));
      t_lines.push_back(first_axis(-pi / 2 + m * delta, 0.0));
    }
    // The horizon passes through the coordinates' poles (the lune's tips), where at a distance x
    // from the pole the layer spans the longitudes within delta / x of the horizon edge: beside a
    // lobe at the pole it holds mass at every such width (Phong's and Kajiya's grazing floor,
    // tests/extremes_test.cpp, HorizonLayerAtALobesPoleIsHonest). A geometric ladder of longitudes
    // from the layer towards the lune's interior meets its edge at every x, as the lobe's ladder does.
    if (lobe_at_pole)
      for (double offset = kLadderRatio * delta; offset < 1.0 / kLadderRatio; offset *= kLadderRatio) {
        phi_lines.push_back(pi / 2 - offset);
        if (fr.phi_lo <= -pi / 2) phi_lines.push_back(-pi / 2 + offset);
      }
    min_scale = std::min(min_scale, delta);
  }
  const double gap = 0.25 * min_scale;
  std::array<std::vector<double>, 2> cuts{tidy_cuts(t_lines, first_lo, first_hi, gap),
                                          tidy_cuts(phi_lines, fr.phi_lo, pi / 2, gap)};
  add_exact_lines(cuts[0], pole_ladder);
  return cuts;
}

std::array<std::vector<double>, 2> cuts_from_hints(const MassHints& hints, const Lune& fr) {
  return cuts_from_hints(
      hints, fr, [](double t, double) { return t; }, -pi / 2, pi / 2);
}

}  // namespace

std::array<std::vector<double>, 2> lune_cuts(const Model& model, const Lune& lune, const Vec3& fixed, Varying varying) {
  return cuts_from_hints(model.mass_hints(fixed, varying), lune);
}

namespace {

constexpr int kNodes = kRuleNodes;
using PanelDirections = std::array<Vec3, kNodes * kNodes>;
using PanelWeights = std::array<double, kNodes * kNodes>;

/// Cubature of (k·n) f(k, fixed) [or f(fixed, k)] over a rectangle whose panel nodes
/// `place(nodes, k, weight)` turns into directions k and weights (k·n) × Jacobian.
template <typename Place>
Estimate integrate_rectangle(const Model& model, const Vec3& fixed, Varying varying,
                             const std::array<std::vector<double>, 2>& cuts, const CubatureOptions& options,
                             Place place) {
  PanelDirections k_dirs, fixed_dirs;
  PanelWeights weights;
  fixed_dirs.fill(fixed);
  PanelIntegrand<2> integrand = [&](const std::array<std::span<const double>, 2>& nodes, std::span<double> values) {
    place(nodes, k_dirs, weights);
    const std::size_t count = nodes[0].size() * nodes[1].size();  // a panel, or a line on its side
    const std::span<const Vec3> k(k_dirs.data(), count), f(fixed_dirs.data(), count);
    if (varying == Varying::incident) model.f_batch(k, f, values.first(count));
    else model.f_batch(f, k, values.first(count));
    for (std::size_t m = 0; m < count; ++m) values[m] *= weights[m];
  };
  return adaptive_cubature<2>(integrand, cuts, options);
}

/// Grading of one axis of the rectangle towards the horizon: x = lo + (hi - lo) psi(u), u the
/// panel coordinate scaled to [0, 1], with psi' vanishing at a graded end (psi = 3u^2 - 2u^3 at
/// both ends, u + u^2 - u^3 at the upper one only; either way b - x ~ (1 - u)^2 at a graded end
/// b). An integrand (b - x)^nu there becomes ~ (1 - u)^(2 nu + 1), much smoother for the
/// Gauss–Kronrod rule. Smooth integrands
/// pay for it (specular alpha=10: 1.9x more evaluations), so only hinted edges are graded; the
/// crease frame is not graded (no creased model hints a rough horizon).
struct Grading {
  double lo = 0.0, hi = 1.0;
  bool at_lo = false, at_hi = false;

  static double psi_one_end(double u) { return u + u * u - u * u * u; }  // psi'(1) = 0, psi'(0) = 1
  double psi(double u) const {
    if (at_lo && at_hi) return u * u * (3.0 - 2.0 * u);
    if (at_hi) return psi_one_end(u);
    if (at_lo) return 1.0 - psi_one_end(1.0 - u);
    return u;
  }
  double dpsi(double u) const {
    if (at_lo && at_hi) return 6.0 * u * (1.0 - u);
    if (at_hi) return (1.0 - u) * (1.0 + 3.0 * u);
    if (at_lo) return u * (4.0 - 3.0 * u);
    return 1.0;
  }
  double x(double s) const { return lo + (hi - lo) * psi((s - lo) / (hi - lo)); }
  double dx_ds(double s) const { return dpsi((s - lo) / (hi - lo)); }
  /// The inverse (psi is increasing): where a hint line at x goes on the graded axis.
  double s_of(double x_value) const {
    if (!at_lo && !at_hi) return x_value;
    const double target = (x_value - lo) / (hi - lo);
    double a = 0.0, b = 1.0;
    for (int it = 0; it < 60; ++it) (psi(0.5 * (a + b)) < target ? a : b) = 0.5 * (a + b);
    return lo + (hi - lo) * 0.5 * (a + b);
  }
};

/// The lune rectangle's nodes: k = cos t (cos phi n + sin phi u) + sin t e.
Estimate integrate_on_lune(const Model& model, const Lune& fr, std::array<std::vector<double>, 2> cuts,
                           const Vec3& fixed, Varying varying, const CubatureOptions& options, bool graded) {
  // The horizon: phi = pi/2, the poles t = ±pi/2 of the frame (±e lie on it), and phi = phi_lo
  // when the sky pole is (nearly) n, where the sky edge runs (next) to the horizon.
  const Grading gt{-pi / 2, pi / 2, graded, graded};
  const Grading gp{fr.phi_lo, pi / 2, graded && fr.phi_lo + pi / 2 < kNearHorizonEdge, graded};
  for (double& c : cuts[0]) c = gt.s_of(c);
  for (double& c : cuts[1]) c = gp.s_of(c);
  cuts[0].front() = -pi / 2;  // exact ends, whatever the inverse's rounding
  cuts[0].back() = pi / 2;
  cuts[1].front() = fr.phi_lo;
  cuts[1].back() = pi / 2;
  return integrate_rectangle(
      model, fixed, varying, cuts, options,
      [&](const std::array<std::span<const double>, 2>& nodes, PanelDirections& k_dirs, PanelWeights& weights) {
        std::array<double, kNodes> cos_t, sin_t, cos_phi, sin_phi, jt, jp;
        const std::size_t na = nodes[0].size(), nb = nodes[1].size();
        for (std::size_t m = 0; m < na; ++m) {
          const double t = gt.x(nodes[0][m]);
          jt[m] = gt.dx_ds(nodes[0][m]);
          cos_t[m] = std::cos(t);
          sin_t[m] = std::sin(t);
        }
        for (std::size_t m = 0; m < nb; ++m) {
          const double phi = gp.x(nodes[1][m]);
          jp[m] = gp.dx_ds(nodes[1][m]);
          cos_phi[m] = std::cos(phi);
          sin_phi[m] = std::sin(phi);
        }
        for (std::size_t a = 0; a < na; ++a)
          for (std::size_t b = 0; b < nb; ++b) {
            const std::size_t m = a * nb + b;
            k_dirs[m] = cos_t[a] * (cos_phi[b] * kNormal + sin_phi[b] * fr.u) + sin_t[a] * fr.e;
            // (k·n) = cos t cos phi >= 0 on the rectangle; times the Jacobians cos t and the gradings'.
            weights[m] = cos_t[a] * cos_t[a] * cos_phi[b] * jt[a] * jp[b];
          }
      });
}

/// Lines at a smooth step of the integrand at longitude `centre` and width `w` (its centre,
/// ±2 widths when sharp, and a ladder outwards), as for a lobe (cuts_from_hints).
void add_step_lines(std::vector<double>& phi_cuts, double centre, double w) {
  if (!(w < kBroadLobe) || !(centre > phi_cuts.front() && centre < phi_cuts.back())) return;
  w = std::max(w, kNarrowestWidth);
  std::vector<double> lines(phi_cuts.begin() + 1, phi_cuts.end() - 1);
  lines.push_back(centre);
  std::vector<double> offsets;
  if (w < kCentreLineOnly) offsets.push_back(kFlankWidths);
  for (double m = kLadderFirst; m * w < kBroadLobe; m *= kLadderRatio) offsets.push_back(m);
  for (double m : offsets) {
    lines.push_back(centre - m * w);
    lines.push_back(centre + m * w);
  }
  phi_cuts = tidy_cuts(lines, phi_cuts.front(), phi_cuts.back(), 0.25 * w);
}

/// Integrands that jump across half great circles through ±e (MassHints::crease_axis), done in
/// the frame whose meridians are those circles: k = cos t (cos phi n + sin phi u) + sin t e with
/// e the (horizontal) crease axis, so every crease is a line phi = const and a cut of the
/// initial grid. The hemisphere is t, phi ∈ [-pi/2, pi/2]. A sky pole p clips each meridian
/// once: with e oriented so that p·e > 0, k·p >= 0 is t >= t0(phi) = atan(-(m(phi)·p)/(p·e)),
/// m(phi) = cos phi n + sin phi u, so the lune is the rectangle s ∈ [0, 1] × phi ∈ [-pi/2, pi/2]
/// with t = t0 + s (pi/2 - t0) and Jacobian (pi/2 - t0) cos t. t0 is analytic; it steps from
/// -pi/2 to pi/2 within |p·e|/|p × e| of the longitude where m·p = 0, which gets step lines.
/// With p·e = 0 the sky circle is itself a meridian and the lune the usual rectangle.
Estimate integrate_creased(const Model& model, const Vec3& pole, const Vec3& fixed, Varying varying,
                           const MassHints& hints, const CubatureOptions& options) {
  Vec3 e = glm::normalize(hints.crease_axis);
  std::vector<double> creases = hints.crease_longitudes;
  auto flip = [&] {  // e -> -e turns u into -u, so every longitude changes sign
    e = -e;
    for (double& c : creases) c = -c;
  };
  const double p_e = glm::dot(pole, e);
  const Vec3 n_x_pole = glm::cross(kNormal, pole);
  const double sin_pole = glm::length(n_x_pole);
  if (p_e == 0.0 || sin_pole == 0.0) {  // the hemisphere (or the empty set), or the pole ⊥ e
    if (sin_pole == 0.0 && pole.z < 0.0) return {};
    if (sin_pole > 0.0 && glm::dot(n_x_pole, e) < 0.0) flip();  // lune(): e = n x pole / |n x pole|
    Lune fr;
    fr.e = e;
    fr.u = glm::cross(e, kNormal);
    fr.phi_lo = std::atan2(sin_pole, pole.z) - pi / 2;
    if (!(fr.phi_lo < pi / 2)) return {};
    auto cuts = cuts_from_hints(hints, fr);
    add_exact_lines(cuts[1], creases);
    return integrate_on_lune(model, fr, cuts, fixed, varying, options, false);
  }
  if (p_e < 0.0) flip();
  Lune fr;  // the hemisphere frame, for placing the hints
  fr.e = e;
  fr.u = glm::cross(e, kNormal);
  fr.phi_lo = -pi / 2;
  const double p_n = pole.z, p_u = glm::dot(pole, fr.u), p_e_abs = std::abs(p_e);
  auto t0 = [&](double cos_phi, double sin_phi) { return std::atan(-(cos_phi * p_n + sin_phi * p_u) / p_e_abs); };
  auto first_axis = [&](double t, double phi) {
    const double t_lo = t0(std::cos(phi), std::sin(phi));
    return std::clamp((t - t_lo) / (pi / 2 - t_lo), 0.0, 1.0);
  };
  auto cuts = cuts_from_hints(hints, fr, first_axis, 0.0, 1.0);
  // m(phi)·p = R cos(phi - phi_p) vanishes at phi_p ± pi/2, where t0 steps.
  const double radius = std::hypot(p_n, p_u), phi_p = std::atan2(p_u, p_n);
  if (radius > 0.0)
    for (double centre : {phi_p - pi / 2, phi_p + pi / 2}) add_step_lines(cuts[1], centre, p_e_abs / radius);
  add_exact_lines(cuts[1], creases);
  return integrate_rectangle(
      model, fixed, varying, cuts, options,
      [&](const std::array<std::span<const double>, 2>& nodes, PanelDirections& k_dirs, PanelWeights& weights) {
        const std::size_t na = nodes[0].size(), nb = nodes[1].size();
        for (std::size_t b = 0; b < nb; ++b) {
          const double cos_phi = std::cos(nodes[1][b]), sin_phi = std::sin(nodes[1][b]);
          const double t_lo = t0(cos_phi, sin_phi), span = pi / 2 - t_lo;
          const Vec3 meridian = cos_phi * kNormal + sin_phi * fr.u;
          for (std::size_t a = 0; a < na; ++a) {
            const double t = t_lo + nodes[0][a] * span, cos_t = std::cos(t);
            const std::size_t m = a * nb + b;
            k_dirs[m] = cos_t * meridian + std::sin(t) * e;
            weights[m] = cos_t * cos_t * cos_phi * span;
          }
        }
      });
}

/// Whether the model said where its mass is: then the initial grid is placed there and trusted
/// as it is (CubatureOptions::bisect_initial_panels); a model without hints gets its 2x2 grid's
/// panels bisected once before any is accepted.
bool hinted(const MassHints& hints) {
  return !hints.peaks.empty() || hints.horizon_layer > 0.0 || hints.rough_horizon ||
         hints.crease_axis != Vec3{0.0, 0.0, 0.0};
}

Estimate integrate_lune(const Model& model, const Vec3& pole, const Vec3& fixed, Varying varying,
                        const CubatureOptions& caller) {
  const MassHints hints = model.mass_hints(fixed, varying);
  CubatureOptions options = caller;
  options.bisect_initial_panels = caller.bisect_initial_panels && !hinted(hints);
  if (hints.crease_axis != Vec3{0.0, 0.0, 0.0}) return integrate_creased(model, pole, fixed, varying, hints, options);
  const Lune fr = lune(pole, fixed);
  if (fr.empty) return {};
  const bool graded = hints.rough_horizon || (hints.horizon_layer > 0.0 && hints.horizon_layer < kGradedLayer);
  return integrate_on_lune(model, fr, cuts_from_hints(hints, fr), fixed, varying, options, graded);
}

}  // namespace

Estimate vignetting(const Model& model, const Vec3& i, const Vec3& j, const CubatureOptions& options) {
  if (j.z < 0.0) return {};
  return integrate_lune(model, glm::normalize(i), glm::normalize(j), Varying::incident, options);
}

Estimate darkening(const Model& model, const Vec3& j, const CubatureOptions& options) {
  if (j.z < 0.0) return {};
  return integrate_lune(model, kNormal, glm::normalize(j), Varying::incident, options);
}

Estimate albedo(const Model& model, const Vec3& i, const CubatureOptions& options) {
  if (i.z < 0.0) return {};
  return integrate_lune(model, kNormal, glm::normalize(i), Varying::outgoing, options);
}

// r = (1/pi) ∫ (i·n) a(i) di. Isotropic models: a depends on i·n = mu only, so r = 2 ∫_0^1 mu a(mu)
// dmu; otherwise the outer integral runs over the hemisphere. The tolerance is split evenly:
// each inner a is computed to tol/2 and the outer weights integrate to 1, so the inner errors
// add at most their maximum; the outer quadrature gets the other half.
Estimate double_diffuse(const Model& model, const CubatureOptions& options) {
  CubatureOptions inner = options, outer = options;
  inner.abs_tol = outer.abs_tol = 0.5 * options.abs_tol;
  // The outer integrand is an albedo, smooth in i (each of its nodes is a whole inner integral):
  // its fixed grid is trusted as it is.
  outer.bisect_initial_panels = false;
  double max_inner_error = 0.0;
  long long inner_evaluations = 0;
  bool inner_converged = true;
  auto run_inner = [&](std::span<const Vec3> dirs, std::span<double> values) {
    std::vector<Estimate> est(dirs.size());
    tbb::parallel_for(std::size_t{0}, dirs.size(), [&](std::size_t m) { est[m] = albedo(model, dirs[m], inner); });
    for (std::size_t m = 0; m < dirs.size(); ++m) {  // sequential: deterministic sums
      values[m] = est[m].value;
      max_inner_error = std::max(max_inner_error, est[m].error);
      inner_evaluations += est[m].evaluations;
      inner_converged = inner_converged && est[m].converged;
    }
  };

  Estimate out;
  if (model.traits().isotropic) {
    PanelIntegrand<1> integrand = [&](const std::array<std::span<const double>, 1>& nodes, std::span<double> values) {
      std::vector<Vec3> dirs(nodes[0].size());
      for (std::size_t m = 0; m < dirs.size(); ++m) {
        const double mu = nodes[0][m];
        dirs[m] = {std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0.0, mu};
      }
      run_inner(dirs, values);
      for (std::size_t m = 0; m < dirs.size(); ++m) values[m] *= 2.0 * nodes[0][m];
    };
    out = adaptive_cubature<1>(integrand, {std::vector<double>{0.0, 0.5, 1.0}}, outer);
  } else {
    PanelIntegrand<2> integrand = [&](const std::array<std::span<const double>, 2>& nodes, std::span<double> values) {
      const std::size_t na = nodes[0].size(), nb = nodes[1].size();
      std::vector<Vec3> dirs(na * nb);
      std::vector<double> weight(dirs.size());
      for (std::size_t a = 0; a < na; ++a)
        for (std::size_t b = 0; b < nb; ++b) {  // hemisphere as the lune with pole n, e = y
          const double t = nodes[0][a], phi = nodes[1][b];
          dirs[a * nb + b] = {std::cos(t) * std::sin(phi), std::sin(t), std::cos(t) * std::cos(phi)};
          weight[a * nb + b] = std::cos(t) * std::cos(t) * std::cos(phi) / pi;
        }
      run_inner(dirs, values);
      for (std::size_t m = 0; m < dirs.size(); ++m) values[m] *= weight[m];
    };
    out = adaptive_cubature<2>(
        integrand, {std::vector<double>{-pi / 2, 0.0, pi / 2}, std::vector<double>{-pi / 2, 0.0, pi / 2}}, outer);
  }
  out.error += max_inner_error;
  out.evaluations += inner_evaluations;
  out.converged = out.converged && inner_converged && out.error <= options.abs_tol;
  return out;
}

Estimate evaluate_law(const Model& model, Law law, const Vec3& i, const Vec3& j, const CubatureOptions& options) {
  switch (law) {
    case Law::f: return {model.f(glm::normalize(i), glm::normalize(j)), 0.0, 1, true};
    case Law::g: return vignetting(model, i, j, options);
    case Law::h: return darkening(model, j, options);
    case Law::a: return albedo(model, i, options);
    case Law::r: return double_diffuse(model, options);
  }
  return {};
}

}  // namespace ganzfeld
