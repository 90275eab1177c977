// Scenes (scene/scene.h), the tables they need (scene/plan.h) and the table cache (tables/cache.h):
// parsing with defaults, every refusal of a bad scene, the plan per light field, reuse of a
// cached table and re-baking of a corrupt or mismatching one.
#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/temp_dir.h"

#include "models/spec.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "tables/cache.h"
#include "tables/exr_io.h"
#include "util/error.h"
#include "util/hash.h"

// Suite names start with lower-case "scene" so that `ctest -R scene` selects exactly these.
namespace ganzfeld {
using namespace ganzfeld::tables;
using namespace ganzfeld::scene;

namespace {

namespace fs = std::filesystem;

// Tiny tables so the cache tests bake in well under a second: these tests are about which
// file is reused, not about accuracy.
constexpr double kTinyTol = 1e-6;
const std::vector<int> kTinyH{5};
const std::vector<int> kTinyG{3, 3, 3};
// Normalized weights are computed as w / sum(w): exact up to a couple of roundings.
constexpr double kWeightTol = 1e-15;

using testing_support::temp_dir;

/// Writes `text` to a fresh file in the temporary directory and returns its path.
std::string write_scene(const std::string& text) {
  static int counter = 0;
  const std::string path = (fs::path(temp_dir()) / ("scene" + std::to_string(counter++) + ".json")).string();
  std::ofstream(path) << text;
  return path;
}

Scene scene_from(const std::string& text) { return load_scene(write_scene(text)); }

/// The message load_scene gives for `text` ("" when it accepts the scene).
std::string refusal(const std::string& text) {
  try {
    load_scene(write_scene(text));
  } catch (const InputError& e) { return e.what(); }
  return "";
}

/// A scene with one sphere of material "m" = `material` (JSON) under `lights` (JSON array).
std::string sphere_scene(const std::string& material, const std::string& lights) {
  return R"({"materials": {"m": )" + material + R"(}, "objects": [{"shape": "sphere", "material": "m"}], "lights": )" +
         lights + "}";
}

std::vector<std::pair<std::string, Law>> plan_of(const Scene& scene) {
  std::vector<std::pair<std::string, Law>> out;
  for (const TableRequest& r : tables_needed(scene)) out.emplace_back(r.spec, r.law);
  return out;
}

// --- load_scene -----------------------------------------------------------------------------

TEST(Scene, ContractExampleParses) {
  const std::string mesh_dir = (fs::path(temp_dir()) / "meshes").string();
  const Scene s = scene_from(R"({
    "camera": {"width": 320, "height": 200, "eye": [0, 0, 6], "target": [0, 0, 0],
               "up": [0, 1, 0], "fov_deg": 25, "background": [0, 0, 0]},
    "materials": {
      "velvet":  {"model": "asperity:alpha=4", "color": [0.6, 0.1, 0.1]},
      "plastic": {"lobes": [{"weight": 0.8, "model": "minnaert:xi=1",   "color": [0.2, 0.4, 0.8]},
                            {"weight": 0.2, "model": "specular:alpha=8", "color": [1, 1, 1]}]}
    },
    "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "velvet"},
                {"shape": "mesh", "path": "meshes/model.obj", "material": "plastic"}],
    "lights": [{"type": "collimated",    "direction": [1, 1, 1], "irradiance": [1, 1, 1]},
               {"type": "hemispherical", "pole": [0, 1, 0],     "radiance": [0.5, 0.5, 0.5]},
               {"type": "ganzfeld",                               "radiance": [0.2, 0.2, 0.2]}]
  })");
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 200);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "velvet");  // file order
  ASSERT_EQ(s.materials[1].lobes.size(), 2u);
  EXPECT_EQ(s.materials[1].lobes[1].spec, "specular:alpha=8");
  EXPECT_NEAR(s.materials[1].lobes[0].weight, 0.8, kWeightTol);
  EXPECT_EQ(s.materials[1].lobes[0].color, (Rgb{0.2, 0.4, 0.8}));
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].material, 0u);
  EXPECT_EQ(s.objects[1].material, 1u);
  EXPECT_EQ(s.objects[1].shape, SceneObject::Shape::mesh);
  EXPECT_EQ(s.objects[1].mesh_path, (fs::path(mesh_dir) / "model.obj").string());
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[1].type, Light::Type::hemispherical);
  EXPECT_NEAR(glm::length(s.lights[0].direction), 1.0, kWeightTol);  // normalized
  EXPECT_NEAR(s.lights[0].direction.x, 1.0 / std::sqrt(3.0), kWeightTol);
}

TEST(Scene, DefaultsForMissingFields) {
  const Scene s = scene_from(R"({"camera": {"width": 64}, "materials": {"m": {"model": "lambert"}},
                                 "objects": [{"shape": "sphere", "material": "m"}]})");
  const Camera defaults;
  EXPECT_EQ(s.camera.width, 64);
  EXPECT_EQ(s.camera.height, defaults.height);
  EXPECT_EQ(s.camera.fov_deg, defaults.fov_deg);
  EXPECT_EQ(s.camera.eye, defaults.eye);
  EXPECT_EQ(s.materials[0].lobes[0].color, (Rgb{1, 1, 1}));
  EXPECT_EQ(s.objects[0].radius, 1.0);
  EXPECT_TRUE(s.lights.empty());
}

TEST(Scene, MixtureModelSplitsIntoLobesWithMultipliedWeights) {
  const Scene s = scene_from(sphere_scene(R"({"lobes": [
      {"weight": 1, "model": "0.7*minnaert:xi=1 + 0.3*specular:alpha=8", "color": [0, 0, 1]},
      {"weight": 1, "model": "lambert"}]})",
                                          "[]"));
  const auto& lobes = s.materials[0].lobes;
  ASSERT_EQ(lobes.size(), 3u);
  EXPECT_EQ(lobes[0].spec, "minnaert:xi=1");
  EXPECT_EQ(lobes[1].spec, "specular:alpha=8");
  EXPECT_EQ(lobes[2].spec, "lambert");
  EXPECT_NEAR(lobes[0].weight, 0.35, kWeightTol);
  EXPECT_NEAR(lobes[1].weight, 0.15, kWeightTol);
  EXPECT_NEAR(lobes[2].weight, 0.5, kWeightTol);
  EXPECT_EQ(lobes[1].color, (Rgb{0, 0, 1}));  // a mixture's lobes share its colour
  ASSERT_TRUE(lobes[1].model);
  EXPECT_EQ(lobes[1].model->spec(), "specular:alpha=8");
}

TEST(Scene, RefusesBadScenesNamingTheValue) {
  struct Case {
    std::string text, fragment;
  };
  const std::string m = R"("materials": {"m": {"model": "lambert"}})";
  const std::string sphere = R"("objects": [{"shape": "sphere", "material": "m"}])";
  const std::vector<Case> cases = {
      {"{\"camera\": {\"width\": 512,}}", "line 1, column"},
      {"[1, 2]", "[1,2]"},
      {R"({"camera": {}, "lamps": []})", "unknown top-level key 'lamps'; allowed: camera, materials, objects, lights"},
      {R"({"camera": {"width": 0}})", "camera.width = 0"},
      {R"({"camera": {"width": 16385}})", "16385"},
      {R"({"camera": {"height": 2.5}})", "camera.height = 2.5"},
      {R"({"camera": {"width": "512"}})", "camera.width = \"512\""},
      {R"({"camera": {"fov_deg": 180}})", "camera.fov_deg = 180"},
      {R"({"camera": {"fov_deg": 0}})", "camera.fov_deg = 0"},
      {R"({"camera": {"eye": [0, 0]}})", "camera.eye = [0,0]"},
      {R"({"camera": {"zoom": 2}})", "unknown key 'camera.zoom'"},
      {R"({"camera": {"up": [0, 0, 0]}})", "camera.up = [0,0,0]"},
      {"{" + m + R"(, "objects": [{"shape": "sphere", "material": "gold"}]})", "\"gold\" is not defined"},
      {"{" + m + R"(, "objects": [{"shape": "cube", "material": "m"}]})", "\"cube\""},
      {"{" + m + R"(, "objects": [{"shape": "sphere", "radius": 0, "material": "m"}]})", "objects[0].radius = 0"},
      {"{" + m + R"(, "objects": [{"shape": "sphere", "radius": -1, "material": "m"}]})", "radius = -1"},
      {"{" + m + R"(, "objects": [{"shape": "mesh", "material": "m"}]})", "has no \"path\""},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "spot"}]})",
       "\"spot\" is not allowed; allowed: collimated, hemispherical, ganzfeld"},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "collimated", "direction": [0, 0, 0]}]})",
       "lights[0].direction = [0,0,0]"},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "hemispherical", "pole": [0, 0, 0]}]})",
       "lights[0].pole = [0,0,0]"},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "collimated", "direction": [1e999, 0, 0]}]})",
       "number overflow parsing '1e999'"},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "collimated", "irradiance": [1, -1, 1]}]})",
       "lights[0].irradiance[1] = -1"},
      {"{" + m + "," + sphere + R"(, "lights": [{"type": "ganzfeld", "radiance": -0.5}]})", "radiance = -0.5"},
      {R"({"materials": {"m": {"model": "no-such-model"}}})", "unknown model 'no-such-model'"},
      {R"({"materials": {"m": {"model": "specular:alpha=0"}}})", "alpha=0"},
      {R"({"materials": {"m": {"model": "lambert", "color": [1, 1]}}})", "materials.m.color = [1,1]"},
      {R"({"materials": {"m": {"model": "lambert", "color": [1, -2, 1]}}})", "materials.m.color[1] = -2"},
      {R"({"materials": {"m": {"lobes": [{"weight": -1, "model": "lambert"}]}}})", "materials.m.lobes[0].weight = -1"},
      {R"({"materials": {"m": {"lobes": [{"weight": 1, "model": "lambert", "colour": 1}]}}})",
       "unknown key 'materials.m.lobes[0].colour'"},
      {R"({"materials": {"m": {}}})", "exactly one of"},
      {R"({"materials": {"m": {"model": "lambert", "shine": 1}}})", "unknown key 'materials.m.shine'"},
  };
  for (const Case& c : cases) {
    const std::string message = refusal(c.text);
    EXPECT_NE(message.find(c.fragment), std::string::npos) << c.text << "\n -> " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("scene '"), std::string::npos) << message;  // names the file
  }
}

TEST(Scene, RefusesMissingOrUnreadableFiles) {
  try {
    load_scene(temp_dir() + "/no/such/scene.json");
    FAIL() << "accepted a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_scene(temp_dir()), InputError);  // a directory
}

TEST(Scene, MeshPathIsRelativeToTheSceneFile) {
  const Scene s = scene_from(R"({"materials": {"m": {"model": "lambert"}},
                                 "objects": [{"shape": "mesh", "path": "../bunny.obj", "material": "m"},
                                             {"shape": "mesh", "path": "/abs/cube.obj", "material": "m"}]})");
  EXPECT_EQ(s.objects[0].mesh_path, (fs::path(temp_dir()).parent_path() / "bunny.obj").string());
  EXPECT_EQ(s.objects[1].mesh_path, "/abs/cube.obj");
}

// --- tables_needed ----------------------------------------------------------------------------

TEST(Scene, CollimatedOnlyNeedsNoTable) {
  const Scene s = scene_from(sphere_scene(R"({"model": "specular:alpha=8"})", R"([{"type": "collimated"}])"));
  EXPECT_TRUE(tables_needed(s).empty());
}

TEST(Scene, GanzfeldNeedsHOfNonLambertLobesOnly) {
  const Scene s =
      scene_from(sphere_scene(R"({"model": "0.5*lambert + 0.5*specular:alpha=8"})", R"([{"type": "ganzfeld"}])"));
  const auto plan = plan_of(s);
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0], std::make_pair(std::string("specular:alpha=8"), Law::h));
}

TEST(Scene, SkyAndGanzfeldNeedGAndHOfEachLobeDeduplicated) {
  const Scene s = scene_from(R"({
    "materials": {"a": {"model": "0.8*minnaert:xi=2 + 0.2*specular:alpha=8"},
                  "b": {"lobes": [{"weight": 1, "model": "specular:alpha=8", "color": [1, 0, 0]},
                                  {"weight": 1, "model": "asperity:alpha=4"},
                                  {"weight": 1, "model": "lambert"}]},
                  "unused": {"model": "backscatter:alpha=1"}},
    "objects": [{"shape": "sphere", "material": "b"}, {"shape": "sphere", "material": "a"},
                {"shape": "sphere", "material": "a"}],
    "lights": [{"type": "ganzfeld"}, {"type": "hemispherical"}, {"type": "collimated"}, {"type": "ganzfeld"}]
  })");
  const std::vector<std::pair<std::string, Law>> want = {{"minnaert:xi=2", Law::g},    {"specular:alpha=8", Law::g},
                                                         {"asperity:alpha=4", Law::g}, {"minnaert:xi=2", Law::h},
                                                         {"specular:alpha=8", Law::h}, {"asperity:alpha=4", Law::h}};
  EXPECT_EQ(plan_of(s), want);
}

TEST(Scene, AnisotropicLobesNeedNoTable) {
  // Their g would need a fourth axis; renders compute them directly instead (scene/plan.h).
  const Scene s = scene_from(sphere_scene(R"({"model": "0.5*ward-aniso + 0.5*specular:alpha=8"})",
                                          R"([{"type": "ganzfeld"}, {"type": "hemispherical"}])"));
  const std::vector<std::pair<std::string, Law>> want = {{"specular:alpha=8", Law::g}, {"specular:alpha=8", Law::h}};
  EXPECT_EQ(plan_of(s), want);
}

TEST(Scene, UnusedMaterialNeedsNothing) {
  const Scene s = scene_from(R"({"materials": {"m": {"model": "specular:alpha=8"}}, "objects": [],
                                 "lights": [{"type": "ganzfeld"}, {"type": "hemispherical"}]})");
  EXPECT_TRUE(tables_needed(s).empty());
}

// --- the cache --------------------------------------------------------------------------------

BakeOptions tiny(Law law) {
  BakeOptions o;
  o.resolution = law == Law::g ? kTinyG : kTinyH;
  o.tolerance = kTinyTol;
  return o;
}

std::string fresh_dir(const std::string& name) {
  const fs::path d = fs::path(temp_dir()) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

TEST(Scene, CacheKeyAndFileName) {
  const ModelPtr m = parse_model("specular:alpha=8");
  const TableKey key = table_key(*m, Law::h, tiny(Law::h));
  const std::string name = cache_file_name(key);
  EXPECT_EQ(name.rfind("specular_alpha=8.h.", 0), 0u) << name;
  EXPECT_EQ(name.size(), std::string("specular_alpha=8.h.").size() + 16 + 4) << name;
  EXPECT_EQ(name, cache_file_name(table_key(*m, Law::h, tiny(Law::h))));  // deterministic
  // Every part of the key changes the name.
  BakeOptions o = tiny(Law::h);
  o.tolerance = 1e-7;
  EXPECT_NE(cache_file_name(table_key(*m, Law::h, o)), name);
  o = tiny(Law::h);
  o.resolution = {6};
  EXPECT_NE(cache_file_name(table_key(*m, Law::h, o)), name);
  o = tiny(Law::h);
  o.encoding = Encoding::half;
  EXPECT_NE(cache_file_name(table_key(*m, Law::h, o)), name);
  o = tiny(Law::h);
  o.mappings = {Mapping::linear};
  EXPECT_NE(cache_file_name(table_key(*m, Law::h, o)), name);
  EXPECT_NE(cache_file_name(table_key(*m, Law::a, tiny(Law::a))), name);
  EXPECT_NE(cache_file_name(table_key(*parse_model("specular:alpha=9"), Law::h, tiny(Law::h))), name);
  EXPECT_EQ(util::fnv1a_64(""), 0xcbf29ce484222325ull);                       // the FNV-1a offset basis
  EXPECT_EQ(util::fnv1a_64("a"), 0xaf63dc4c8601ec8cull);                      // published test vector
  EXPECT_EQ(util::fnv1a_64("b", util::fnv1a_64("a")), util::fnv1a_64("ab"));  // in pieces
  EXPECT_EQ(util::content_digest_of("a"), "fnv1a64:af63dc4c8601ec8c");
  EXPECT_TRUE(util::is_content_digest("fnv1a64:af63dc4c8601ec8c"));
  EXPECT_FALSE(util::is_content_digest("fnv1a64:AF63DC4C8601EC8C"));
  EXPECT_FALSE(util::is_content_digest("fnv1a64:af63dc4c8601ec8"));
}

TEST(Scene, CacheReusesAMatchingTable) {
  const std::string dir = fresh_dir("reuse");
  const ModelPtr m = parse_model("specular:alpha=8");
  const CacheResult first = bake_or_reuse(cache_path(dir, *m, Law::g, tiny(Law::g)), *m, Law::g, tiny(Law::g), "test");
  EXPECT_EQ(first.status, CacheStatus::baked);
  EXPECT_TRUE(fs::exists(first.path));
  const auto written = fs::last_write_time(first.path);
  const CacheResult second = bake_or_reuse(cache_path(dir, *m, Law::g, tiny(Law::g)), *m, Law::g, tiny(Law::g), "test");
  EXPECT_EQ(second.status, CacheStatus::reused);
  EXPECT_EQ(second.path, first.path);
  EXPECT_EQ(second.table.value, first.table.value);
  EXPECT_EQ(fs::last_write_time(first.path), written);
  EXPECT_EQ(
      bake_or_reuse(cache_path(dir, *m, Law::g, tiny(Law::g)), *m, Law::g, tiny(Law::g), "test", /*force=*/true).status,
      CacheStatus::baked);
  // A different key is a different file.
  BakeOptions o = tiny(Law::g);
  o.encoding = Encoding::half;
  const CacheResult half = bake_or_reuse(cache_path(dir, *m, Law::g, o), *m, Law::g, o, "test");
  EXPECT_EQ(half.status, CacheStatus::baked);
  EXPECT_NE(half.path, first.path);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 2);  // no temporaries left
}

// A best-effort bake (the scene defaults) keeps the most accurate table its search made when the
// target is out of reach, its stated error the miss; that table serves best-effort requests only:
// a strict request for the same key bakes again and is refused.
TEST(Scene, CacheServesABestEffortTableOnlyToBestEffortRequests) {
  const std::string dir = fresh_dir("best-effort");
  const ModelPtr m = parse_model("specular:alpha=100");
  TargetBake o;
  o.target = {1e-6, 32, 0, true};  // 32 value bytes, 8 nodes of h: far from 1e-6
  const std::string path = cache_path(dir, *m, Law::h, o);
  const CacheResult first = bake_or_reuse(path, *m, Law::h, o, "test");
  EXPECT_EQ(first.status, CacheStatus::baked);
  EXPECT_GT(first.table.lookup_error, 1e-6);
  EXPECT_EQ(first.table.target_error, 1e-6);
  EXPECT_LE(value_bytes(first.table), 32u);
  EXPECT_EQ(bake_or_reuse(path, *m, Law::h, o, "test").status, CacheStatus::reused);
  TargetBake strict = o;
  strict.target.best_effort = false;
  EXPECT_EQ(cache_path(dir, *m, Law::h, strict), path);  // one file per target
  EXPECT_THROW(bake_or_reuse(path, *m, Law::h, strict, "test"), InputError);
  EXPECT_EQ(bake_or_reuse(path, *m, Law::h, o, "test").status, CacheStatus::reused);  // still there
}

TEST(Scene, CacheRebakesACorruptFile) {
  const std::string dir = fresh_dir("corrupt");
  const ModelPtr m = parse_model("asperity:alpha=4");
  const std::string path = cache_path(dir, *m, Law::h, tiny(Law::h));
  // Truncated: half of a valid table.
  const CacheResult good = bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test");
  const auto size = fs::file_size(path);
  fs::resize_file(path, size / 2);
  const CacheResult truncated =
      bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test");
  EXPECT_EQ(truncated.status, CacheStatus::baked);
  EXPECT_EQ(read_table(path).value, good.table.value);
  // Not an EXR at all.
  std::ofstream(path, std::ios::trunc) << "garbage";
  EXPECT_EQ(bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test").status,
            CacheStatus::baked);
  EXPECT_EQ(bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test").status,
            CacheStatus::reused);
}

TEST(Scene, CacheRebakesAMismatchingFile) {
  const std::string dir = fresh_dir("mismatch");
  const ModelPtr m = parse_model("specular:alpha=8");
  const std::string path = cache_path(dir, *m, Law::h, tiny(Law::h));
  // A valid table of another key sitting under this key's name (a copy, a stale file, a collision).
  BakeOptions other = tiny(Law::h);
  other.tolerance = 1e-5;
  EXPECT_EQ(bake_or_reuse(path, *m, Law::h, other, "test").status, CacheStatus::baked);
  EXPECT_EQ(read_table(path).tolerance, 1e-5);
  const CacheResult r = bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test");
  EXPECT_EQ(r.status, CacheStatus::baked);
  EXPECT_EQ(read_table(path).tolerance, kTinyTol);
  // And another model, same law and axes.
  EXPECT_EQ(bake_or_reuse(path, *parse_model("specular:alpha=9"), Law::h, tiny(Law::h), "test").status,
            CacheStatus::baked);
  EXPECT_EQ(bake_or_reuse(cache_path(dir, *m, Law::h, tiny(Law::h)), *m, Law::h, tiny(Law::h), "test").status,
            CacheStatus::baked);
  EXPECT_EQ(read_table(path).model, "specular:alpha=8");
}

// A tabulated BRDF of constant f (ganzfeld-tabulated-brdf 1 on a 2x2x2 grid) at `path`.
void write_constant_brdf(const std::string& path, const char* f) {
  std::ofstream out(path, std::ios::trunc);
  out << "ganzfeld-tabulated-brdf 1\ntheta_i: 0 90\ntheta_r: 0 90\nphi: 0 180\n";
  for (int k = 0; k < 8; ++k) out << f << " ";
}

// A measured model is keyed by its file's bytes, not by its path.
TEST(Scene, CacheKeysMeasuredModelsByContent) {
  const std::string dir = fresh_dir("content"), data = (fs::path(dir) / "m.tab").string();
  write_constant_brdf(data, "0.3");
  auto bake_at = [&](const std::string& path, const ModelPtr& m) {
    return bake_or_reuse(path, *m, Law::h, tiny(Law::h), "test").status;
  };
  const ModelPtr first = parse_model("tabulated:file=" + data);
  const std::string path = cache_path(dir, *first, Law::h, tiny(Law::h));
  EXPECT_EQ(bake_at(path, first), CacheStatus::baked);
  EXPECT_EQ(bake_at(path, parse_model("tabulated:file=" + data)), CacheStatus::reused);  // unchanged bytes
  EXPECT_EQ(read_table(path).model_content, first->content_digest());

  // New bytes at the same path: another key, so another cache file, and a fixed file is re-baked.
  write_constant_brdf(data, "0.2");
  const ModelPtr changed = parse_model("tabulated:file=" + data);
  EXPECT_EQ(changed->spec(), first->spec());
  const std::string changed_path = cache_path(dir, *changed, Law::h, tiny(Law::h));
  EXPECT_NE(changed_path, path);
  EXPECT_EQ(bake_at(changed_path, changed), CacheStatus::baked);
  EXPECT_EQ(bake_at(path, changed), CacheStatus::baked);
  EXPECT_NEAR(read_table(path).value.back(), 0.2 * 3.141592653589793, 1e-5);  // h = pi f

  // The same bytes at another path: the same key; the table keeps naming the path it was baked from.
  const std::string moved = (fs::path(dir) / "moved.tab").string();
  fs::rename(data, moved);
  const ModelPtr elsewhere = parse_model("tabulated:file=" + moved);
  EXPECT_EQ(cache_path(dir, *elsewhere, Law::h, tiny(Law::h)), changed_path);
  EXPECT_EQ(bake_at(changed_path, elsewhere), CacheStatus::reused);
  EXPECT_EQ(read_table(changed_path).model, changed->spec());
}

TEST(Scene, CacheRebakesAMeasuredTableWithoutContent) {
  // A table written before ganzfeld.model_content existed reads with an empty digest: analytic
  // ones stay valid, a measured one is baked again (what its file held then is unknown).
  const std::string dir = fresh_dir("no_content"), data = (fs::path(dir) / "m.tab").string();
  write_constant_brdf(data, "0.3");
  const ModelPtr m = parse_model("tabulated:file=" + data);
  const std::string path = cache_path(dir, *m, Law::h, tiny(Law::h));
  Table old = bake(*m, Law::h, tiny(Law::h));
  old.model_content.clear();
  write_table(old, path);
  EXPECT_EQ(bake_or_reuse(path, *m, Law::h, tiny(Law::h), "test").status, CacheStatus::baked);
  EXPECT_EQ(bake_or_reuse(path, *m, Law::h, tiny(Law::h), "test").status, CacheStatus::reused);
}

}  // namespace
}  // namespace ganzfeld
