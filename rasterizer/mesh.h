// Triangle meshes with per-vertex normals: the only geometry the rasterizer draws.
// A UV sphere remembers the sphere it approximates so the rasterizer can refine each pixel to
// the exact surface (raster.h): the laws are then shaded with the true normal, not a facet's.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "models/model.h"

namespace ganzfeld::raster {

struct Sphere {
  Vec3 center{0, 0, 0};
  double radius = 1.0;
};

struct Mesh {
  std::vector<Vec3> positions;                          ///< world space
  std::vector<Vec3> normals;                            ///< unit, one per position
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside
  std::optional<Sphere> exact_sphere;                   ///< set by uv_sphere
};

/// A UV sphere: `segments` slices in longitude (>= 3) and segments/2 (>= 2) stacks in latitude,
/// normals (p - center)/radius. Every vertex lies on the sphere, so the mesh is inscribed in it.
/// Throws InputError for radius <= 0 or segments outside [3, 4096].
Mesh uv_sphere(const Vec3& center, double radius, int segments);

/// Wavefront OBJ: `v`, `vn`, `f` with v, v/vt, v//vn and v/vt/vn corners (negative = relative
/// indices), polygons fan-triangulated; other statements are ignored. When any face lacks
/// normals, all normals are computed as area-weighted averages of the face normals around each
/// position. Throws InputError naming the file (and line) for a missing file, a malformed
/// statement or an index out of range.
Mesh load_obj(const std::string& path);

/// Area-weighted vertex normals from the triangles (positions without a face get +z).
void compute_normals(Mesh& mesh);

}  // namespace ganzfeld::raster
