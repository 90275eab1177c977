// The data a fit compares a model with: pairs of directions (i, j), the data's BRDF there and the
// solid-angle measure dω_i dω_o each pair stands for.
//
// Where the samples come from:
//  - a MERL file (merl:file=…): its own nodes, every node of the (θ_h, θ_d, φ_d) grid or every
//    s-th along each axis (`SampleOptions::grid` must divide 90 × 90 × 180), valid nodes only, the
//    stored value itself (no interpolation);
//  - a tabulated file (tabulated:file=…): its own (θ_i, θ_r, φ) nodes;
//  - any other model (an analytic spec, a mixture): the nodes of a MERL-like grid of `grid`
//    counts — θ_h = (k/n_h)² π/2, θ_d = k/n_d · π/2, φ_d = k/n_p · π (models/measured.h) — where
//    the model is evaluated; at 90 × 90 × 180 they are exactly the nodes of a file written by
//    `ganzfeld export-brdf`.
// Both measured formats are isotropic, so a node's value holds for the pair rotated about n by
// any φ_h: sample s is rotated by φ_h = 2π frac(s/golden ratio), so that an anisotropic model
// fitted to the data sees every azimuth (for isotropic models the rotation changes nothing).
//
// The measure of a node is that of its cell: dω_i dω_o = 4 cos θ_d dω_h dω_d (Rusinkiewicz's
// change of variables: dω_o = 4 (ω_i·ω_h) dω_h at fixed ω_i, and ω_d is ω_i rotated), integrated
// exactly over the cell between the midpoints to the neighbouring nodes: (cos a − cos b) along θ_h,
// 2 (sin² b − sin² a) along θ_d, the cell's length along φ_d (and 2π along φ_h; × 2 for the half
// of φ_d, or of the relative azimuth φ, that the formats fold away). Tabulated nodes: (cos a −
// cos b) along θ_i and θ_r, the length along φ. Over every valid pair the measures sum to (2π)².
// Pairs with θ_i or θ_o beyond `max_theta_deg` are left out: Ngan, Durand & Matusik (2005, §3.1)
// drop them as unreliable measurements near grazing.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld::fit {

struct SampleOptions {
  /// Nodes along θ_h, θ_d, φ_d (MERL files: counts dividing 90, 90, 180).
  std::array<int, 3> grid{90, 30, 30};
  double max_theta_deg = 80.0;  ///< pairs with θ_i or θ_o beyond are left out
};

/// The samples, as arrays (f_batch takes whole arrays).
struct FitData {
  std::vector<Vec3> i, j;
  std::vector<double> value;   ///< the data's f in 1/sr
  std::vector<double> weight;  ///< the solid-angle measure dω_i dω_o of the sample's cell
  std::string source;          ///< how they were taken, for reports: "own nodes of the MERL file, ..."
  std::size_t size() const { return value.size(); }
};

/// Parses "AxBxC" (each >= 2, <= 1000) for --grid; throws InputError naming the flag.
std::array<int, 3> parse_grid(const std::string& text);

/// The samples of `data` (see above). Throws InputError for a MERL file whose grid does not divide
/// its nodes, or when no sample is left (all beyond max_theta_deg or invalid).
FitData sample_data(const Model& data, const SampleOptions& options);

}  // namespace ganzfeld::fit
