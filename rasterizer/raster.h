// Perspective camera, z-buffer rasterization and the per-pixel geometry the laws need.
//
// For each pixel centre the rasterizer finds the nearest triangle (z-buffer, near-plane clipped),
// and interpolates world position and normal perspective-correctly: screen-space barycentrics b_k
// are divided by the vertices' camera depths z_k and renormalized, w_k = (b_k/z_k) / Σ (b_m/z_m),
// which is exact for points of the planar triangle. Meshes made by uv_sphere are then refined to
// the exact sphere: the pixel ray is intersected with it and n = (p - c)/r.
// The image is cut into tiles rendered in parallel with oneTBB; a pixel belongs to one tile and
// a tile visits its triangles in a fixed order with a strict depth test, so the output does not
// depend on the number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "rasterizer/mesh.h"
#include "scene/scene.h"

namespace ganzfeld::raster {

/// Largest accepted image side, pixels.
inline constexpr int kMaxImageSide = 16384;

/// Throws InputError unless 1 <= width, height <= kMaxImageSide, the field of view is in
/// (0, 180) degrees and eye, target, up span a frame.
void validate_camera(const Camera& camera);

/// World-space ray through the centre of pixel (x, y); y = 0 is the top row.
struct Ray {
  Vec3 origin, direction;  ///< direction is unit
};
Ray pixel_ray(const Camera& camera, double x, double y);

/// What one pixel sees.
struct Fragment {
  static constexpr std::uint32_t kNone = UINT32_MAX;
  std::uint32_t mesh = kNone;  ///< index of the visible mesh, kNone for background
  Vec3 position{0, 0, 0};      ///< world space
  Vec3 normal{0, 0, 1};        ///< unit, world space
  Vec3 view{0, 0, 1};          ///< j: unit, from the surface towards the eye
  double depth = 0.0;          ///< distance along the camera axis
};

struct GBuffer {
  int width = 0, height = 0;
  std::vector<Fragment> pixels;  ///< row-major, top row first
  const Fragment& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Tile side in pixels.
inline constexpr int kTileSize = 32;

/// Rasterizes the meshes (in order: index = Fragment::mesh) as seen by the camera.
GBuffer rasterize(const Camera& camera, const std::vector<Mesh>& meshes);

}  // namespace ganzfeld::raster
