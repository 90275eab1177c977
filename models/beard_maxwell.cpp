// Beard–Maxwell (NEF form): formulas, sources and the differences from the thesis are in
// models/beard_maxwell.h and docs/models.md.
#include "models/beard_maxwell.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "models/classic_models.h"  // fresnel_complex, kGrazingCosFloor
#include "models/spec.h"
#include "models/text_data.h"
#include "util/error.h"
#include "util/hash.h"

namespace ganzfeld {

using std::numbers::pi;

namespace {

constexpr const char* kFirstSurfaceMagic = "ganzfeld-beard-maxwell-first-surface 1";
/// Largest first-surface table value accepted (1/sr): with the horizon floor (1e-12 for
/// mu_i mu_j) and the Fresnel ratio (<= 1/kBeardMaxwellMinR0) f stays below ~1e24, finite.
constexpr double kMaxTableValue = 1e6;
/// exp(-x) underflows to 0 in double beyond this: the Beckmann lobe is 0 there.
constexpr double kExpUnderflow = 700.0;
/// A retro (beta = 0) kink of SO is hinted only where the first surface weighs at least this
/// fraction of its peak; elsewhere it is invisible at any tolerance we use.
constexpr double kRetroHintFraction = 1e-9;

constexpr double kDeg = pi / 180.0;

/// Defaults of the built-in first surface (a glossy paint: B = R(0) of n = 1.5).
constexpr double kDefaultB = 0.04, kDefaultM = 0.15;

}  // namespace

// ---------------------------------------------------------------------------------------------
double beard_maxwell_so(double theta_N, double beta, double tau, double omega) noexcept {
  const double x = theta_N / omega;
  return (1.0 + x * std::exp(-2.0 * beta / tau)) / (1.0 + x);
}

FirstSurfaceTable parse_first_surface_table(const std::string& text, const std::string& name) {
  TextDataReader in(text, "Beard-Maxwell first-surface table '" + name + "'");
  in.expect_magic(kFirstSurfaceMagic);
  FirstSurfaceTable t;
  t.theta_N = in.read_values("theta_N", 0.0, 90.0, " degrees", true);
  t.rho_fs = in.read_values("rho_fs", 0.0, kMaxTableValue, " 1/sr", false);
  if (t.rho_fs.size() != t.theta_N.size())
    throw in.error("rho_fs has " + std::to_string(t.rho_fs.size()) + " values; theta_N has " +
                   std::to_string(t.theta_N.size()) + " (one rho_fs per theta_N)");
  if (in.next_line()) throw in.error("unexpected content after the rho_fs line");
  return t;
}

// ---------------------------------------------------------------------------------------------
FirstSurface FirstSurface::beckmann(double B, double m) {
  FirstSurface fs;
  fs.B_ = B;
  fs.m_ = m;
  fs.width_ = std::atan(m);  // exp(-tan^2/m^2) = 1/e at tan theta_N = m
  return fs;
}

namespace {

/// Fritsch–Carlson slopes of the monotone piecewise-cubic Hermite interpolant through (x, y):
/// 0 at local extrema, the weighted harmonic mean of the neighbouring secants elsewhere, and
/// shape-preserving three-point end slopes (SciPy's PchipInterpolator). Two nodes: the secant.
std::vector<double> pchip_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  std::vector<double> d(n, 0.0);
  if (n < 2) return d;
  std::vector<double> h(n - 1), delta(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    h[k] = x[k + 1] - x[k];
    delta[k] = (y[k + 1] - y[k]) / h[k];
  }
  if (n == 2) return {delta[0], delta[0]};
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (delta[k - 1] * delta[k] <= 0.0) continue;
    const double w1 = 2.0 * h[k] + h[k - 1], w2 = h[k] + 2.0 * h[k - 1];
    d[k] = (w1 + w2) / (w1 / delta[k - 1] + w2 / delta[k]);
  }
  const auto edge = [](double h0, double h1, double m0, double m1) {
    const double e = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
    if (e * m0 <= 0.0) return 0.0;
    if (m0 * m1 < 0.0 && std::abs(e) > 3.0 * std::abs(m0)) return 3.0 * m0;
    return e;
  };
  d[0] = edge(h[0], h[1], delta[0], delta[1]);
  d[n - 1] = edge(h[n - 2], h[n - 3], delta[n - 2], delta[n - 3]);
  return d;
}

}  // namespace

FirstSurface FirstSurface::table(std::string path, FirstSurfaceTable table, std::string digest) {
  FirstSurface fs;
  fs.path_ = std::move(path);
  fs.digest_ = std::move(digest);
  for (double& t : table.theta_N) t *= kDeg;
  fs.table_ = std::move(table);
  fs.slopes_ = pchip_slopes(fs.table_.theta_N, fs.table_.rho_fs);
  if (fs.table_.theta_N.front() == 0.0) fs.slopes_.front() = 0.0;  // even in theta_N
  // The 1/e half width of rho_fs cos^2 from its value at theta_N = 0, between the nodes.
  const double v0 = fs.rho_fs_cos2(0.0, 1.0);
  fs.width_ = pi / 2;
  if (v0 > 0.0) {
    const auto& th = fs.table_.theta_N;
    double prev_t = 0.0, prev_v = v0;
    for (std::size_t k = 0; k < th.size(); ++k) {
      const double v = fs.rho_fs_cos2(th[k], std::cos(th[k]));
      if (v <= v0 / std::numbers::e) {
        const double target = v0 / std::numbers::e;
        const double s = prev_v > v ? (prev_v - target) / (prev_v - v) : 0.0;
        fs.width_ = std::max(prev_t + s * (th[k] - prev_t), 1e-3);
        break;
      }
      prev_t = th[k];
      prev_v = v;
    }
  }
  return fs;
}

double FirstSurface::rho_fs_cos2(double theta_N, double cos_N) const noexcept {
  if (!(cos_N > 0.0)) return 0.0;
  cos_N = std::min(cos_N, 1.0);
  const double c2 = cos_N * cos_N;
  if (path_.empty()) {
    // B D/(4 cos^2) cos^2 = B exp(-tan^2/m^2) / (4 pi m^2 cos^4)
    const double x = (1.0 - c2) / (c2 * m_ * m_);
    if (x > kExpUnderflow) return 0.0;
    return B_ * std::exp(-x) / (4.0 * pi * m_ * m_ * c2 * c2);
  }
  const auto& th = table_.theta_N;
  const auto& v = table_.rho_fs;
  double rho;
  if (th.size() == 1 || theta_N <= th.front()) {
    rho = v.front();
  } else if (theta_N >= th.back()) {
    rho = v.back();
  } else {
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(th.begin(), th.end(), theta_N) - th.begin()) - 1;
    const double h = th[k + 1] - th[k], t = (theta_N - th[k]) / h, u = 1.0 - t;
    // cubic Hermite basis on [th[k], th[k+1]]
    rho = (1.0 + 2.0 * t) * u * u * v[k] + t * u * u * h * slopes_[k] + t * t * (3.0 - 2.0 * t) * v[k + 1] -
          t * t * u * h * slopes_[k + 1];
    rho = std::max(rho, 0.0);  // monotone between nodes >= 0; guards rounding only
  }
  return rho * c2;
}

// ---------------------------------------------------------------------------------------------
BeardMaxwell::BeardMaxwell(double n, double k, FirstSurface first_surface, double tau_deg, double omega_deg,
                           double rho_D, double rho_V)
    : n_(n),
      k_(k),
      fs_(std::move(first_surface)),
      tau_deg_(tau_deg),
      omega_deg_(omega_deg),
      tau_(tau_deg * kDeg),
      omega_(omega_deg * kDeg),
      rho_D_(rho_D),
      rho_V_(rho_V),
      R0_(fresnel_complex(1.0, n, k)) {}

std::string BeardMaxwell::spec() const {
  ModelSpec spec{
      "beard-maxwell",
      {{"n", n_}, {"k", k_}, {"tau", tau_deg_}, {"omega", omega_deg_}, {"rho_d", rho_D_}, {"rho_v", rho_V_}}};
  if (fs_.is_table())  // the table replaces the analytic first surface's b and m
    spec.file = fs_.path();
  else spec.values.insert({{"b", fs_.B()}, {"m", fs_.m()}});
  return spec_text(spec);
}

double BeardMaxwell::fresnel_ratio(double cos_beta) const noexcept { return fresnel_complex(cos_beta, n_, k_) / R0_; }

double BeardMaxwell::first_surface(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  // Every quantity below is symmetric in i, j (|i - j| = |j - i| exactly): bit-exact reciprocity.
  const Vec3 s = i + j;
  const double len_s = glm::length(s);
  if (!(len_s > 0.0)) return 0.0;  // opposite directions on the horizon: no facet reflects i into j
  const double theta_N = std::atan2(std::hypot(s.x, s.y), s.z);
  const double beta = std::atan2(glm::length(i - j), len_s);  // accurate near 0 and pi/2
  const double q = fs_.rho_fs_cos2(theta_N, s.z / len_s);
  if (!(q > 0.0)) return 0.0;
  const double mu = std::max(i.z, kGrazingCosFloor) * std::max(j.z, kGrazingCosFloor);
  const double v = fresnel_ratio(std::min(0.5 * len_s, 1.0)) * q / mu * beard_maxwell_so(theta_N, beta, tau_, omega_);
  return std::isfinite(v) && v > 0.0 ? v : 0.0;
}

double BeardMaxwell::volumetric(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return rho_D_ + 2.0 * rho_V_ / std::max(i.z + j.z, kGrazingCosFloor);
}

double BeardMaxwell::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return first_surface(i, j) + volumetric(i, j);
}

std::optional<GlslF> BeardMaxwell::glsl_f() const {
  // A first-surface table read from a file has no GLSL form here: the viewer asks the service.
  if (fs_.is_table()) return std::nullopt;
  // As first_surface() + volumetric(): theta_N, beta and the Beckmann rho_fs cos^2 from s = i + j
  // (tan^2 theta_N = |s_xy|^2/s_z^2, no 1 - cos^2 cancellation near the peak).
  const double m2 = fs_.m() * fs_.m();
  return GlslF{std::string(kGlslBelowHorizon) + "  float volumetric = " + decimal_literal(rho_D_) + " + " +
                   decimal_literal(2.0 * rho_V_) + " / max(i.z + j.z, " + decimal_literal(kGrazingCosFloor) +
                   ");\n"
                   "  vec3 s = i + j;\n"
                   "  float len_s = length(s);\n"
                   "  if (!(len_s > 0.0) || !(s.z > 0.0)) return volumetric;\n"
                   "  float theta_N = gz_atan2(length(s.xy), s.z);\n"
                   "  float beta = gz_atan2(length(i - j), len_s);\n"
                   "  float c = s.z / len_s, c2 = c * c;\n"
                   "  float q = " +
                   decimal_literal(fs_.B() / (4.0 * pi * m2)) + " * exp(-dot(s.xy, s.xy) / (s.z * s.z * " +
                   decimal_literal(m2) +
                   ")) / (c2 * c2);\n"
                   "  if (!(q > 0.0)) return volumetric;\n"
                   "  float mu = max(i.z, " +
                   decimal_literal(kGrazingCosFloor) + ") * max(j.z, " + decimal_literal(kGrazingCosFloor) +
                   ");\n"
                   "  float x = theta_N * " +
                   decimal_literal(1.0 / omega_) +
                   ";\n"
                   "  float SO = (1.0 + x * exp(-2.0 * beta * " +
                   decimal_literal(1.0 / tau_) +
                   ")) / (1.0 + x);\n"
                   "  float v = gz_fresnel_complex(min(0.5 * len_s, 1.0), " +
                   decimal_literal(n_) + ", " + decimal_literal(k_) + ") * " + decimal_literal(1.0 / R0_) +
                   " * q / mu * SO;\n"
                   "  return (isinf(v) || isnan(v) || !(v > 0.0) ? 0.0 : v) + volumetric;\n",
               {"gz_atan2", "gz_fresnel_complex"}};
}

MassHints BeardMaxwell::mass_hints(const Vec3& fixed, Varying) const {
  HintBuilder hints;
  const double peak = fs_.rho_fs_cos2(0.0, 1.0);
  if (peak > 0.0 || fs_.is_table()) {
    // theta_N ~ psi/2 near the mirror (psi the angle from the mirror direction).
    hints.lobe(mirror(fixed), std::min(std::sqrt(2.0) * fs_.width(), pi / 2));
    // SO's e^{-2 beta/tau} has a conical kink at k = fixed (beta = |k - fixed|/2).
    const double mu = std::clamp(fixed.z, 0.0, 1.0);
    const double theta_fixed = std::acos(mu);
    if (tau_ < pi / 2 && fs_.rho_fs_cos2(theta_fixed, mu) > kRetroHintFraction * peak)
      hints.lobe(fixed, std::max(tau_, 1e-3));
  }
  // With `fixed` grazing, the facet normal k + fixed turns through 90 degrees within ~fixed.z of
  // the horizon point below -fixed, where the first surface's 1/(mu mu_fixed) is largest: a cone
  // the grid's lines must close in on (g at i = n, j·n = 1e-6: 9.8e-6 off with 1e-8 estimated).
  // The first surface's 1/(mu mu_fixed), floored, makes (k·n) f ramp to 0 across k·n < kGrazingCosFloor
  // whatever `fixed` (h at j·n = 0.3: 7x dishonest without it): kGrazingLayer.
  if (peak > 0.0 || fs_.is_table()) {
    hints.layer(kGrazingLayer);
    if (fixed.z < 1e-3) hints.lobe(glm::normalize(Vec3{-fixed.x, -fixed.y, 0.0}), std::max(fixed.z, kGrazingCosFloor));
  }
  // 2 rho_V/max(mu + mu_fixed, kGrazingCosFloor) switches over mu ~ mu_fixed (as Hapke's
  // 1/(mu_i + mu_j)), and over the floor where mu_fixed is below it: (k·n) f ramps to 2 rho_V across
  // a layer that thin (tests/beard_maxwell_test.cpp, VolumeTermLayerAtAGrazingFixedDirectionIsHonest).
  if (rho_V_ > 0.0) hints.layer(std::max(fixed.z, kGrazingCosFloor));
  return hints.build();
}

// ---------------------------------------------------------------------------------------------
void register_beard_maxwell_models(std::vector<ModelInfo>& c) {
  ModelInfo info{
      "beard-maxwell",
      "paint: first-surface facets + Lambert + volumetric, f = [R(beta)/R(0)] rho_fs(theta_N) cos^2 theta_N "
      "SO/((i.n)(j.n)) + rho_d + 2 rho_v/(i.n + j.n); rho_fs a Beckmann stand-in (b, m) or a table (file=PATH)",
      "Maxwell, Beard, Weiner, Ladd & Ladd 1973, AFAL TR-73-303; NEF form as in Westlund & Meyer 2002, "
      "Graphics Interface; Walker 1999, MSc thesis (U. Oregon), ch. III Beard-Maxwell (eq. III.33)",
      {{"n", ParamType::real, 0.01, 10.0, 1.5, "real part of the complex index n + ik of the first surface"},
       {"k", ParamType::real, 0.0, 20.0, 0.0, "imaginary part (extinction coefficient); R(0) >= 1e-6"},
       {"b", ParamType::real, 0.0, 1.0, kDefaultB,
        "built-in first surface: its reflectance at normal incidence (B = R(0) for a physical interface)"},
       {"m", ParamType::real, 0.01, 1.0, kDefaultM, "built-in first surface: RMS facet slope (Beckmann)"},
       {"tau", ParamType::real, 0.01, 1e6, 15.0, "SO decay angle tau in degrees of beta (half the angle i-j)"},
       {"omega", ParamType::real, 0.01, 1e6, 40.0, "SO obscuration angle Omega in degrees of theta_N"},
       {"rho_d", ParamType::real, 0.0, 1.0, 0.1, "Lambertian BRDF value rho_D in 1/sr (albedo pi rho_D)"},
       {"rho_v", ParamType::real, 0.0, 1.0, 0.01,
        "volumetric rho_V in 1/sr: 2 rho_V/(i.n + j.n), albedo 4 pi rho_V (1 - mu ln(1 + 1/mu))"}},
      {true, true, EnergyClass::not_plausible},
      {},
      nullptr};
  info.make_with_file = [](const std::string& file, const ParamValues& p) -> ModelPtr {
    const double n = p.at("n"), k = p.at("k");
    const double R0 = fresnel_complex(1.0, n, k);
    if (!(R0 >= kBeardMaxwellMinR0))
      throw InputError("beard-maxwell: n=" + format_number(n) + " with k=" + format_number(k) + " gives R(0) = " +
                       format_number(R0) + ", too small for the Fresnel ratio R(beta)/R(0); allowed: R(0) = " +
                       "((n-1)^2 + k^2)/((n+1)^2 + k^2) >= 1e-6");
    FirstSurface fs = FirstSurface::beckmann(p.at("b"), p.at("m"));
    if (!file.empty()) {
      // The table replaces the built-in lobe: b and m would be silently ignored.
      for (const auto& [key, def] : {std::pair{"b", kDefaultB}, std::pair{"m", kDefaultM}})
        if (p.at(key) != def)
          throw InputError("beard-maxwell: " + std::string(key) + "=" + format_number(p.at(key)) +
                           " has no effect with file=" + file +
                           " (the table replaces the built-in first surface); allowed: leave b and m out");
      const std::string text = read_text_file(file, "Beard-Maxwell first-surface table '" + file + "'");
      fs = FirstSurface::table(file, parse_first_surface_table(text, file), util::content_digest_of(text));
    }
    return std::make_shared<BeardMaxwell>(n, k, std::move(fs), p.at("tau"), p.at("omega"), p.at("rho_d"),
                                          p.at("rho_v"));
  };
  info.file_optional = true;
  info.file_meaning =
      "first-surface table rho_fs(theta_N) (docs/models.md); without it the built-in Beckmann stand-in (b, m)";
  c.push_back(std::move(info));
}

}  // namespace ganzfeld
