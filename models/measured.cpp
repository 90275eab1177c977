#include "models/measured.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "models/registry.h"
#include "models/spec.h"
#include "models/text_data.h"
#include "util/error.h"
#include "util/hash.h"

namespace ganzfeld {

using std::numbers::pi;

namespace merl {

namespace {
/// Rodrigues' rotation of v about the unit axis by angle (MERL's rotate_vector).
Vec3 rotate(const Vec3& v, const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (glm::dot(axis, v) * (1.0 - c)) + glm::cross(axis, v) * s;
}
const Vec3 kNormal{0, 0, 1}, kBinormal{0, 1, 0};
}  // namespace

HalfDiff half_diff(const Vec3& i, const Vec3& j) noexcept {
  const Vec3 sum = i + j;
  const double len = glm::length(sum);
  const Vec3 h = len > 0.0 ? sum / len : kNormal;
  HalfDiff out;
  out.theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
  const double phi_h = std::atan2(h.y, h.x);
  const Vec3 diff = rotate(rotate(i, kNormal, -phi_h), kBinormal, -out.theta_h);
  out.theta_d = std::acos(std::clamp(diff.z, -1.0, 1.0));
  out.phi_d = std::atan2(diff.y, diff.x);
  return out;
}

std::array<Vec3, 2> directions(const HalfDiff& a) noexcept {
  const Vec3 diff{std::sin(a.theta_d) * std::cos(a.phi_d), std::sin(a.theta_d) * std::sin(a.phi_d),
                  std::cos(a.theta_d)};
  const Vec3 i = rotate(diff, kBinormal, a.theta_h);
  const Vec3 h{std::sin(a.theta_h), 0.0, std::cos(a.theta_h)};
  return {i, 2.0 * glm::dot(i, h) * h - i};
}

HalfDiff node_angles(int kh, int kd, int kp) noexcept {
  const double u = static_cast<double>(kh) / kThetaHalf;
  return {u * u * (pi / 2), static_cast<double>(kd) / kThetaDiff * (pi / 2), static_cast<double>(kp) / kPhiDiff * pi};
}

}  // namespace merl

// ---------------------------------------------------------------------------------------------
std::shared_ptr<const MerlData> read_merl(const std::string& path) {
  std::error_code ec;  // not a device or FIFO (a FIFO would block)
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError("cannot read MERL file '" + path + "': not a regular file");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError("cannot read MERL file '" + path + "'");
  const auto size = static_cast<std::size_t>(in.tellg());
  in.seekg(0);
  if (size < 12)
    throw InputError("MERL file '" + path + "' has " + std::to_string(size) + " bytes; a MERL file has " +
                     std::to_string(merl::kFileBytes));
  std::int32_t dims[3];
  in.read(reinterpret_cast<char*>(dims), sizeof dims);
  if (dims[0] != merl::kThetaHalf || dims[1] != merl::kThetaDiff || dims[2] != merl::kPhiDiff)
    throw InputError("MERL file '" + path + "' has dimensions " + std::to_string(dims[0]) + "x" +
                     std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + "; allowed: 90x90x180");
  if (size != merl::kFileBytes)
    throw InputError("MERL file '" + path + "' has " + std::to_string(size) + " bytes; 90x90x180 needs " +
                     std::to_string(merl::kFileBytes));
  auto data = std::make_shared<MerlData>();
  data->values.resize(3 * merl::kSamples);
  in.read(reinterpret_cast<char*>(data->values.data()), static_cast<std::streamsize>(data->values.size() * 8));
  if (!in) throw InputError("MERL file '" + path + "' could not be read completely");
  for (std::size_t k = 0; k < data->values.size(); ++k)
    if (!std::isfinite(data->values[k]))
      throw InputError("MERL file '" + path + "' holds a non-finite value at sample " + std::to_string(k));
  // The header and the samples as read are the file's bytes in order (the size was checked).
  const std::uint64_t hash = util::fnv1a_64({reinterpret_cast<const char*>(dims), sizeof dims});
  data->digest = util::content_digest(
      util::fnv1a_64({reinterpret_cast<const char*>(data->values.data()), data->values.size() * sizeof(double)}, hash));
  return data;
}

MerlModel::MerlModel(std::string path, std::shared_ptr<const MerlData> data, int channel, int lookup)
    : path_(std::move(path)), data_(std::move(data)), channel_(channel), lookup_(lookup) {
  // The specular peak's width: the theta_h where the data (at theta_d = 20 deg) falls to half
  // its value at theta_h = 0; the reflected lobe is twice as wide in direction space.
  const int kd = 20;
  const double top = node(0, kd, 0);
  peak_width_ = 0.5;
  if (top > 0.0)
    for (int kh = 1; kh < merl::kThetaHalf; ++kh) {
      const double v = node(kh, kd, 0);
      if (v >= 0.0 && v < 0.5 * top) {
        peak_width_ = std::max(1e-3, 2.0 * merl::node_angles(kh, kd, 0).theta_h);
        break;
      }
    }
}

double MerlModel::node(int kh, int kd, int kp) const noexcept {
  const std::size_t index = (static_cast<std::size_t>(kh) * merl::kThetaDiff + kd) * merl::kPhiDiff + kp;
  auto channel_value = [&](int c) {
    const double v = data_->values[c * merl::kSamples + index];
    return v < 0.0 ? -1.0 : v * merl::kScale[c];
  };
  if (channel_ < 3) return channel_value(channel_);
  const double r = channel_value(0), g = channel_value(1), b = channel_value(2);
  if (r < 0.0 || g < 0.0 || b < 0.0) return -1.0;
  return (r + g + b) / 3.0;
}

double MerlModel::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  merl::HalfDiff a = merl::half_diff(i, j);
  if (a.phi_d < 0.0) a.phi_d += pi;  // reciprocity fold, as BRDFRead.cpp
  const double uh = merl::kThetaHalf * std::sqrt(std::max(0.0, a.theta_h / (pi / 2)));
  const double ud = a.theta_d / (pi / 2) * merl::kThetaDiff;
  const double up = a.phi_d / pi * merl::kPhiDiff;
  if (lookup_ == 0) {  // MERL's reader: truncate to the cell, clamp to the grid
    const int kh = std::clamp(static_cast<int>(uh), 0, merl::kThetaHalf - 1);
    const int kd = std::clamp(static_cast<int>(ud), 0, merl::kThetaDiff - 1);
    const int kp = std::clamp(static_cast<int>(up), 0, merl::kPhiDiff - 1);
    const double v = node(kh, kd, kp);
    if (v >= 0.0) return v;
    // The cell's node is invalid (its own configuration lies below the horizon, or it was not
    // measured) although (i, j) is valid: fall through to the interpolation of the valid ones.
  }
  // Multilinear: theta axes clamp at their last node; phi_diff wraps (phi_d + pi = phi_d).
  const double sh = std::clamp(uh, 0.0, merl::kThetaHalf - 1.0), sd = std::clamp(ud, 0.0, merl::kThetaDiff - 1.0);
  const int h0 = std::min(static_cast<int>(sh), merl::kThetaHalf - 2),
            d0 = std::min(static_cast<int>(sd), merl::kThetaDiff - 2);
  const int p0 = std::clamp(static_cast<int>(up), 0, merl::kPhiDiff - 1);
  const double th = sh - h0, td = sd - d0, tp = std::clamp(up - p0, 0.0, 1.0);
  double sum = 0.0, weight = 0.0;
  for (int c = 0; c < 8; ++c) {
    const int kh = h0 + (c & 1), kd = d0 + ((c >> 1) & 1), kp = (p0 + ((c >> 2) & 1)) % merl::kPhiDiff;
    const double w = ((c & 1) ? th : 1.0 - th) * (((c >> 1) & 1) ? td : 1.0 - td) * (((c >> 2) & 1) ? tp : 1.0 - tp);
    if (w == 0.0) continue;
    const double v = node(kh, kd, kp);
    if (v < 0.0) continue;  // invalid sample: left out, the rest renormalized
    sum += w * v;
    weight += w;
  }
  return weight > 0.0 ? sum / weight : 0.0;
}

MassHints MerlModel::mass_hints(const Vec3& fixed, Varying) const {
  return HintBuilder().lobe(mirror(fixed), peak_width_).build();
}

std::string MerlModel::spec() const {
  return spec_text(
      {"merl", {{"channel", static_cast<double>(channel_)}, {"lookup", static_cast<double>(lookup_)}}, path_});
}

Traits MerlModel::traits() const {
  // Isotropic and reciprocal by the format's construction (phi_d folded); energy not guaranteed.
  return {true, true, EnergyClass::not_plausible};
}

// ---------------------------------------------------------------------------------------------
namespace {

constexpr const char* kTabulatedMagic = "ganzfeld-tabulated-brdf 1";

/// Multilinear position of x on a strictly increasing grid (clamped).
void locate(const std::vector<double>& grid, double x, int& k, double& t) {
  if (grid.size() == 1) {
    k = 0;
    t = 0.0;
    return;
  }
  x = std::clamp(x, grid.front(), grid.back());
  k = static_cast<int>(std::upper_bound(grid.begin(), grid.end(), x) - grid.begin()) - 1;
  k = std::clamp(k, 0, static_cast<int>(grid.size()) - 2);
  t = (x - grid[k]) / (grid[k + 1] - grid[k]);
}

}  // namespace

TabulatedBrdf parse_tabulated(const std::string& text, const std::string& name) {
  TextDataReader in(text, "tabulated BRDF '" + name + "'");
  in.expect_magic(kTabulatedMagic);
  TabulatedBrdf t;
  t.theta_i = in.read_values("theta_i", 0.0, 90.0, " degrees", true);
  t.theta_r = in.read_values("theta_r", 0.0, 90.0, " degrees", true);
  t.phi = in.read_values("phi", 0.0, 180.0, " degrees", true);
  const std::size_t want = t.theta_i.size() * t.theta_r.size() * t.phi.size();
  while (in.next_line()) {
    std::istringstream ls(in.line());
    std::string word;
    while (ls >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end != word.c_str() + word.size()) throw in.error("'" + word + "' is not a number");
      if (!std::isfinite(v) || v < 0.0)
        throw in.error("BRDF value " + word + " is not allowed; values must be finite and >= 0");
      t.values.push_back(v);
    }
  }
  if (t.values.size() != want)
    throw InputError("tabulated BRDF '" + name + "' has " + std::to_string(t.values.size()) +
                     " values; its grid needs " + std::to_string(want));
  return t;
}

std::string format_tabulated(const TabulatedBrdf& table, const std::string& comment) {
  std::ostringstream s;
  s << kTabulatedMagic << "\n# " << comment << "\n";
  auto axis = [&](const char* key, const std::vector<double>& v) {
    s << key << ":";
    for (double x : v) s << " " << format_number(x);
    s << "\n";
  };
  axis("theta_i", table.theta_i);
  axis("theta_r", table.theta_r);
  axis("phi", table.phi);
  for (std::size_t k = 0; k < table.values.size(); ++k)
    s << format_number(table.values[k]) << ((k + 1) % table.phi.size() == 0 ? "\n" : " ");
  return s.str();
}

TabulatedModel::TabulatedModel(std::string path, TabulatedBrdf table, int lookup, std::string digest)
    : path_(std::move(path)), table_(std::move(table)), lookup_(lookup), digest_(std::move(digest)) {}

std::string TabulatedModel::spec() const {
  return spec_text({"tabulated", {{"lookup", static_cast<double>(lookup_)}}, path_});
}

Traits TabulatedModel::traits() const { return {true, false, EnergyClass::not_plausible}; }

double TabulatedModel::f(const Vec3& i, const Vec3& j) const noexcept {
  if (i.z < 0.0 || j.z < 0.0) return 0.0;
  const double deg = 180.0 / pi;
  const double ti = std::acos(std::clamp(i.z, -1.0, 1.0)) * deg, tr = std::acos(std::clamp(j.z, -1.0, 1.0)) * deg;
  double phi = 0.0;
  const double ri = std::hypot(i.x, i.y), rj = std::hypot(j.x, j.y);
  if (ri > 0.0 && rj > 0.0) phi = std::abs(std::atan2(i.x * j.y - i.y * j.x, i.x * j.x + i.y * j.y)) * deg;
  int k[3];
  double t[3];
  locate(table_.theta_i, ti, k[0], t[0]);
  locate(table_.theta_r, tr, k[1], t[1]);
  locate(table_.phi, phi, k[2], t[2]);
  const int n[3] = {static_cast<int>(table_.theta_i.size()), static_cast<int>(table_.theta_r.size()),
                    static_cast<int>(table_.phi.size())};
  if (lookup_ == 0)  // nearest node
    for (int d = 0; d < 3; ++d) {
      if (t[d] >= 0.5 && k[d] + 1 < n[d]) ++k[d];
      t[d] = 0.0;
    }
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    double w = 1.0;
    int idx[3];
    for (int d = 0; d < 3; ++d) {
      const bool up = (c >> d) & 1;
      w *= up ? t[d] : 1.0 - t[d];
      idx[d] = std::min(k[d] + (up ? 1 : 0), n[d] - 1);
    }
    if (w == 0.0) continue;
    sum += w * table_.values[(static_cast<std::size_t>(idx[0]) * n[1] + idx[1]) * n[2] + idx[2]];
  }
  return sum;
}

// ---------------------------------------------------------------------------------------------
void register_measured_models(std::vector<ModelInfo>& catalogue) {
  using P = ParamType;
  ModelInfo merl_info{"merl",
                      "measured isotropic BRDF from a MERL binary file (file=PATH; 90x90x180 half/difference "
                      "angles, channel scales 1/1500, 1.15/1500, 1.66/1500)",
                      "Matusik, Pfister, Brand, McMillan 2003, \"A Data-Driven Reflectance Model\"; MERL BRDFRead.cpp",
                      {{"channel", P::integer, 0.0, 3.0, 3.0, "0 red, 1 green, 2 blue, 3 mean of the three"},
                       {"lookup", P::integer, 0.0, 1.0, 1.0, "0 MERL's truncation to the cell, 1 multilinear"}},
                      {true, true, EnergyClass::not_plausible},
                      {},
                      nullptr};
  merl_info.make_with_file = [](const std::string& file, const ParamValues& v) -> ModelPtr {
    return std::make_shared<MerlModel>(file, read_merl(file), static_cast<int>(v.at("channel")),
                                       static_cast<int>(v.at("lookup")));
  };
  catalogue.push_back(std::move(merl_info));
  ModelInfo tab_info{"tabulated",
                     "measured isotropic BRDF from ganzfeld's text table (file=PATH; grid of theta_i, theta_r, phi in "
                     "degrees; docs/measured.md)",
                     "docs/measured.md",
                     {{"lookup", P::integer, 0.0, 1.0, 1.0, "0 nearest node, 1 multilinear"}},
                     {true, false, EnergyClass::not_plausible},
                     {},
                     nullptr};
  tab_info.make_with_file = [](const std::string& file, const ParamValues& v) -> ModelPtr {
    const std::string text = read_text_file(file, "tabulated BRDF '" + file + "'");
    return std::make_shared<TabulatedModel>(file, parse_tabulated(text, file), static_cast<int>(v.at("lookup")),
                                            util::content_digest_of(text));
  };
  catalogue.push_back(std::move(tab_info));
}

}  // namespace ganzfeld
