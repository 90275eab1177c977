// What the service computes for the viewer where the page cannot (docs/serve.md, "The viewer"):
//   GET /api/fgrid?model=SPEC&theta=DEG&phi=DEG&res=N[&adjoint=1]
//       f(i, j) with i at (theta, phi) (degrees, the local frame: n = +z, the tangent +x) and j at
//       the centres of a res x 2 res grid over the hemisphere, theta_j = (a + 1/2)/res 90°, phi_j =
//       (b + 1/2)/(2 res) 360°, rows theta_j; with adjoint=1, f(k, j) with j fixed at (theta, phi)
//       and k over the grid (the lobe over incident directions). For models without a GLSL f.
//   GET /api/sphere?model=SPEC&law=f|g|h[&dir=X,Y,Z]&size=N[&along=latitude|longitude][&tol=T]
//       the K&P figure's sphere (rasterizer/figure.h: a unit sphere seen from (0, 0, 6), 25° field
//       of view) as `ganzfeld render` draws it (the same code: rasterizer/shading.h), lit by one
//       light of unit intensity: law f a collimated beam from dir ((i.n) f per pixel), g a sky with
//       pole dir, h a Ganzfeld; g and h by cubature per pixel to tol (the laws of anisotropic models,
//       which have no tables). The tangent follows the latitude (default) or the meridians about the
//       view's up axis +y (scene/scene.h, TangentRule). Per pixel, top row first: the value and a
//       mask (1 on the sphere, 0.5 where j.n < 0.05 near the silhouette, 0 behind it), as the
//       viewer's test mode writes its own spheres.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "integrate/laws.h"
#include "scene/scene.h"
#include "serve/data.h"
#include "serve/request.h"

namespace ganzfeld::serve {

struct FGridQuery {
  ModelPtr model;
  Vec3 fixed{0, 0, 1};
  int res = 32;
  bool adjoint = false;
};
FGridQuery parse_fgrid(const Query& query, const DataFiles& data);
/// {"model", "res", "fixed", "adjoint", "values": [res x 2 res]}.
nlohmann::ordered_json fgrid_json(const FGridQuery& q, const DataFiles& data);

/// Largest sphere side: f is cheap; g and h cost a cubature per pixel.
inline constexpr int kMaxSphereSide = 256;
inline constexpr int kMaxCubatureSphereSide = 96;

struct SphereQuery {
  ModelPtr model;
  Law law = Law::f;
  Vec3 light{0, 0, 1};
  int size = 64;
  TangentRule tangent;
  double tolerance = 1e-5;
  std::string key;  ///< one computation per key (serve/bakery.h)
};
SphereQuery parse_sphere(const Query& query, const DataFiles& data);
/// {"model", "law", "width", "height", "value": [...], "mask": [...]}.
nlohmann::ordered_json sphere_json(const SphereQuery& q, const DataFiles& data);

}  // namespace ganzfeld::serve
