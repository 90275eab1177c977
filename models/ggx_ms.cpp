#include "models/ggx_ms.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <map>
#include <mutex>
#include <numbers>

#include <boost/math/quadrature/gauss.hpp>

#include "models/ggx_energy.h"
#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld {

using std::numbers::pi;

namespace ggx {

namespace {

/// The rule's level for the nodes; its error is estimated against the next level at a few nodes
/// and added to the table's bound.
constexpr int kRuleLevel = 1;
constexpr int kInitialIntervals = 16;
constexpr int kMaxIntervals = 512;

/// Catmull–Rom weights at t in [0, 1] for the nodes k − 1 … k + 2.
std::array<double, 4> catmull_rom(double t) {
  const double t2 = t * t, t3 = t2 * t;
  return {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
          0.5 * (t3 - t2)};
}

}  // namespace

double EnergyTable::at(double mu) const noexcept {
  const int n = static_cast<int>(E.size()) - 1;  // intervals
  const double s = std::sqrt(std::sqrt(std::clamp(mu, 0.0, 1.0))) * n;
  const int k = std::min(static_cast<int>(s), n - 1);
  // Missing nodes beyond the ends: quadratic extrapolation 3 p0 − 3 p1 + p2.
  auto node = [&](int m) {
    if (m < 0) return 3.0 * E[0] - 3.0 * E[1] + E[2];
    if (m > n) return 3.0 * E[n] - 3.0 * E[n - 1] + E[n - 2];
    return E[m];
  };
  const std::array<double, 4> w = catmull_rom(s - k);
  return w[0] * node(k - 1) + w[1] * node(k) + w[2] * node(k + 1) + w[3] * node(k + 2);
}

namespace {

EnergyTable build(double alpha, G2Form g2) {
  const bool separable = g2 == G2Form::separable;
  auto E = [&](double t) { return ggx_albedo_rule(std::pow(t, 4), alpha, 1.0, separable, kRuleLevel); };
  EnergyTable table;
  for (int k = 0; k <= kInitialIntervals; ++k) table.E.push_back(E(static_cast<double>(k) / kInitialIntervals));
  // Double the nodes until the interpolant at the new nodes (the old midpoints) is within the
  // tolerance of the rule there: the new nodes are then kept, so the check costs nothing extra.
  while (true) {
    const int n = static_cast<int>(table.E.size()) - 1;
    EnergyTable finer;
    double deviation = 0.0;
    std::vector<double> mids(n);  // independent integrals: two threads, the same bits either way
    auto fill = [&](int lo, int hi) {
      for (int k = lo; k < hi; ++k) mids[k] = E((k + 0.5) / n);
    };
    auto half = std::async(std::launch::async, fill, 0, n / 2);
    fill(n / 2, n);
    half.get();
    for (int k = 0; k < n; ++k) {
      const double mid = mids[k];
      deviation = std::max(deviation, std::abs(mid - table.at(std::pow((k + 0.5) / n, 4))));
      finer.E.push_back(table.E[k]);
      finer.E.push_back(mid);
    }
    finer.E.push_back(table.E.back());
    table = std::move(finer);
    // The finer table's error is far below the coarser one's deviation (Catmull–Rom is third
    // order: halving the spacing divides it by ~8); the deviation is kept as the bound.
    table.error = deviation;
    if (deviation <= kEnergyTableTolerance || 2 * n >= kMaxIntervals) break;
  }
  // The rule's own error at a few nodes (its level against the next).
  for (double t : {0.05, 0.3, 0.7, 1.0})
    table.error += ggx_albedo_reference(std::pow(t, 4), alpha, 1.0, separable, kRuleLevel).error;
  // E_avg = 2 ∫ E μ dμ = 8 ∫ E(t⁴) t⁷ dt: per interval a polynomial of degree 10 in t, which
  // the 6-point Gauss–Legendre rule integrates exactly.
  const int n = static_cast<int>(table.E.size()) - 1;
  double sum = 0.0;
  for (int k = 0; k < n; ++k)
    sum += boost::math::quadrature::gauss<double, 6>::integrate(
        [&](double t) { return table.at(std::pow(t, 4)) * std::pow(t, 7); }, static_cast<double>(k) / n, (k + 1.0) / n);
  table.E_avg = 8.0 * sum;
  return table;
}

}  // namespace

std::shared_ptr<const EnergyTable> energy_table(double alpha, G2Form g2) {
  static std::mutex mutex;
  static std::map<std::pair<double, int>, std::shared_ptr<const EnergyTable>> cache;
  const std::pair<double, int> key{alpha, static_cast<int>(g2)};
  {
    std::lock_guard lock(mutex);
    if (const auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto table = std::make_shared<const EnergyTable>(build(alpha, g2));  // outside the lock: may take a while
  std::lock_guard lock(mutex);
  return cache.emplace(key, table).first->second;
}

}  // namespace ggx

GgxMs::GgxMs(double alpha, double f0, ggx::G2Form g2)
    : ggx_({alpha, alpha}, f0, g2), energy_(ggx::energy_table(alpha, g2)) {
  const double F_avg = f0 + (1.0 - f0) / 21.0;  // 2 ∫ (1 − μ)⁵ μ dμ = 1/21
  const double E_avg = energy_->E_avg;
  const double F_ms = F_avg * F_avg * E_avg / (1.0 - F_avg * (1.0 - E_avg));
  f_ms_scale_ = E_avg < 1.0 ? F_ms / (pi * (1.0 - E_avg)) : 0.0;
}

std::string GgxMs::spec() const { return spec_text({"ggx-ms", ggx_.parameters()}); }

double GgxMs::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  return ggx_.f(i, j) + f_ms_scale_ * (1.0 - energy_->at(i.z)) * (1.0 - energy_->at(j.z));
}

std::optional<GlslF> GgxMs::glsl_f() const {
  // 1 - E(mu) as 1 - ggx::EnergyTable::at: Catmull-Rom in mu^(1/4) on the table's nodes, quadratic
  // extrapolation beyond its ends (both affine, so interpolating 1 - E is the same and keeps the
  // small 1 - E of a smooth surface to float precision); the nodes as a constant array.
  const std::vector<double>& E = energy_->E;
  const int n = static_cast<int>(E.size()) - 1;
  std::string nodes;
  for (double e : E) nodes += (nodes.empty() ? "" : ", ") + decimal_literal(1.0 - e);
  return GlslF{std::string(kGlslBelowHorizon) + ggx_.glsl_single_scattering() + "  const float E[" +
                   std::to_string(n + 1) + "] = float[" + std::to_string(n + 1) + "](" + nodes +
                   ");\n"
                   "  float one_minus_E[2];\n"
                   "  for (int q = 0; q < 2; ++q) {\n"
                   "    float u = sqrt(sqrt(clamp(q == 0 ? i.z : j.z, 0.0, 1.0))) * " +
                   std::to_string(n) +
                   ".0;\n"
                   "    int k = min(int(u), " +
                   std::to_string(n - 1) +
                   ");\n"
                   "    float t = u - float(k), t2 = t * t, t3 = t2 * t;\n"
                   "    float p[4];\n"
                   "    for (int c = 0; c < 4; ++c) {\n"
                   "      int m = k - 1 + c;\n"
                   "      p[c] = m < 0 ? 3.0 * E[0] - 3.0 * E[1] + E[2]\n"
                   "           : m > " +
                   std::to_string(n) + " ? 3.0 * E[" + std::to_string(n) + "] - 3.0 * E[" + std::to_string(n - 1) +
                   "] + E[" + std::to_string(n - 2) +
                   "] : E[m];\n"
                   "    }\n"
                   "    float e = 0.5 * ((-t3 + 2.0 * t2 - t) * p[0] + (3.0 * t3 - 5.0 * t2 + 2.0) * p[1]\n"
                   "                     + (-3.0 * t3 + 4.0 * t2 + t) * p[2] + (t3 - t2) * p[3]);\n"
                   "    one_minus_E[q] = e;\n"
                   "  }\n"
                   "  return ggx_value + " +
                   decimal_literal(f_ms_scale_) + " * one_minus_E[0] * one_minus_E[1];\n",
               {"gz_schlick"}};
}

std::optional<IncidentSample> GgxMs::sample_incident(const Vec3& j, const std::array<double, 3>& u) const {
  if (!(j.z > 0.0)) return std::nullopt;
  const Vec3 i = u[2] < energy_->at(j.z) ? [&] {
    const auto s = ggx_.sample_incident(j, u);
    return s ? s->i : Vec3{0.0, 0.0, -1.0};
  }()
                                          : sample_cosine(u[0], u[1]);
  const double pdf = pdf_incident(j, i);
  if (!(i.z > 0.0) || !(pdf > 0.0)) return std::nullopt;
  return IncidentSample{i, pdf};
}

double GgxMs::pdf_incident(const Vec3& j, const Vec3& i) const {
  if (!(j.z > 0.0) || !(i.z > 0.0)) return 0.0;
  const double p = energy_->at(j.z);
  return p * ggx_.pdf_incident(j, i) + (1.0 - p) * i.z / pi;
}

}  // namespace ganzfeld
