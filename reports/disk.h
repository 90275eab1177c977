// The halfway-vector disk view of any BRDF: Edwards et al. 2006, §5 and Fig. 13 ("screenshots of
// our BRDF-fitting software showing the distribution of halfway vectors ... on the disk for
// different values of ω_o; data points ... in red and points from our data-fitting model in blue").
//
// For an outgoing direction ω_o (our j, azimuth 0) the halfway vectors H = ω_i + ω_o lie on the
// unit hemisphere over the disk of radius 1 centred at ω_o's tangential part (models/hvd.h); a
// BRDF is a density p on that disk, ρ (ω_i·N) dω_i = p dA:
//   orthogonal projection (eq. 22–24): h = ω_i,uv + ω_o,uv, dA = (ω_i·N) dω_i, so p(h) = ρ;
//   scaling projection (eq. 15, 19–20): h = (ω_o·N)/(H·N) H, p(h) = ρ (ω_i·N) / (dμ/dω_i) with
//   dμ/dω_i = hvd::scaling_jacobian.
// Any model (measured data included) is drawn by evaluating ρ at the ω_i each disk point maps to
// (hvd::incident_from_orthogonal / hvd::incident_from_scaling). The disks are drawn in one fixed
// (u, v) frame, so, as in Fig. 13, the disk moves with ω_o while the origin (the mirror
// direction's halfway vector) stays put.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/hvd.h"

namespace ganzfeld {

enum class DiskProjection { orthogonal, scaling };

/// The density p of `model` at disk point h for outgoing direction j (see above); 0 off the disk.
double disk_density(const Model& model, DiskProjection projection, const Vec3& j, const hvd::Uv& h) noexcept;

struct DiskOptions {
  std::vector<double> theta_o_deg{0, 15, 30, 45, 60, 75};  ///< Fig. 13's outgoing angles
  int pixels_per_unit = 56;                                ///< of the (u, v) plane
  int samples_per_pixel_axis = 2;                          ///< the density per pixel: the mean of n × n points
  int points = 3000;                                       ///< halfway vectors drawn per disk and model
  std::uint64_t seed = 13;                                 ///< of the draws: the same figure every time
};

/// The figure, as Fig. 13 shows it: halfway vectors drawn from each density as dots, red for the
/// data, blue for the fit; a row per ω_o; columns data, fit and both in the orthogonal projection,
/// then the same in the scaling projection (without a fit, one column per projection). Written
/// atomically as PNG.
void write_disk_figure(const Model& data, const Model* fit, const DiskOptions& options, const std::string& path);

/// How widely the specular part of the density spreads about the origin on the orthogonal disk:
/// sqrt(∫ q |h|² dA / ∫ q dA), q = max(0, p − the density's median over the disk) (the median is
/// the diffuse floor wherever the lobe covers less than half of the disk). The tightening toward
/// grazing that Edwards et al. describe for Fig. 13 shows as a falling spread.
double disk_spread(const Model& model, double theta_o_deg);

}  // namespace ganzfeld
