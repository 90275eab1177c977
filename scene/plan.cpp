#include "scene/plan.h"

#include <algorithm>

#include "models/registry.h"
#include "models/spec.h"

namespace ganzfeld::scene {

tables::BakeRequest TableOptions::request(Law law) const {
  if (target) {
    tables::TargetBake bake;
    bake.max_evaluations = max_evaluations;
    bake.encoding = encoding;
    bake.target = *target;
    return bake;
  }
  tables::BakeOptions grid;
  grid.max_evaluations = max_evaluations;
  grid.encoding = encoding;
  grid.resolution = law == Law::g ? resolution_g : resolution_h;
  grid.tolerance = tolerance;
  return grid;
}

TableOptions TableOptions::scene_defaults() {
  TableOptions options;
  options.target = tables::ErrorTarget{kSceneTargetError, kSceneMaxBytes, kSceneFetches, true};
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
        TableRequest r{lobe.spec, law, lobe.model, options.request(law)};
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
  const tables::BakeCommon& common = tables::common(request.options);
  std::vector<std::string> words{"ganzfeld", "bake", "--model", request.spec, "--law", to_string(request.law)};
  if (const auto* bake = std::get_if<tables::TargetBake>(&request.options)) {
    const tables::ErrorTarget& target = bake->target;
    words.insert(words.end(), {"--max-error", format_number(target.lookup_error)});
    if (target.max_bytes) words.insert(words.end(), {"--max-bytes", std::to_string(target.max_bytes)});
    if (target.max_fetches) words.insert(words.end(), {"--fetches", std::to_string(target.max_fetches)});
    if (target.best_effort) words.push_back("--best-effort");
  } else {
    const tables::BakeOptions& grid = std::get<tables::BakeOptions>(request.options);
    words.insert(words.end(),
                 {"--res", tables::resolution_text(grid.resolution), "--tol", format_number(grid.tolerance)});
  }
  words.insert(words.end(), {"--encoding", to_string(common.encoding), "--max-evals",
                             std::to_string(common.max_evaluations), "-o", path});
  return words;
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
