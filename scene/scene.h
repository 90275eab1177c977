// The scene file (examples/default.json) as plain data. The planner beside it (scene/plan.h) decides
// from it which tables exist (lights × lobes); rasterizer/, export/ and cli/ read the same structures.
// Directions are in world space; a light's direction/pole points *towards* the source.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "models/spec.h"

namespace ganzfeld {

using Rgb = std::array<double, 3>;

struct Camera {
  int width = 512, height = 512;
  Vec3 eye{0, 0, 6}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 25.0;  ///< vertical field of view
  Rgb background{0, 0, 0};
};

/// One lobe of a material: its weight (normalized over the material), model and colour
/// (K&P conclusions: body colour for diffuse/backscatter, source colour for specular/asperity).
struct MaterialLobe {
  double weight = 1.0;
  std::string spec;  ///< canonical spec of a single (non-mixture) model
  ModelPtr model;
  Rgb color{1, 1, 1};
};

struct Material {
  std::string name;
  std::vector<MaterialLobe> lobes;
};

/// How an object orients anisotropic lobes (their local +x axis, models/model.h): the tangent
/// follows the circles of latitude about `axis` (axis x n: "brushed" around the axis) or its
/// meridians (the axis' part across n: brushed towards the axis' poles), as Walker's Fig. 30
/// shows them. Default: latitude about +y (world up). Isotropic lobes ignore it.
struct TangentRule {
  Vec3 axis{0, 1, 0};
  bool latitude = true;
};

/// The unit tangent of `rule` at unit normal n. Where n lies along the axis (|rule's tangent|^2
/// <= 1e-12 |axis|^2: the poles) the world axis farthest from n instead: +x, or +y when
/// |n.x| >= 0.9. models/glsl.cpp's gz_brush_tangent is the same rule in GLSL.
Vec3 brush_tangent(const Vec3& n, const TangentRule& rule);

struct SceneObject {
  enum class Shape { sphere, mesh } shape = Shape::sphere;
  Vec3 center{0, 0, 0};
  double radius = 1.0;
  std::string mesh_path;     ///< resolved relative to the scene file's directory
  std::size_t material = 0;  ///< index into Scene::materials
  TangentRule tangent;       ///< "tangent": {"axis": [x, y, z], "along": "latitude" | "longitude"}
};

struct Light {
  enum class Type { collimated, hemispherical, ganzfeld } type = Type::collimated;
  Vec3 direction{0, 0, 1};  ///< collimated: towards the source; hemispherical: the sky's pole
  Rgb intensity{1, 1, 1};   ///< collimated: normal irradiance H0; otherwise radiance N
};

/// A light of grey intensity (irradiance H0 or radiance N) from/with `direction`.
inline Light grey_light(Light::Type type, const Vec3& direction, double intensity) {
  return {type, direction, {intensity, intensity, intensity}};
}

struct Scene {
  Camera camera;
  std::vector<Material> materials;
  std::vector<SceneObject> objects;
  std::vector<Light> lights;
};

/// Parses and validates a scene file; throws InputError with a one-line message naming the bad
/// key or value and what is allowed (implemented in scene/scene.cpp).
Scene load_scene(const std::string& path);

/// The same for the scene file's text: `path` names it in messages and is where relative mesh
/// paths are resolved from (the fuzzer and tests parse scenes from memory).
Scene load_scene_text(const std::string& text, const std::string& path);

}  // namespace ganzfeld
