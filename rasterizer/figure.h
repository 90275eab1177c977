// The Koenderink–Pont 2×2 panel of one material ("Material Properties and Extended Sources for
// Surface Rendering", figures 1–5):
//   top left     the scattering indicatrix: the surface r(j) j with r(j) = f(i, j) / max_j f(i, j)
//                for i at 45° (the red rod), over the surface's plane (grey disc)
//   top right    a sphere in a collimated beam 45° from the viewing direction, from the upper right
//   bottom left  a sphere under a uniform hemispherical sky, pole up
//   bottom right a sphere in a Ganzfeld (the background is the Ganzfeld's own radiance, so a
//                white Lambertian sphere is invisible)
// The laws g and h come from small tables baked on the fly (Lambert lobes: closed forms).
// Exposure: every field has radiance kFieldRadiance (collimated: H0 = pi kFieldRadiance, so a
// white Lambertian surface facing the beam has that radiance too).
#pragma once

#include <string>
#include <vector>

#include "rasterizer/image.h"
#include "scene/plan.h"

namespace ganzfeld::raster {

inline constexpr double kFieldRadiance = 0.8;
/// Linear grey behind the indicatrix, the collimated and the sky sphere.
inline constexpr double kFigureBackground = 0.1;

struct FigureOptions {
  int size = 256;  ///< pixels per quadrant side
  /// The small tables of g and h each non-Lambert lobe needs (scene/plan.h); anisotropic lobes
  /// are computed by cubature per pixel at the same tolerance.
  scene::TableOptions tables{{24, 24, 12}, {64}, 1e-6};
  scene::TableStore store;  ///< in memory by default; a cache directory with `figure --cache`
};

/// One 2×2 panel, (2 size + gap) pixels square. Throws InputError for a bad spec or size.
Image koenderink_pont_panel(const std::string& spec, const FigureOptions& options);

/// Panels side by side (left to right), separated by a gap.
Image side_by_side(const std::vector<Image>& panels);

/// Separator between quadrants and panels, pixels.
int figure_gap(int size);

}  // namespace ganzfeld::raster
