#include "models/ggx_energy.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>

namespace ganzfeld::ggx {

namespace {

using std::numbers::pi;
using Rule = boost::math::quadrature::gauss<double, 20>;

/// ∫₀^b F(x) dx by the 20-point Gauss–Legendre rule on each panel between sorted cuts.
template <typename F>
double gauss_panels(const std::vector<double>& cuts, F&& f) {
  double sum = 0.0;
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
    const double a = cuts[p], b = cuts[p + 1], half = 0.5 * (b - a), mid = 0.5 * (a + b);
    if (!(b > a)) continue;
    // Boost stores the non-negative abscissas; each x > 0 stands for ±x.
    const auto& x = Rule::abscissa();
    const auto& w = Rule::weights();
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double term = x[k] == 0.0 ? f(mid) : f(mid - half * x[k]) + f(mid + half * x[k]);
      sum += half * w[k] * term;
    }
  }
  return sum;
}

/// Cuts of [0, hi]: 4 level equal panels, plus geometric ones (ratio 2^(1/level)) towards 0 and
/// π/2 down to the scale alpha/4, and towards hi = θ* down to the scale mu/4 (near grazing the
/// masking of o changes within o_z ~ μ of the horizon).
std::vector<double> theta_cuts(double hi, double alpha, double mu, int level) {
  std::vector<double> cuts{0.0, hi};
  const double ratio = std::pow(2.0, 1.0 / level);
  for (double s = 0.25 * alpha; s < pi / 2; s *= ratio) {
    cuts.push_back(s);
    cuts.push_back(pi / 2 - s);
  }
  for (double s = 0.25 * mu; s > 0.0 && s < 0.25; s *= ratio) cuts.push_back(hi - s);
  const int uniform = 4 * level;
  for (int k = 1; k < uniform; ++k) cuts.push_back(hi * k / uniform);
  std::erase_if(cuts, [&](double c) { return !(c >= 0.0 && c <= hi); });
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  return cuts;
}

/// One level of the rule for an integrand g(cos θ_o, v·h, θ_h) = f cos θ_o 4 (v·h) (per dθ dφ,
/// without sin θ_h).
double rule(double mu, double alpha, int level, const std::function<double(double, double, double)>& g) {
  const double sin_v = std::sqrt(std::max(0.0, 1.0 - mu * mu));  // μ = 0: θ* = π/4 ± π/4 by the sign of cos φ_h
  std::vector<double> phi_cuts;
  const int phi_panels = 8 * level;
  for (int k = 0; k <= phi_panels; ++k) phi_cuts.push_back(pi * k / phi_panels);
  // θ* swings from above π/4 to below it across φ_h = π/2 within ~μ/sin θ_v: geometric cuts there.
  const double ratio = std::pow(2.0, 1.0 / level);
  for (double w = 0.25 * mu / std::max(sin_v, 1e-300); w > 0.0 && w < pi / phi_panels; w *= ratio) {
    phi_cuts.push_back(pi / 2 - w);
    phi_cuts.push_back(pi / 2 + w);
  }
  std::sort(phi_cuts.begin(), phi_cuts.end());
  const double half_circle = gauss_panels(phi_cuts, [&](double phi) {
    const double cos_phi = std::cos(phi);
    const double theta_star = 0.5 * std::atan2(sin_v * cos_phi, mu) + pi / 4;
    return gauss_panels(theta_cuts(theta_star, alpha, mu, level), [&](double theta) {
      const double s = std::sin(theta), c = std::cos(theta);
      const double vh = sin_v * s * cos_phi + mu * c;
      const double o_z = 2.0 * vh * c - mu;
      if (!(o_z > 0.0) || !(vh > 0.0)) return 0.0;
      return g(o_z, vh, theta) * s;
    });
  });
  return 2.0 * half_circle;  // even in φ_h
}

ReferenceValue converged(const std::function<double(int)>& at, int level) {
  const double coarse = at(level), fine = at(level + 1);
  return {fine, std::abs(fine - coarse)};
}

/// Smith Λ of GGX for a direction with cos θ = z (Heitz 2014 eq. 86), written out here.
double lambda(double z, double alpha) {
  const double tan2 = (1.0 - z * z) / (z * z);
  return 0.5 * (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

}  // namespace

double ggx_albedo_rule(double mu, double alpha, double f0, bool separable, int level) {
  const double a2 = alpha * alpha;
  // μ Λ(v) = (sqrt(μ² + α² (1 − μ²)) − μ)/2 stays finite at μ = 0, and so does G2/μ below.
  const double mu_lambda_v = 0.5 * (std::sqrt(mu * mu + a2 * (1.0 - mu * mu)) - mu);
  auto g = [&](double o_z, double vh, double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    const double q = a2 * c * c + s * s;
    const double D = a2 / (pi * q * q);  // Walter eq. 33 with 1 + (α² − 1) cos² = α² cos² + sin²
    const double lambda_o = lambda(o_z, alpha);
    const double G2_over_mu =
        separable ? 1.0 / ((mu + mu_lambda_v) * (1.0 + lambda_o)) : 1.0 / (mu * (1.0 + lambda_o) + mu_lambda_v);
    const double F = f0 + (1.0 - f0) * std::pow(1.0 - vh, 5);
    // f cos θ_o 4 (v·h) = F D G2/(4 μ o_z) · o_z · 4 (v·h).
    return F * D * G2_over_mu * vh;
  };
  return rule(mu, alpha, level, g);
}

ReferenceValue ggx_albedo_reference(double mu, double alpha, double f0, bool separable, int level) {
  return converged([&](int l) { return ggx_albedo_rule(mu, alpha, f0, separable, l); }, level);
}

ReferenceValue charlie_albedo_reference(double mu, double alpha, int level) {
  auto g = [&](double o_z, double vh, double theta) {
    const double D = (2.0 + 1.0 / alpha) * std::pow(std::sin(theta), 1.0 / alpha) / (2.0 * pi);
    const double V = 1.0 / (4.0 * (mu + o_z - mu * o_z));
    return D * V * o_z * 4.0 * vh;
  };
  return converged([&](int l) { return rule(mu, alpha, l, g); }, level);
}

}  // namespace ganzfeld::ggx
