#include "rasterizer/shading.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "models/kp_lobes.h"
#include "tables/sample.h"

namespace ganzfeld::raster {

namespace {

class LambertLaws final : public LawSource {
 public:
  bool has(Law) const override { return true; }
  double g(const Vec3& i, const Vec3&) const override { return lambert::g(i.z); }
  double h(const Vec3&) const override { return 1.0; }
};

class TableLaws final : public LawSource {
 public:
  TableLaws(std::shared_ptr<const tables::Table> g, std::shared_ptr<const tables::Table> h)
      : g_(std::move(g)), h_(std::move(h)) {}
  bool has(Law law) const override { return (law == Law::g && g_) || (law == Law::h && h_); }
  double g(const Vec3& i, const Vec3& j) const override {
    const auto x = tables::coordinates(Law::g, i, j);
    return tables::sample(*g_, std::span<const double>(x)).value;
  }
  double h(const Vec3& j) const override {
    const double x[1] = {std::clamp(j.z, 0.0, 1.0)};
    return tables::sample(*h_, std::span<const double>(x)).value;
  }
  const tables::Table* table(Law law) const override {
    return law == Law::g ? g_.get() : law == Law::h ? h_.get() : nullptr;
  }

 private:
  std::shared_ptr<const tables::Table> g_, h_;
};

class DirectLaws final : public LawSource {
 public:
  DirectLaws(ModelPtr model, double tolerance) : model_(std::move(model)) { options_.abs_tol = tolerance; }
  bool has(Law law) const override { return law == Law::g || law == Law::h; }
  double g(const Vec3& i, const Vec3& j) const override { return vignetting(*model_, i, j, options_).value; }
  double h(const Vec3& j) const override { return darkening(*model_, j, options_).value; }

 private:
  ModelPtr model_;
  CubatureOptions options_;
};

/// j clamped to the horizon (j·n >= 0) for the laws of extended sources (shading.h).
Vec3 clamp_to_horizon(Vec3 j) {
  if (j.z >= 0.0) return j;
  const double r = std::hypot(j.x, j.y);
  return r > 0.0 ? Vec3{j.x / r, j.y / r, 0.0} : Vec3{1.0, 0.0, 0.0};
}

/// The radiance a model's mirror delta (Model::mirror_reflectance) adds towards j under a unit
/// extended source: rho(j·n) when the mirror direction of j sees the source (always in a
/// Ganzfeld; in a sky with pole i when mirror(j)·i > 0), else 0. Under a collimated beam the
/// delta lights a single direction, a point of no area on a sphere: nothing to add.
double mirror_term(const Model& model, const Vec3& j, const Vec3* sky_pole) {
  if (sky_pole && !(glm::dot(mirror(j), *sky_pole) > 0.0)) return 0.0;
  return model.mirror_reflectance(j.z);
}

}  // namespace

LawSourcePtr lambert_laws() { return std::make_shared<LambertLaws>(); }
LawSourcePtr table_laws(std::shared_ptr<const tables::Table> g, std::shared_ptr<const tables::Table> h) {
  return std::make_shared<TableLaws>(std::move(g), std::move(h));
}
LawSourcePtr direct_laws(ModelPtr model, double tolerance) {
  return std::make_shared<DirectLaws>(std::move(model), tolerance);
}

bool is_lambert(const Model& model) { return dynamic_cast<const Lambert*>(&model) != nullptr; }

TangentFrame::TangentFrame(const Vec3& normal) : n(normal) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b_ = n.x * n.y * a;
  t = {1.0 + sign * n.x * n.x * a, sign * b_, -sign * n.x};
  b = {b_, sign + n.y * n.y * a, -n.y};
}

TangentFrame::TangentFrame(const Vec3& normal, const Vec3& tangent)
    : t(glm::normalize(tangent - glm::dot(tangent, normal) * normal)), b(glm::cross(normal, t)), n(normal) {}

MaterialShader::MaterialShader(const ShadingMaterial& material, const std::vector<Light>& lights) {
  for (const Light& light : lights) {
    PreparedLight prepared{light.type, glm::normalize(light.direction), {}, {}, {}};
    const Law law = light.type == Light::Type::hemispherical ? Law::g : Law::h;
    for (const ShadingLobe& lobe : material) {
      LobeTerm term{&lobe, {}};
      for (int c = 0; c < 3; ++c) term.scale[c] = lobe.weight * lobe.color[c] * light.intensity[c];
      const tables::Table* table =
          light.type == Light::Type::collimated || !lobe.laws ? nullptr : lobe.laws->table(law);
      if (table == nullptr) {
        prepared.lobes.push_back(term);
        continue;
      }
      if (has_mirror_delta(*lobe.model)) prepared.mirrors.push_back(term);  // no table holds the delta
      auto shared = std::find_if(prepared.tables.begin(), prepared.tables.end(),
                                 [&](const SummedTable& t) { return tables::same_lookup(t.lookup.table(), *table); });
      if (shared == prepared.tables.end()) {
        prepared.tables.push_back(
            {tables::Lookup(*table), std::vector<std::array<double, 3>>(table->value.size(), {0.0, 0.0, 0.0})});
        shared = prepared.tables.end() - 1;
      }
      for (std::size_t m = 0; m < table->value.size(); ++m)
        for (int c = 0; c < 3; ++c) shared->entries[m][c] += term.scale[c] * table->value[m];
    }
    lights_.push_back(std::move(prepared));
  }
}

Rgb MaterialShader::radiance(const Vec3& n, const Vec3& j_world, const Vec3& tangent) const {
  const TangentFrame frame(n, tangent);
  const Vec3 j = frame.local(j_world);
  const Vec3 j_clamped = clamp_to_horizon(j);
  Rgb out{0, 0, 0};
  for (const PreparedLight& light : lights_) {
    const Vec3 i = frame.local(light.direction);
    for (const LobeTerm& term : light.lobes) {
      const ShadingLobe& lobe = *term.lobe;
      double value = 0.0;
      switch (light.type) {
        case Light::Type::collimated:
          if (i.z > 0.0 && j.z > 0.0) value = i.z * lobe.model->f(i, j);
          break;
        case Light::Type::hemispherical:
          value = lobe.laws->g(i, j_clamped) + mirror_term(*lobe.model, j_clamped, &i);
          break;
        case Light::Type::ganzfeld:
          value = lobe.laws->h(j_clamped) + mirror_term(*lobe.model, j_clamped, nullptr);
          break;
      }
      for (int c = 0; c < 3; ++c) out[c] += term.scale[c] * value;
    }
    for (const LobeTerm& term : light.mirrors) {
      const Vec3* sky_pole = light.type == Light::Type::hemispherical ? &i : nullptr;
      const double rho = mirror_term(*term.lobe->model, j_clamped, sky_pole);
      for (int c = 0; c < 3; ++c) out[c] += term.scale[c] * rho;
    }
    if (light.tables.empty()) continue;
    // The law's coordinates once per light (TableLaws: g at (i, j clamped), h at clamped j·n).
    tables::Point x;
    if (light.type == Light::Type::hemispherical) x = tables::law_point(Law::g, i, j_clamped);
    else x.x[0] = std::clamp(j_clamped.z, 0.0, 1.0), x.size = 1;
    for (const SummedTable& table : light.tables) {
      table.lookup.visit(table.lookup.at_law(x), [&](std::size_t m, double w) {
        for (int c = 0; c < 3; ++c) out[c] += w * table.entries[m][c];
      });
    }
  }
  return out;
}

Rgb shade(const ShadingMaterial& material, const std::vector<Light>& lights, const Vec3& n, const Vec3& j_world,
          const Vec3& tangent) {
  return MaterialShader(material, lights).radiance(n, j_world, tangent);
}

void check_laws_available(const RenderScene& scene) {
  if (scene.mesh_material.size() != scene.meshes.size()) throw std::logic_error("one material index per mesh expected");
  const scene::LightFields needed = scene::light_fields(scene.lights);
  for (std::size_t m : scene.mesh_material) {  // materials no mesh uses are never shaded
    if (m >= scene.materials.size()) throw std::logic_error("mesh material index out of range");
    for (const ShadingLobe& lobe : scene.materials[m]) {
      if (!lobe.model) throw std::logic_error("a shading lobe has no model");
      if ((needed.sky || needed.ganzfeld) && !lobe.laws)
        throw std::logic_error("lobe " + lobe.model->spec() + " has no law source");
      if (needed.sky && !lobe.laws->has(Law::g)) throw std::logic_error("lobe " + lobe.model->spec() + " has no g");
      if (needed.ganzfeld && !lobe.laws->has(Law::h))
        throw std::logic_error("lobe " + lobe.model->spec() + " has no h");
    }
  }
}

Image shade_image(const RenderScene& scene, const GBuffer& gb) {
  check_laws_available(scene);
  std::vector<std::optional<MaterialShader>> shaders(scene.materials.size());
  for (std::size_t m : scene.mesh_material)
    if (!shaders[m]) shaders[m].emplace(scene.materials[m], scene.lights);
  Image image(gb.width, gb.height, scene.camera.background);
  tbb::parallel_for(tbb::blocked_range<int>(0, gb.height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < gb.width; ++x) {
        const Fragment& f = gb.at(x, y);
        if (f.mesh == Fragment::kNone) continue;
        const TangentRule rule = f.mesh < scene.mesh_tangent.size() ? scene.mesh_tangent[f.mesh] : TangentRule{};
        const Rgb c = shaders[scene.mesh_material[f.mesh]]->radiance(f.normal, f.view, brush_tangent(f.normal, rule));
        float* p = image.at(x, y);
        for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(c[k]);
      }
  });
  return image;
}

Image render(const RenderScene& scene) { return shade_image(scene, rasterize(scene.camera, scene.meshes)); }

void add_scene_geometry(const Scene& scene, RenderScene& out) {
  for (const SceneObject& object : scene.objects) {
    if (object.shape == SceneObject::Shape::sphere)
      out.meshes.push_back(uv_sphere(object.center, object.radius, kSphereSegments));
    else out.meshes.push_back(load_obj(object.mesh_path));
    out.mesh_material.push_back(object.material);
    out.mesh_tangent.push_back(object.tangent);
  }
}

namespace {
LawSourcePtr law_source(const scene::PlannedLobe& lobe, double direct_tolerance) {
  using scene::LawOrigin;
  const bool direct = lobe.g == LawOrigin::direct || lobe.h == LawOrigin::direct;
  const bool closed = lobe.g == LawOrigin::closed_form || lobe.h == LawOrigin::closed_form;
  if (direct) return direct_laws(lobe.model, direct_tolerance);
  if (closed) return lambert_laws();
  return table_laws(lobe.g_table, lobe.h_table);
}
}  // namespace

std::vector<ShadingMaterial> shading_materials(const scene::ShadingPlan& plan, double direct_tolerance) {
  std::vector<ShadingMaterial> out;
  for (const scene::PlannedMaterial& material : plan.materials) {
    ShadingMaterial shading;
    for (const scene::PlannedLobe& lobe : material)
      shading.push_back({lobe.weight, lobe.color, lobe.model, law_source(lobe, direct_tolerance)});
    out.push_back(std::move(shading));
  }
  return out;
}

RenderScene render_scene(const Scene& scene, const scene::ShadingPlan& plan, double direct_tolerance) {
  RenderScene out;
  out.camera = scene.camera;
  out.lights = scene.lights;
  add_scene_geometry(scene, out);
  out.materials = shading_materials(plan, direct_tolerance);
  return out;
}

}  // namespace ganzfeld::raster
