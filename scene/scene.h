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

struct SceneObject {
  enum class Shape { sphere, mesh } shape = Shape::sphere;
  Vec3 center{0, 0, 0};
  double radius = 1.0;
  std::string mesh_path;  ///< resolved relative to the scene file's directory
  std::size_t material = 0;  ///< index into Scene::materials
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
