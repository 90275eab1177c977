// Radiance per pixel: K&P's three canonical light fields, summed over lights and lobes
// ("Material Properties and Extended Sources for Surface Rendering", section "Extended sources"):
//   collimated beam     N = H0 (i·n) f(i, j)        0 when i·n <= 0 (body shadow) or j·n <= 0
//   hemispherical sky   N = N_i g(i, j, n)          i = the sky's pole, i·n in [-1, 1]
//   Ganzfeld            N = N_i h(j, n)
// Everything is evaluated in the LOCAL frame of the pixel's normal (n = +z) and the object's
// tangent (+x: the scene file's tangent rule, scene/scene.h brush_tangent): anisotropic lobes are
// oriented by it; the isotropic laws only see i·n, j·n and the relative azimuth of the tangential
// parts of i and j, which any frame preserves.
// A pixel's j·n can be slightly negative only through interpolated mesh normals at a silhouette;
// for the sky and the Ganzfeld j is then clamped to the horizon (the limit of the visible side).
//
// A model's mirror delta (Model::mirror_reflectance: he-torrance's coherent specular term), which
// f and its laws exclude, is added exactly: rho(j·n) under a Ganzfeld, and under a sky when the
// mirror direction of j lies in it; nothing under a collimated beam (it lights one direction).
// f is always the model's own closed form. g and h come from a LawSource, one per lobe:
//   tables  — tables::sample on baked tables (fast; error = table error + interpolation error)
//   direct  — integrate/laws.h cubature per pixel (slow; the reference, to a tolerance)
//   lambert — the closed forms g = (1 + i·n)/2, h = 1 (exact)
// A picture prepares each material once (MaterialShader): the tables of lobes that share a lookup
// are summed, so a pixel makes one lookup per light and law, as a shader would with one texture.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "integrate/laws.h"
#include "rasterizer/image.h"
#include "rasterizer/raster.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/sample.h"
#include "tables/table.h"

namespace ganzfeld::raster {

/// The laws of one lobe beyond f, in the local frame (n = +z, unit i and j, j·n >= 0).
class LawSource {
 public:
  virtual ~LawSource() = default;
  virtual bool has(Law law) const = 0;
  /// Law of vignetting for the sky pole i (i·n in [-1, 1]).
  virtual double g(const Vec3& i, const Vec3& j) const = 0;
  /// Law of darkening.
  virtual double h(const Vec3& j) const = 0;
  /// The table law g or h is looked up in, if it is (table_laws); nullptr otherwise.
  virtual const tables::Table* table(Law) const { return nullptr; }
};
using LawSourcePtr = std::shared_ptr<const LawSource>;

/// g = (1 + i·n)/2, h = 1 (K&P, white Lambertian surface).
LawSourcePtr lambert_laws();
/// Tables of one lobe (either may be null when the scene does not need that law).
LawSourcePtr table_laws(std::shared_ptr<const tables::Table> g, std::shared_ptr<const tables::Table> h);
/// Cubature per call at absolute tolerance `tolerance` (integrate/laws.h).
LawSourcePtr direct_laws(ModelPtr model, double tolerance);

/// True for the Lambert model, whose g and h have the exact closed forms above.
bool is_lambert(const Model& model);

struct ShadingLobe {
  double weight = 1.0;
  Rgb color{1, 1, 1};
  ModelPtr model;
  LawSourcePtr laws;
};
using ShadingMaterial = std::vector<ShadingLobe>;

/// A right-handed orthonormal frame (t, b, n); local(v) = (v·t, v·b, v·n).
struct TangentFrame {
  Vec3 t, b, n;
  /// Any frame for unit n (Duff et al. 2017, "Building an orthonormal basis, revisited").
  explicit TangentFrame(const Vec3& n);
  /// t = the part of `tangent` across unit n, normalized (tangent not along n); b = n x t.
  TangentFrame(const Vec3& n, const Vec3& tangent);
  Vec3 local(const Vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
};

/// A material prepared for shading under a set of lights, once per picture: the lights' unit
/// directions, each lobe's weight x colour x light, and the tables of the lobes that share a
/// lookup (tables::same_lookup) summed entry by entry into one colour table per light and law, so
/// that a pixel looks each law up once per light however many lobes the material has (the laws are
/// linear in f: a lookup's blend of the summed entries is the sum of the lobes' lookups, up to
/// rounding). Lobes without tables (closed forms, cubature) are evaluated one by one, and so is the
/// mirror delta of a lobe with tables (Model::mirror_reflectance), which its tables leave out.
class MaterialShader {
 public:
  MaterialShader(const ShadingMaterial& material, const std::vector<Light>& lights);
  /// Radiance towards j (unit, world) of a surface with unit world normal n and tangent t (any
  /// vector not along n; anisotropic lobes are oriented by its part across n).
  Rgb radiance(const Vec3& n, const Vec3& j, const Vec3& t) const;

  /// Lobes whose law (g or h) is looked up in a table, and the lookups a pixel makes per light.
  struct SummedTable {
    tables::Lookup lookup;                       ///< the lookup's axes (one of the summed tables), prepared once
    std::vector<std::array<double, 3>> entries;  ///< Σ weight x colour x light intensity x value
  };
  struct LobeTerm {
    const ShadingLobe* lobe = nullptr;
    Rgb scale{};  ///< weight x colour x light intensity
  };
  struct PreparedLight {
    Light::Type type = Light::Type::collimated;
    Vec3 direction{0, 0, 1};      ///< unit, world
    std::vector<LobeTerm> lobes;  ///< collimated: every lobe; sky, Ganzfeld: lobes without a table
    std::vector<SummedTable> tables;
    std::vector<LobeTerm> mirrors;  ///< sky, Ganzfeld: lobes in `tables` with a mirror delta, added apart
  };
  const std::vector<PreparedLight>& lights() const { return lights_; }

 private:
  std::vector<PreparedLight> lights_;
};

/// Radiance towards j (unit, world) of a surface with unit world normal n and tangent t
/// (MaterialShader(material, lights).radiance(n, j, t); a picture prepares its materials once).
Rgb shade(const ShadingMaterial& material, const std::vector<Light>& lights, const Vec3& n, const Vec3& j,
          const Vec3& t);

/// Everything the rasterizer needs to make a picture.
struct RenderScene {
  Camera camera;
  std::vector<Mesh> meshes;
  std::vector<std::size_t> mesh_material;  ///< per mesh: index into materials
  std::vector<TangentRule> mesh_tangent;   ///< per mesh: its object's tangent rule (empty: the default)
  std::vector<ShadingMaterial> materials;
  std::vector<Light> lights;
};

/// Throws std::logic_error when a lobe lacks a law the lights need (a programming error: the
/// caller builds the sources from the scene's lights).
void check_laws_available(const RenderScene& scene);

/// Shades a G-buffer (rows in parallel; deterministic). Background pixels get the camera's colour.
Image shade_image(const RenderScene& scene, const GBuffer& gbuffer);

/// rasterize + shade_image.
Image render(const RenderScene& scene);

/// Meshes and per-mesh materials of a scene's objects: spheres become uv_sphere(center, radius,
/// kSphereSegments), mesh objects are loaded with load_obj.
inline constexpr int kSphereSegments = 128;
void add_scene_geometry(const Scene& scene, RenderScene& out);

/// The shading materials of a plan (scene/plan.h): closed forms, the plan's tables, or cubature
/// per pixel at `direct_tolerance` for laws the plan marks direct.
std::vector<ShadingMaterial> shading_materials(const scene::ShadingPlan& plan, double direct_tolerance);

/// What render() needs for `scene` shaded as `plan` says: camera, lights, geometry, materials.
RenderScene render_scene(const Scene& scene, const scene::ShadingPlan& plan, double direct_tolerance);

}  // namespace ganzfeld::raster
