#include "rasterizer/figure.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "models/spec.h"
#include "rasterizer/shading.h"
#include "util/error.h"

namespace ganzfeld::raster {

namespace {

constexpr double kPi = std::numbers::pi;
/// Angle of incidence of the indicatrix, from the normal (K&P draw i at 45°).
constexpr double kIndicatrixTheta = kPi / 4;
constexpr int kIndicatrixThetaSteps = 64, kIndicatrixPhiSteps = 128;

/// Local frame of the indicatrix (n = +z) to world (y up, the camera looks along -z):
/// (x, y, z) -> (x, z, -y), a rotation.
Vec3 to_world(const Vec3& v) { return {v.x, v.z, -v.y}; }

Camera sphere_camera(int size, const Rgb& background) {
  Camera c;
  c.width = c.height = size;
  c.eye = {0, 0, 6};
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fov_deg = 25;
  c.background = background;
  return c;
}

ShadingMaterial lambert_material(const Rgb& color) {
  ShadingLobe lobe;
  lobe.color = color;
  lobe.model = parse_model("lambert");
  lobe.laws = lambert_laws();
  return {lobe};
}

/// The lobe surface r(j) j over the hemisphere, r = f(i, j) / max f.
Mesh indicatrix_mesh(const Model& model, const Vec3& i) {
  const int nt = kIndicatrixThetaSteps, np = kIndicatrixPhiSteps;
  std::vector<Vec3> directions;
  std::vector<double> f;
  for (int a = 0; a <= nt; ++a)
    for (int b = 0; b < np; ++b) {
      const Vec3 j = direction(0.5 * kPi * a / nt, 2 * kPi * b / np);
      directions.push_back(j);
      f.push_back(model.f(i, j));
    }
  const double f_max = *std::max_element(f.begin(), f.end());
  Mesh mesh;
  for (std::size_t k = 0; k < directions.size(); ++k)
    mesh.positions.push_back(to_world((f_max > 0 ? f[k] / f_max : 0.0) * directions[k]));
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b) {
      const auto v = [&](int aa, int bb) { return static_cast<std::uint32_t>(aa * np + (bb % np)); };
      mesh.triangles.push_back({v(a, b), v(a + 1, b), v(a + 1, b + 1)});
      mesh.triangles.push_back({v(a, b), v(a + 1, b + 1), v(a, b + 1)});
    }
  compute_normals(mesh);
  // The surface is star-shaped about the origin, so its outward normal has a positive radial
  // component: orient every normal that way whatever the triangles' winding.
  for (std::size_t k = 0; k < mesh.normals.size(); ++k)
    if (glm::dot(mesh.normals[k], to_world(directions[k])) < 0) mesh.normals[k] = -mesh.normals[k];
  return mesh;
}

/// A rod from a to b (open cylinder), radial normals.
Mesh rod(const Vec3& a, const Vec3& b, double radius, int segments) {
  const Vec3 axis = glm::normalize(b - a);
  const Vec3 helper = std::abs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  const Vec3 u = glm::normalize(glm::cross(axis, helper)), v = glm::cross(axis, u);
  Mesh mesh;
  for (int s = 0; s < segments; ++s) {
    const double phi = 2 * kPi * s / segments;
    const Vec3 n = std::cos(phi) * u + std::sin(phi) * v;
    for (const Vec3& end : {a, b}) {
      mesh.positions.push_back(end + radius * n);
      mesh.normals.push_back(n);
    }
  }
  for (int s = 0; s < segments; ++s) {
    const auto k0 = static_cast<std::uint32_t>(2 * s), k1 = static_cast<std::uint32_t>(2 * ((s + 1) % segments));
    mesh.triangles.push_back({k0, k1, k0 + 1});
    mesh.triangles.push_back({k1, k1 + 1, k0 + 1});
  }
  return mesh;
}

/// A flat disc of normal +y at height y.
Mesh disc(double radius, double y, int segments) {
  Mesh mesh;
  mesh.positions.push_back({0, y, 0});
  mesh.normals.push_back({0, 1, 0});
  for (int s = 0; s < segments; ++s) {
    const double phi = 2 * kPi * s / segments;
    mesh.positions.push_back({radius * std::cos(phi), y, radius * std::sin(phi)});
    mesh.normals.push_back({0, 1, 0});
  }
  for (int s = 0; s < segments; ++s)
    mesh.triangles.push_back(
        {0, static_cast<std::uint32_t>(1 + s), static_cast<std::uint32_t>(1 + (s + 1) % segments)});
  return mesh;
}

Image indicatrix_quadrant(const Model& model, int size) {
  const Vec3 i = direction(kIndicatrixTheta, kPi);  // from the left, so a specular lobe points right
  RenderScene scene;
  scene.camera = sphere_camera(size, {kFigureBackground, kFigureBackground, kFigureBackground});
  scene.camera.eye = {0, 1.7, 4.6};
  scene.camera.target = {0, 0.35, 0};
  scene.camera.fov_deg = 36;
  scene.meshes = {indicatrix_mesh(model, i), rod({0, 0, 0}, to_world(1.45 * i), 0.018, 16), disc(1.2, -0.002, 96)};
  scene.materials = {lambert_material({0.9, 0.9, 0.9}), lambert_material({0.9, 0.15, 0.1}),
                     lambert_material({0.35, 0.35, 0.4})};
  scene.mesh_material = {0, 1, 2};
  // A key light from the viewer's upper left and a soft fill, so the surface reads in 3-D.
  scene.lights = {grey_light(Light::Type::collimated, {-0.4, 0.8, 0.5}, 0.75 * kPi),
                  grey_light(Light::Type::ganzfeld, {0, 1, 0}, 0.2)};
  return render(scene);
}

/// Sphere quadrants need g (sky) and h (Ganzfeld) of every lobe, planned as a scene's are.
ShadingMaterial figure_material(const std::string& spec, const FigureOptions& options) {
  const std::vector<Light> fields{grey_light(Light::Type::hemispherical, {0, 1, 0}, 1.0),
                                  grey_light(Light::Type::ganzfeld, {0, 1, 0}, 1.0)};
  const scene::ShadingPlan plan = scene::plan_material(scene::material_of(spec), fields, options.tables, options.store);
  return shading_materials(plan, options.tables.tolerance).front();
}

Image sphere_quadrant(const ShadingMaterial& material, const Light& light, int size, double background) {
  RenderScene scene;
  scene.camera = sphere_camera(size, {background, background, background});
  scene.meshes = {uv_sphere({0, 0, 0}, 1.0, kSphereSegments)};
  scene.materials = {material};
  scene.mesh_material = {0};
  scene.lights = {light};
  return render(scene);
}

}  // namespace

int figure_gap(int size) { return std::max(2, size / 64); }

Image koenderink_pont_panel(const std::string& spec, const FigureOptions& options) {
  if (options.size < 16 || options.size > 4096)
    throw InputError("figure size " + std::to_string(options.size) +
                     " is invalid; allowed: 16..4096 pixels per quadrant");
  const ModelPtr model = parse_model(spec);
  const ShadingMaterial material = figure_material(spec, options);
  const int s = options.size, gap = figure_gap(s);
  // Collimated beam 45° from the viewing direction (+z), from the upper right.
  const Vec3 beam = std::cos(kPi / 4) * Vec3{0, 0, 1} + std::sin(kPi / 4) * glm::normalize(Vec3{1, 1, 0});
  Image panel(2 * s + gap, 2 * s + gap, {1, 1, 1});
  blit(indicatrix_quadrant(*model, s), panel, 0, 0);
  blit(sphere_quadrant(material, grey_light(Light::Type::collimated, beam, kPi * kFieldRadiance), s, kFigureBackground),
       panel, s + gap, 0);
  blit(sphere_quadrant(material, grey_light(Light::Type::hemispherical, {0, 1, 0}, kFieldRadiance), s,
                       kFigureBackground),
       panel, 0, s + gap);
  blit(sphere_quadrant(material, grey_light(Light::Type::ganzfeld, {0, 1, 0}, kFieldRadiance), s, kFieldRadiance),
       panel, s + gap, s + gap);
  return panel;
}

Image side_by_side(const std::vector<Image>& panels) {
  if (panels.empty()) throw InputError("no panels to put side by side");
  const int gap = figure_gap(panels.front().height / 2);
  int width = -gap, height = 0;
  for (const Image& p : panels) {
    width += p.width + gap;
    height = std::max(height, p.height);
  }
  Image out(width, height, {1, 1, 1});
  int x = 0;
  for (const Image& p : panels) {
    blit(p, out, x, 0);
    x += p.width + gap;
  }
  return out;
}

}  // namespace ganzfeld::raster
