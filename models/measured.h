// Measured BRDFs behind the Model interface:
//
//  merl:file=PATH[,channel=C][,lookup=L]   a MERL isotropic BRDF file (Matusik et al., "A
//      Data-Driven Reflectance Model", SIGGRAPH 2003; the format of MERL's BRDFRead.cpp):
//      three int32 dimensions 90, 90, 180, then planar float64 R, G, B arrays indexed
//      [theta_half][theta_diff][phi_diff] (phi_diff fastest), scaled by 1/1500, 1.15/1500 and
//      1.66/1500; negative entries mark invalid (unmeasured) samples. Indices (Rusinkiewicz's
//      half/difference angles):
//        theta_half  k = 90 sqrt(theta_h / (pi/2))   (dense near the specular peak)
//        theta_diff  k = 90 theta_d / (pi/2)
//        phi_diff    k = 180 phi_d / pi, phi_d folded into [0, pi) (reciprocity: f(phi_d) = f(phi_d + pi))
//      channel: 0 red, 1 green, 2 blue, 3 the mean of the three (default).
//      lookup 0: MERL's own rule (truncate each index to its cell; where that node is invalid, the
//      interpolation below); lookup 1 (default): multilinear between the nodes, wrapping phi_diff,
//      invalid nodes left out and the weights renormalized (0 where all eight are invalid).
//  tabulated:file=PATH[,lookup=L]   our own isotropic table (docs/measured.md): a text file
//      "ganzfeld-tabulated-brdf 1", the grid of theta_i, theta_r (degrees, [0, 90]) and relative
//      azimuth phi (degrees, [0, 180]), then f in 1/sr for every grid point, phi fastest. NEF-style
//      measurements resampled onto a grid fit it.
//
// File paths go into the spec as `file=PATH`; a path must not contain ',', '+' or '*'.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld {

namespace merl {
inline constexpr int kThetaHalf = 90, kThetaDiff = 90, kPhiDiff = 180;
inline constexpr std::size_t kSamples = std::size_t{kThetaHalf} * kThetaDiff * kPhiDiff;
inline constexpr std::array<double, 3> kScale{1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
/// Bytes of a valid file: the header and three channels of float64.
inline constexpr std::size_t kFileBytes = 3 * 4 + 3 * kSamples * 8;

/// Rusinkiewicz's half/difference angles of (i, j) as MERL's std_coords_to_half_diff_coords
/// computes them: theta_h, theta_d in [0, pi/2] (for directions above the horizon), phi_d in (-pi, pi].
struct HalfDiff {
  double theta_h = 0.0, theta_d = 0.0, phi_d = 0.0;
};
HalfDiff half_diff(const Vec3& i, const Vec3& j) noexcept;
/// The inverse for phi_h = 0: (i, j) with half_diff(i, j) = (theta_h, theta_d, phi_d).
std::array<Vec3, 2> directions(const HalfDiff& angles) noexcept;
/// The angles of node (kh, kd, kp).
HalfDiff node_angles(int kh, int kd, int kp) noexcept;
}  // namespace merl

/// A MERL file's three channels, unscaled (as stored).
struct MerlData {
  std::vector<double> values;  ///< 3 * kSamples: R, then G, then B
  std::string digest;          ///< util::content_digest of the file's bytes
};
/// Reads and validates a MERL file: size exactly kFileBytes, dimensions 90 x 90 x 180, no NaN or
/// Inf. Throws InputError naming the file and the problem.
std::shared_ptr<const MerlData> read_merl(const std::string& path);

class MerlModel final : public Model {
 public:
  MerlModel(std::string path, std::shared_ptr<const MerlData> data, int channel, int lookup);
  std::string spec() const override;
  std::string content_digest() const override { return data_->digest; }
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  MassHints mass_hints(const Vec3& fixed, Varying varying) const override;
  /// The stored value of node (kh, kd, kp) in 1/sr for this channel; negative when invalid.
  double node(int kh, int kd, int kp) const noexcept;

 private:
  std::string path_;
  std::shared_ptr<const MerlData> data_;
  int channel_, lookup_;
  double peak_width_;  ///< angular half width of the specular peak, estimated from the data
};

/// Our tabulated isotropic BRDF (see above).
struct TabulatedBrdf {
  std::vector<double> theta_i, theta_r, phi;  ///< degrees, strictly increasing
  std::vector<double> values;                 ///< 1/sr, [theta_i][theta_r][phi], phi fastest
};
/// Parses the text format; throws InputError naming the file, the line and the problem.
TabulatedBrdf parse_tabulated(const std::string& text, const std::string& name);
/// The text of a table (exactly what parse_tabulated reads).
std::string format_tabulated(const TabulatedBrdf& table, const std::string& comment);

class TabulatedModel final : public Model {
 public:
  /// `digest`: util::content_digest of the file's bytes.
  TabulatedModel(std::string path, TabulatedBrdf table, int lookup, std::string digest);
  std::string spec() const override;
  std::string content_digest() const override { return digest_; }
  Traits traits() const override;
  double f(const Vec3& i, const Vec3& j) const noexcept override;
  /// The grid and values as read (f at the nodes, exactly).
  const TabulatedBrdf& table() const { return table_; }

 private:
  std::string path_;
  TabulatedBrdf table_;
  int lookup_;
  std::string digest_;
};

}  // namespace ganzfeld
