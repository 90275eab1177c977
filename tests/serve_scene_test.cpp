// GET /api/glsl?scene=SCENE (serve/service.h): the shader export-glsl --scene writes for the same
// scene and cache, its tables obtained through the service's bakery (into the cache, reused by
// the next request); refusals: a data file, a malformed scene, too many tables, mixed parameters.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "export/glsl.h"
#include "scene/plan.h"
#include "scene/scene.h"
#include "serve/service.h"
#include "tests/temp_dir.h"

namespace ganzfeld::serve {
namespace {

/// Two materials, one of two lobes, under all three light fields: g and h tables of each
/// non-Lambert lobe, four tables (Lambert needs none: K&P's closed forms).
constexpr const char* kScene = R"({
  "materials": {"plastic": {"lobes": [{"weight": 0.8, "model": "minnaert:xi=1"},
                                      {"weight": 0.2, "model": "specular:alpha=8"}]},
                "chalk": {"model": "lambert"}},
  "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "plastic"},
              {"shape": "sphere", "center": [2, 0, 0], "radius": 1, "material": "chalk"}],
  "lights": [{"type": "collimated", "direction": [1, 1, 1], "irradiance": [1, 1, 1]},
             {"type": "hemispherical", "pole": [0, 1, 0], "radiance": [0.3, 0.3, 0.3]},
             {"type": "ganzfeld", "radiance": [0.1, 0.1, 0.1]}]})";
constexpr std::size_t kSceneTables = 4;

/// Every byte but [A-Za-z0-9] as %XX: the query as a browser's encodeURIComponent sends it.
std::string percent_encoded(const std::string& text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : text) {
    if (std::isalnum(c)) {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

/// Small tables: the test checks plumbing, not accuracy.
scene::TableOptions small_tables() {
  scene::TableOptions o;
  o.resolution_g = {9, 9, 5};
  o.resolution_h = {17};
  o.tolerance = 1e-6;
  return o;
}

class ServeScene : public ::testing::Test {
 protected:
  std::string cache = [] {  // one per test: each starts from an empty cache
    const std::string dir =
        testing_support::temp_dir() + "/serve-scene-" + ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::create_directories(dir);
    return dir;
  }();
  ServiceOptions options() const {
    ServiceOptions o;
    o.cache_dir = cache;
    o.defaults = small_tables();
    return o;
  }
  static std::string header(const Reply& r, const std::string& name) {
    for (const auto& [key, value] : r.headers)
      if (key == name) return value;
    return "";
  }
};

TEST_F(ServeScene, ShaderIsExportGlslsForTheSameSceneAndCache) {
  Service service(options());
  const Reply first = service.handle("/api/glsl", "scene=" + percent_encoded(kScene), "");
  ASSERT_EQ(first.status, 200) << first.body;
  EXPECT_EQ(first.content_type, "text/plain; charset=utf-8");
  EXPECT_EQ(header(first, "X-Ganzfeld-Table"), "baked,baked,baked,baked");
  // export-glsl --scene's path: the same planner over the same cache, now filled by the service
  const Scene scene = load_scene_text(kScene, "scene");
  const scene::ShadingPlan plan =
      scene::plan_shading(scene, small_tables(), scene::TableStore{cache, false, {}, {}, {}});
  ASSERT_EQ(plan.tables.size(), kSceneTables);
  for (const scene::PlannedTable& t : plan.tables) EXPECT_EQ(t.status, tables::CacheStatus::reused) << t.path;
  EXPECT_EQ(first.body, exporting::glsl_scene_shader(scene, plan, kSceneShaderSource));
  // again: every table reused, the same bytes and tag; If-None-Match: 304
  const Reply again = service.handle("/api/glsl", "scene=" + percent_encoded(kScene), "");
  EXPECT_EQ(header(again, "X-Ganzfeld-Table"), "reused,reused,reused,reused");
  EXPECT_EQ(again.body, first.body);
  EXPECT_EQ(service.handle("/api/glsl", "scene=" + percent_encoded(kScene), header(first, "ETag")).status, 304);
}

TEST_F(ServeScene, JsonListsTheSamplersAndTheirCacheFiles) {
  Service service(options());
  const Reply r = service.handle("/api/glsl", "format=json&scene=" + percent_encoded(kScene), "");
  ASSERT_EQ(r.status, 200) << r.body;
  const auto doc = nlohmann::json::parse(r.body);
  ASSERT_EQ(doc["textures"].size(), kSceneTables);
  for (const auto& t : doc["textures"]) {
    const std::string sampler = t["sampler"];
    EXPECT_NE(doc["glsl"].get<std::string>().find(t["type"].get<std::string>() + " " + sampler + ";"),
              std::string::npos)
        << sampler;
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(cache) / t["file"].get<std::string>())) << t["file"];
  }
}

TEST_F(ServeScene, Refusals) {
  ServiceOptions o = options();
  o.limits.max_scene_tables = kSceneTables - 1;
  Service service(o);
  // The scene parser reads a model's data file while it parses the spec: refused before parsing,
  // in any string of the document, however the JSON escapes it (\u0066 is 'f').
  const std::string data_file = R"({"materials": {"m": {"model": "merl:file=/etc/passwd"}},
    "objects": [{"shape": "sphere", "material": "m"}], "lights": [{"type": "ganzfeld"}]})";
  const std::string escaped = R"({"materials": {"m": {"lobes": [{"model": "tabulated: \u0066ile = /etc/passwd"}]}}})";
  for (const auto& [query, status, fragment] : std::vector<std::tuple<std::string, int, std::string>>{
           {"scene=" + percent_encoded(kScene), 413, "the scene needs 4 tables; this service bakes at most 3"},
           {"scene=" + percent_encoded(data_file), 400, "names a data file"},
           {"scene=" + percent_encoded(escaped), 400, "names a data file"},
           {"scene=" + percent_encoded("{\"materials\": 3}"), 400, "scene 'scene': materials"},
           {"scene=%7B", 400, "malformed JSON"},
           {"scene=" + percent_encoded(kScene) + "&model=lambert", 400, "unknown parameter 'model'"},
           {"scene=" + percent_encoded(kScene) + "&format=exr", 400, "unknown format 'exr'; allowed: glsl, json"}}) {
    const Reply r = service.handle("/api/glsl", query, "");
    EXPECT_EQ(r.status, status) << query << " -> " << r.body;
    EXPECT_NE(nlohmann::json::parse(r.body)["error"].get<std::string>().find(fragment), std::string::npos) << r.body;
  }
  EXPECT_TRUE(std::filesystem::is_empty(cache));  // refused before any bake
}

}  // namespace
}  // namespace ganzfeld::serve
