#include "rasterizer/raster.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace ganzfeld::raster {

namespace {

/// Orthonormal camera frame: right, up, forward (looking along forward).
struct Frame {
  Vec3 right, up, forward;
  double tan_half_fov, aspect;
};

Frame camera_frame(const Camera& camera) {
  Frame f;
  f.forward = glm::normalize(camera.target - camera.eye);
  f.right = glm::normalize(glm::cross(f.forward, camera.up));
  f.up = glm::cross(f.right, f.forward);
  f.tan_half_fov = std::tan(camera.fov_deg * std::numbers::pi / 360.0);
  f.aspect = static_cast<double>(camera.width) / camera.height;
  return f;
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Camera-space clip distance: geometry closer than this to the eye plane is cut away.
constexpr double kNear = 1e-4;
/// Coverage slack in normalized barycentrics, so that a pixel centre exactly on an edge shared by
/// two triangles is never missed by both because of rounding (it may be claimed by both; the
/// strict depth test then keeps the first).
constexpr double kEdgeSlack = 1e-9;

struct ClipVertex {
  Vec3 cam;     ///< camera space (x right, y up, z forward depth)
  Vec3 world;   ///< world position
  Vec3 normal;  ///< world normal (not renormalized)
};

struct ScreenTriangle {
  double sx[3], sy[3];  ///< pixel coordinates (x right, y down), pixel centres at k + 0.5
  double inv_z[3];      ///< 1 / camera depth
  Vec3 world[3], normal[3];
  std::uint32_t mesh;
  int x0, x1, y0, y1;  ///< inclusive pixel bounds, clipped to the image
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, double t) {
  return {a.cam + t * (b.cam - a.cam), a.world + t * (b.world - a.world), a.normal + t * (b.normal - a.normal)};
}

/// Sutherland–Hodgman against z >= kNear: a triangle becomes 0, 1 or 2 triangles (fan).
std::vector<ClipVertex> clip_near(const std::array<ClipVertex, 3>& in) {
  std::vector<ClipVertex> out;
  for (int k = 0; k < 3; ++k) {
    const ClipVertex& a = in[k];
    const ClipVertex& b = in[(k + 1) % 3];
    const bool a_in = a.cam.z >= kNear, b_in = b.cam.z >= kNear;
    if (a_in) out.push_back(a);
    if (a_in != b_in) out.push_back(lerp(a, b, (kNear - a.cam.z) / (b.cam.z - a.cam.z)));
  }
  return out;
}

std::vector<ScreenTriangle> project(const Camera& camera, const Frame& frame, const std::vector<Mesh>& meshes) {
  std::vector<ScreenTriangle> out;
  const double W = camera.width, H = camera.height;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    for (const auto& t : mesh.triangles) {
      std::array<ClipVertex, 3> v;
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = mesh.positions[t[k]];
        const Vec3 d = p - camera.eye;
        v[k] = {{glm::dot(d, frame.right), glm::dot(d, frame.up), glm::dot(d, frame.forward)}, p, mesh.normals[t[k]]};
      }
      const std::vector<ClipVertex> poly = clip_near(v);
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        const ClipVertex* c[3] = {&poly[0], &poly[k], &poly[k + 1]};
        ScreenTriangle s;
        s.mesh = static_cast<std::uint32_t>(m);
        double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
        for (int q = 0; q < 3; ++q) {
          const Vec3& cam = c[q]->cam;
          s.inv_z[q] = 1.0 / cam.z;
          s.sx[q] = (cam.x * s.inv_z[q] / (frame.tan_half_fov * frame.aspect) + 1.0) * 0.5 * W;
          s.sy[q] = (1.0 - cam.y * s.inv_z[q] / frame.tan_half_fov) * 0.5 * H;
          s.world[q] = c[q]->world;
          s.normal[q] = c[q]->normal;
          xmin = std::min(xmin, s.sx[q]);
          xmax = std::max(xmax, s.sx[q]);
          ymin = std::min(ymin, s.sy[q]);
          ymax = std::max(ymax, s.sy[q]);
        }
        // Pixel k covers [k, k+1); its centre k + 0.5 lies in [min, max] iff k in [min-0.5, max-0.5].
        const double bx0 = std::ceil(xmin - 0.5), bx1 = std::floor(xmax - 0.5);
        const double by0 = std::ceil(ymin - 0.5), by1 = std::floor(ymax - 0.5);
        if (!(bx0 <= bx1 && by0 <= by1) || bx1 < 0 || by1 < 0 || bx0 > W - 1 || by0 > H - 1) continue;
        s.x0 = static_cast<int>(std::max(bx0, 0.0));
        s.x1 = static_cast<int>(std::min(bx1, W - 1));
        s.y0 = static_cast<int>(std::max(by0, 0.0));
        s.y1 = static_cast<int>(std::min(by1, H - 1));
        out.push_back(s);
      }
    }
  }
  return out;
}

/// Refines a pixel of a UV sphere to the exact sphere along the pixel ray (raster.h).
void refine_to_sphere(const Sphere& sphere, const Ray& ray, const Frame& frame, const Camera& camera,
                      Fragment& fragment) {
  const Vec3 oc = ray.origin - sphere.center;
  const double b = glm::dot(oc, ray.direction);
  const double c = glm::dot(oc, oc) - sphere.radius * sphere.radius;
  if (c <= 0.0) return;  // eye inside the sphere: keep the mesh's answer
  // The mesh is inscribed in the sphere, so a ray that hits it hits the sphere (disc >= 0 up to
  // rounding, hence the clamp).
  const double t = -b - std::sqrt(std::max(b * b - c, 0.0));
  if (!(t > 0.0)) return;
  fragment.position = ray.origin + t * ray.direction;
  fragment.normal = glm::normalize(fragment.position - sphere.center);
  fragment.depth = glm::dot(fragment.position - camera.eye, frame.forward);
}

}  // namespace

void validate_camera(const Camera& camera) {
  auto bad_side = [](int v) { return v < 1 || v > kMaxImageSide; };
  if (bad_side(camera.width) || bad_side(camera.height))
    throw InputError("image size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                     " is invalid; allowed: width and height in 1.." + std::to_string(kMaxImageSide));
  if (!(camera.fov_deg > 0.0 && camera.fov_deg < 180.0))
    throw InputError("camera fov_deg " + std::to_string(camera.fov_deg) + " is invalid; allowed: (0, 180)");
  if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up))
    throw InputError("camera eye, target and up must be finite");
  const Vec3 forward = camera.target - camera.eye;
  if (!(glm::length(forward) > 0.0)) throw InputError("camera eye and target coincide; they must differ");
  if (!(glm::length(glm::cross(glm::normalize(forward), camera.up)) > 1e-9))
    throw InputError("camera up is parallel to the viewing direction (or zero); it must not be");
}

Ray pixel_ray(const Camera& camera, double x, double y) {
  const Frame f = camera_frame(camera);
  const double u = (2.0 * (x + 0.5) / camera.width - 1.0) * f.tan_half_fov * f.aspect;
  const double v = (1.0 - 2.0 * (y + 0.5) / camera.height) * f.tan_half_fov;
  return {camera.eye, glm::normalize(f.forward + u * f.right + v * f.up)};
}

GBuffer rasterize(const Camera& camera, const std::vector<Mesh>& meshes) {
  validate_camera(camera);
  const Frame frame = camera_frame(camera);
  const std::vector<ScreenTriangle> triangles = project(camera, frame, meshes);

  const int tiles_x = (camera.width + kTileSize - 1) / kTileSize;
  const int tiles_y = (camera.height + kTileSize - 1) / kTileSize;
  // Binning in triangle order, so every tile visits its triangles in the same order each run.
  std::vector<std::vector<std::uint32_t>> bins(static_cast<std::size_t>(tiles_x) * tiles_y);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const ScreenTriangle& s = triangles[t];
    for (int ty = s.y0 / kTileSize; ty <= s.y1 / kTileSize; ++ty)
      for (int tx = s.x0 / kTileSize; tx <= s.x1 / kTileSize; ++tx)
        bins[static_cast<std::size_t>(ty) * tiles_x + tx].push_back(static_cast<std::uint32_t>(t));
  }

  GBuffer gb;
  gb.width = camera.width;
  gb.height = camera.height;
  gb.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height);

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      const int tx = tile % tiles_x, ty = tile / tiles_x;
      const int px0 = tx * kTileSize, py0 = ty * kTileSize;
      const int px1 = std::min(px0 + kTileSize, camera.width), py1 = std::min(py0 + kTileSize, camera.height);
      std::vector<double> zbuf(static_cast<std::size_t>(kTileSize) * kTileSize, INFINITY);
      for (std::uint32_t t : bins[tile]) {
        const ScreenTriangle& s = triangles[t];
        const double area = (s.sx[1] - s.sx[0]) * (s.sy[2] - s.sy[0]) - (s.sx[2] - s.sx[0]) * (s.sy[1] - s.sy[0]);
        if (!(std::abs(area) > 0.0)) continue;  // degenerate on screen
        for (int y = std::max(py0, s.y0); y < std::min(py1, s.y1 + 1); ++y) {
          const double py = y + 0.5;
          for (int x = std::max(px0, s.x0); x < std::min(px1, s.x1 + 1); ++x) {
            const double px = x + 0.5;
            // Normalized screen-space barycentrics from the edge functions.
            double b[3];
            for (int k = 0; k < 3; ++k) {
              const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
              b[k] = ((s.sx[k2] - s.sx[k1]) * (py - s.sy[k1]) - (s.sy[k2] - s.sy[k1]) * (px - s.sx[k1])) / area;
            }
            if (b[0] < -kEdgeSlack || b[1] < -kEdgeSlack || b[2] < -kEdgeSlack) continue;
            // Perspective-correct weights w_k = (b_k / z_k) / Σ b_m / z_m; depth z = 1 / Σ b_m / z_m.
            const double inv_z = b[0] * s.inv_z[0] + b[1] * s.inv_z[1] + b[2] * s.inv_z[2];
            if (!(inv_z > 0.0)) continue;
            const double z = 1.0 / inv_z;
            double& zb = zbuf[static_cast<std::size_t>(y - py0) * kTileSize + (x - px0)];
            if (!(z < zb)) continue;
            zb = z;
            Vec3 position{0, 0, 0}, normal{0, 0, 0};
            for (int k = 0; k < 3; ++k) {
              const double w = b[k] * s.inv_z[k] * z;
              position += w * s.world[k];
              normal += w * s.normal[k];
            }
            Fragment& f = gb.pixels[static_cast<std::size_t>(y) * camera.width + x];
            f.mesh = s.mesh;
            f.position = position;
            const double len = glm::length(normal);
            f.normal = len > 0.0 ? normal / len : Vec3{0, 0, 1};
            f.depth = z;
          }
        }
      }
      // View direction and exact spheres, once per covered pixel.
      for (int y = py0; y < py1; ++y)
        for (int x = px0; x < px1; ++x) {
          Fragment& f = gb.pixels[static_cast<std::size_t>(y) * camera.width + x];
          if (f.mesh == Fragment::kNone) continue;
          const Ray ray = pixel_ray(camera, x, y);
          if (meshes[f.mesh].exact_sphere) refine_to_sphere(*meshes[f.mesh].exact_sphere, ray, frame, camera, f);
          f.view = -ray.direction;
        }
    }
  });
  return gb;
}

}  // namespace ganzfeld::raster
