#include "export/brdf_export.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numbers>
#include <random>

#include "models/registry.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace ganzfeld::exporting {

namespace {
/// The noise factor of each node in writing order: 1 without noise.
class NoiseFactors {
 public:
  explicit NoiseFactors(const Noise& noise) : sigma_(noise.sigma), engine_(noise.seed) {}
  double next() { return sigma_ > 0.0 ? 1.0 + sigma_ * normal_(engine_) : 1.0; }

 private:
  double sigma_;
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_;
};
}  // namespace

void validate_noise(const Noise& noise) {
  if (!std::isfinite(noise.sigma) || noise.sigma < 0.0 || noise.sigma > 1.0)
    throw InputError(
        {Named{"noise", format_number(noise.sigma)}, " is not allowed; allowed: a relative sigma in [0, 1]"});
}

std::vector<char> merl_bytes(const Model& model, const Noise& noise) {
  validate_noise(noise);
  NoiseFactors factors(noise);
  std::vector<char> bytes(merl::kFileBytes);
  const std::int32_t dims[3] = {merl::kThetaHalf, merl::kThetaDiff, merl::kPhiDiff};
  std::memcpy(bytes.data(), dims, sizeof dims);
  // The doubles start at byte 12, unaligned: copied in one by one.
  std::size_t index = 0;
  for (int kh = 0; kh < merl::kThetaHalf; ++kh)
    for (int kd = 0; kd < merl::kThetaDiff; ++kd)
      for (int kp = 0; kp < merl::kPhiDiff; ++kp, ++index) {
        const auto [i, j] = merl::directions(merl::node_angles(kh, kd, kp));
        const bool valid = i.z >= 0.0 && j.z >= 0.0;
        const double f = valid ? std::max(0.0, model.f(i, j) * factors.next()) : 0.0;
        for (int c = 0; c < 3; ++c) {
          const double stored = valid ? f / merl::kScale[c] : -1.0;
          std::memcpy(bytes.data() + sizeof dims + (c * merl::kSamples + index) * 8, &stored, 8);
        }
      }
  return bytes;
}

void write_merl(const Model& model, const std::string& path, const Noise& noise) {
  const std::vector<char> bytes = merl_bytes(model, noise);
  write_atomically(
      path,
      [&](const std::string& temp) {
        std::ofstream out(temp, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        if (!out.flush()) throw std::runtime_error("write failed");
      },
      "MERL file");
}

TabulatedBrdf tabulate(const Model& model, const std::vector<int>& counts, const Noise& noise) {
  validate_noise(noise);
  NoiseFactors factors(noise);
  if (counts.size() != 3 || counts[0] < 2 || counts[1] < 2 || counts[2] < 2 || counts[0] > 1000 || counts[1] > 1000 ||
      counts[2] > 1000)
    throw InputError("a tabulated BRDF needs 3 node counts (theta_i x theta_r x phi), each in 2..1000");
  TabulatedBrdf t;
  auto grid = [](int n, double max) {
    std::vector<double> g(n);
    for (int k = 0; k < n; ++k) g[k] = max * k / (n - 1);
    return g;
  };
  t.theta_i = grid(counts[0], 90.0);
  t.theta_r = grid(counts[1], 90.0);
  t.phi = grid(counts[2], 180.0);
  const double rad = std::numbers::pi / 180.0;
  for (double ti : t.theta_i)
    for (double tr : t.theta_r)
      for (double p : t.phi) {
        const Vec3 i{std::sin(ti * rad), 0.0, std::cos(ti * rad)};
        const Vec3 j{std::sin(tr * rad) * std::cos(p * rad), std::sin(tr * rad) * std::sin(p * rad),
                     std::cos(tr * rad)};
        t.values.push_back(std::max(0.0, model.f(i, j) * factors.next()));
      }
  return t;
}

void write_tabulated(const Model& model, const std::vector<int>& counts, const std::string& path, const Noise& noise) {
  const std::string comment =
      "tabulated from " + model.spec() +
      (noise.sigma > 0.0 ? " with noise sigma " + format_number(noise.sigma) + ", seed " + std::to_string(noise.seed)
                         : "");
  write_text_atomically(path, format_tabulated(tabulate(model, counts, noise), comment), "table");
}

}  // namespace ganzfeld::exporting
