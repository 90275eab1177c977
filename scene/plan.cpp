#include "scene/plan.h"

#include <algorithm>

#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld::scene {

tables::BakeOptions TableOptions::bake_options(Law law) const {
  tables::BakeOptions options;
  options.resolution = law == Law::g ? resolution_g : resolution_h;
  options.tolerance = tolerance;
  options.max_evaluations = max_evaluations;
  options.encoding = encoding;
  options.target_error = target_error;
  options.max_bytes = max_bytes;
  options.max_fetches = max_fetches;
  options.best_effort = best_effort;
  return options;
}

TableOptions TableOptions::scene_defaults() {
  TableOptions options;
  options.target_error = kSceneTargetError;
  options.max_fetches = kSceneFetches;
  options.best_effort = true;
  return options;
}

LightFields light_fields(const std::vector<Light>& lights) {
  LightFields fields;
  for (const Light& light : lights) {
    fields.collimated = fields.collimated || light.type == Light::Type::collimated;
    fields.sky = fields.sky || light.type == Light::Type::hemispherical;
    fields.ganzfeld = fields.ganzfeld || light.type == Light::Type::ganzfeld;
  }
  return fields;
}

LawOrigin law_origin(const Model& model, Law law, const LightFields& fields) {
  if (!(law == Law::g ? fields.sky : law == Law::h && fields.ganzfeld)) return LawOrigin::none;
  if (model.spec() == "lambert") return LawOrigin::closed_form;
  return model.traits().isotropic ? LawOrigin::table : LawOrigin::direct;
}

namespace {

std::vector<bool> materials_used(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (const SceneObject& object : scene.objects)
    if (object.material < used.size()) used[object.material] = true;
  return used;
}

/// tables_needed for materials flagged in `used`.
std::vector<TableRequest> requests_of(const std::vector<Material>& materials, const std::vector<bool>& used,
                                      const LightFields& fields, const TableOptions& options) {
  std::vector<TableRequest> out;
  for (const Law law : {Law::g, Law::h})
    for (std::size_t m = 0; m < materials.size(); ++m) {
      if (!used[m]) continue;
      for (const MaterialLobe& lobe : materials[m].lobes) {
        if (law_origin(*lobe.model, law, fields) != LawOrigin::table) continue;
        TableRequest r{lobe.spec, law, lobe.model, options.bake_options(law)};
        if (std::find(out.begin(), out.end(), r) == out.end()) out.push_back(std::move(r));
      }
    }
  return out;
}

}  // namespace

PlannedTable obtain_table(TableRequest request, const TableStore& store) {
  if (store.obtain) return store.obtain(std::move(request));
  PlannedTable out;
  if (store.before_bake) store.before_bake(request);
  if (store.cache_dir.empty()) {
    // Not stored, but stamped all the same: what exports and renders say made their tables
    // (the file name is the one the cache would give it).
    tables::Table table = tables::bake(*request.model, request.law, request.options);
    if (store.command_line)
      table.command = store.command_line(
          bake_command(request, tables::cache_path("", *request.model, request.law, request.options)));
    out.table = std::make_shared<const tables::Table>(std::move(table));
  } else {
    const std::string path = tables::cache_path(store.cache_dir, *request.model, request.law, request.options);
    const std::string command = store.command_line ? store.command_line(bake_command(request, path)) : "";
    tables::CacheResult r =
        tables::bake_or_reuse(path, *request.model, request.law, request.options, command, store.force);
    out.path = r.path;
    out.status = r.status;
    out.seconds = r.seconds;
    out.table = std::make_shared<const tables::Table>(std::move(r.table));
  }
  out.request = std::move(request);
  return out;
}

namespace {

std::shared_ptr<const tables::Table> find_table(const std::vector<PlannedTable>& tables, const std::string& spec,
                                                Law law) {
  for (const PlannedTable& t : tables)
    if (t.request.spec == spec && t.request.law == law) return t.table;
  return nullptr;
}

ShadingPlan plan(const std::vector<Material>& materials, std::vector<bool> used, const std::vector<Light>& lights,
                 const TableOptions& options, const TableStore& store, bool direct) {
  ShadingPlan out;
  out.fields = light_fields(lights);
  out.material_used = std::move(used);
  if (!direct)
    for (TableRequest& request : requests_of(materials, out.material_used, out.fields, options))
      out.tables.push_back(obtain_table(std::move(request), store));
  for (const Material& material : materials) {
    PlannedMaterial planned;
    for (const MaterialLobe& lobe : material.lobes) {
      PlannedLobe p;
      p.weight = lobe.weight;
      p.color = lobe.color;
      p.spec = lobe.spec;
      p.model = lobe.model;
      p.g = law_origin(*lobe.model, Law::g, out.fields);
      p.h = law_origin(*lobe.model, Law::h, out.fields);
      if (direct && p.g == LawOrigin::table) p.g = LawOrigin::direct;
      if (direct && p.h == LawOrigin::table) p.h = LawOrigin::direct;
      if (p.g == LawOrigin::table) p.g_table = find_table(out.tables, lobe.spec, Law::g);
      if (p.h == LawOrigin::table) p.h_table = find_table(out.tables, lobe.spec, Law::h);
      planned.push_back(std::move(p));
    }
    out.materials.push_back(std::move(planned));
  }
  return out;
}

}  // namespace

std::vector<TableRequest> tables_needed(const Scene& scene, const TableOptions& options) {
  return requests_of(scene.materials, materials_used(scene), light_fields(scene.lights), options);
}

std::vector<std::string> bake_command(const TableRequest& request, const std::string& path) {
  const tables::BakeOptions& o = request.options;
  if (o.target_error > 0.0) {
    std::vector<std::string> words{"ganzfeld", "bake", "--model", request.spec, "--law", to_string(request.law),
                                   "--max-error", format_number(o.target_error)};
    if (o.max_bytes) words.insert(words.end(), {"--max-bytes", std::to_string(o.max_bytes)});
    if (o.max_fetches) words.insert(words.end(), {"--fetches", std::to_string(o.max_fetches)});
    if (o.best_effort) words.push_back("--best-effort");
    words.insert(words.end(), {"--encoding", to_string(o.encoding), "--max-evals", std::to_string(o.max_evaluations),
                               "-o", path});
    return words;
  }
  return {"ganzfeld", "bake", "--model", request.spec, "--law", to_string(request.law),
          "--res", tables::resolution_text(o.resolution), "--tol", format_number(o.tolerance),
          "--encoding", to_string(o.encoding), "--max-evals", std::to_string(o.max_evaluations),
          "-o", path};
}

ShadingPlan plan_shading(const Scene& scene, const TableOptions& options, const TableStore& store, bool direct) {
  return plan(scene.materials, materials_used(scene), scene.lights, options, store, direct);
}

ShadingPlan plan_material(const Material& material, const std::vector<Light>& lights, const TableOptions& options,
                          const TableStore& store) {
  return plan({material}, {true}, lights, options, store, false);
}

Material material_of(const std::string& spec) {
  Material material{spec, {}};
  for (const Lobe& lobe : parse_lobes(spec)) material.lobes.push_back({lobe.weight, lobe.model->spec(), lobe.model});
  return material;
}

}  // namespace ganzfeld::scene
