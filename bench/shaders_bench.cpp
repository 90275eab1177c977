#include "bench/shaders_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bench/cubature_bench.h"
#include "export/glsl.h"
#include "export/glsl_f.h"
#include "export/param_export.h"
#include "gl/draw.h"
#include "models/spec.h"
#include "scene/plan.h"
#include "tables/bake.h"
#include "tables/preset.h"
#include "tables/sample.h"
#include "util/error.h"
#include "util/timing.h"

namespace ganzfeld::bench {

ShadersBenchOptions quick_shaders_options() {
  ShadersBenchOptions options;
  options.quick = true;
  options.size = 128;
  options.points_side = 32;
  return options;
}

namespace {

/// The fetch-counting pass is this many pixels on a side (the same normals and views as the
/// timed pass, fewer of them).
constexpr int kCountSide = 256;
/// The split-sum pass: a cubemap of this many texels on a side at level 0, all mips; the DFG
/// table's samples per axis (ganzfeld's default) and the quick run's.
constexpr int kEnvironmentSide = 64;
constexpr int kDfgSamples = 64, kQuickDfgSamples = 16;

// ---------------------------------------------------------------------------------------------
// GLSL

/// The pass around a shading call: the pixel's normal and view, and the output (the colour, or
/// the fetches counted, when GZ_COUNT_FETCHES is defined).
std::string pass_main(const std::string& shade) {
  return R"(
uniform vec2 u_size;
out vec4 out_color;
// The pixel's normal: the hemisphere facing the viewer (+z), octahedrally mapped onto the square
// (Cigolle et al. 2014, "A Survey of Efficient Representations for Independent Unit Vectors",
// hemi-octahedral), so that every pixel has its own; its view: a pinhole camera's ray.
void main() {
  vec2 p = gl_FragCoord.xy / u_size * 2.0 - 1.0;
  vec2 t = 0.5 * vec2(p.x + p.y, p.x - p.y);
  vec3 n = normalize(vec3(t, 1.0 - abs(t.x) - abs(t.y)));
  vec3 j = normalize(vec3(-0.25 * p, 1.0));
  vec3 c = )" +
         shade + R"(;
#ifdef GZ_COUNT_FETCHES
  out_color = vec4(float(gz_fetches), c);
#else
  out_color = vec4(c, 1.0);
#endif
}
)";
}

/// S: a standard GGX point light + split-sum image-based light (Karis 2013, "Real Shading in
/// Unreal Engine 4"; Filament's shading model: Lagarde's height-correlated Smith visibility, the
/// DFG table in Filament's channel order, SH irradiance up to l = 2, Ramamoorthi & Hanrahan 2001).
constexpr const char* kSplitSum = R"(
const float GZ_PI = 3.14159265;
uniform highp samplerCube u_environment;  // prefiltered radiance: mip level = roughness x u_max_lod
uniform highp sampler2D u_dfg;            // RG16F (dfg_fc, dfg_e) over (n.v, roughness), texel grid
uniform vec3 u_sh[9];                     // irradiance SH, the band constants folded in
uniform vec3 u_light_direction;
uniform vec3 u_light_irradiance;
uniform vec3 u_base_color;
uniform float u_roughness;
uniform float u_f0;
uniform float u_max_lod;
float gz_d_ggx(float NoH, float a) {
  float a2 = a * a;
  float f = (NoH * a2 - NoH) * NoH + 1.0;
  return a2 / (GZ_PI * f * f);
}
float gz_v_smith_ggx_correlated(float NoV, float NoL, float a) {
  float a2 = a * a;
  float lambda_v = NoL * sqrt((NoV - NoV * a2) * NoV + a2);
  float lambda_l = NoV * sqrt((NoL - NoL * a2) * NoL + a2);
  return 0.5 / (lambda_v + lambda_l);
}
vec3 gz_irradiance_sh(vec3 n) {
  return u_sh[0] + u_sh[1] * n.y + u_sh[2] * n.z + u_sh[3] * n.x + u_sh[4] * (n.y * n.x) + u_sh[5] * (n.y * n.z) +
         u_sh[6] * (3.0 * n.z * n.z - 1.0) + u_sh[7] * (n.z * n.x) + u_sh[8] * (n.x * n.x - n.y * n.y);
}
vec3 gz_split_sum(vec3 n, vec3 v) {
  float NoV = max(dot(n, v), 1e-4);
  vec3 l = u_light_direction;
  vec3 h = normalize(v + l);
  float NoL = clamp(dot(n, l), 0.0, 1.0), NoH = clamp(dot(n, h), 0.0, 1.0), LoH = clamp(dot(l, h), 0.0, 1.0);
  float a = u_roughness * u_roughness;
  vec3 f0 = vec3(u_f0);
  vec3 F = f0 + (1.0 - f0) * pow(1.0 - LoH, 5.0);
  vec3 direct = (gz_d_ggx(NoH, a) * gz_v_smith_ggx_correlated(NoV, NoL, a) * F + u_base_color / GZ_PI) *
                u_light_irradiance * NoL;
  vec2 dfg = texture(u_dfg, vec2(NoV, u_roughness)).rg;
  vec3 E = mix(dfg.xxx, dfg.yyy, f0);  // Schlick: f0 dfg_e + (1 - f0) dfg_fc
  vec3 specular = textureLod(u_environment, reflect(-v, n), u_roughness * u_max_lod).rgb * E;
  return direct + specular + u_base_color * gz_irradiance_sh(n);
}
)";

/// The fragment shader of a pass: `body` (functions and uniforms), then main calling `shade`.
/// With count, every texture call of the body is counted (gl::count_texture_fetches).
std::string fragment_source(const std::string& define, bool count, const std::string& body, const std::string& shade) {
  std::string out = std::string("#version ") + gl::glsl_version(gl::Api::core43) + "\n";
  if (!define.empty()) out += "#define " + define + "\n";
  if (count) out += "#define GZ_COUNT_FETCHES\nint gz_fetches = 0;\n";
  return out + (count ? gl::count_texture_fetches(body) : body) + pass_main(shade);
}

/// The variants a GLSL text offers: "" and every GANZFELD_* macro it tests with #ifdef.
std::vector<std::string> variants(const std::string& glsl) {
  std::vector<std::string> out{""};
  static const std::regex ifdef(R"(#\s*ifdef\s+(GANZFELD_[A-Z0-9_]+))");
  std::set<std::string> seen;
  for (auto it = std::sregex_iterator(glsl.begin(), glsl.end(), ifdef); it != std::sregex_iterator(); ++it)
    if (seen.insert((*it)[1]).second) out.push_back((*it)[1]);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Scenes

const Light kSun{Light::Type::collimated, glm::normalize(Vec3{0.4, 0.6, 0.7}), {1.0, 0.95, 0.9}};
const Light kSky{Light::Type::hemispherical, glm::normalize(Vec3{0.2, 0.9, 0.4}), {0.3, 0.35, 0.45}};
const Light kAmbient{Light::Type::ganzfeld, {0, 0, 1}, {0.1, 0.1, 0.1}};

struct TableSet {
  std::string label;
  scene::TableOptions options;
};

/// The bake requests whose tables are measured: their schemes are whatever `bake` makes of them.
std::vector<TableSet> table_sets(bool quick) {
  if (quick) {
    scene::TableOptions small{{9, 9, 5}, {17}, 1e-6};
    scene::TableOptions to_error;
    to_error.target = tables::ErrorTarget{1e-2, 0, 0};
    return {{"`--res 9x9x5` (g), `--res 17` (h)", small}, {"`--max-error 1e-2`", to_error}};
  }
  std::vector<TableSet> out{
      {"scene defaults (`bake scene`: `--max-error 1e-3 --fetches 1`)", scene::TableOptions::scene_defaults()}};
  for (const auto& [e, text] : {std::pair{1e-3, "1e-3"}, std::pair{1e-4, "1e-4"}}) {
    scene::TableOptions options;
    options.target = tables::ErrorTarget{e, 0, 0};
    out.push_back({std::string("`--max-error ") + text + "`", options});
  }
  // Eight fetches per law: the b-spline's two hardware-filtered fetches per axis (docs/lut-format.md).
  scene::TableOptions eight;
  eight.target = tables::ErrorTarget{3e-4, 0, 8};
  out.push_back({"`--max-error 3e-4 --fetches 8`", eight});
  return out;
}

Scene scene_of(const Material& material, std::vector<Light> lights) {
  Scene scene;
  scene.materials = {material};
  scene.lights = std::move(lights);
  return scene;
}

// ---------------------------------------------------------------------------------------------
// Passes on the GPU

/// What a pass binds: its programs (timed, counting), textures and uniforms.
struct Bound {
  gl::Program timed, counting;
  std::vector<std::pair<GLenum, GLuint>> textures;  ///< per unit: target, name
  std::function<void(const gl::Program&)> set_uniforms;
};

void check_program(const gl::Program& program, const std::string& log, const std::string& pass) {
  if (!program) throw std::runtime_error("bench shaders: the " + pass + " pass does not compile: " + log);
}

void use(const Bound& bound, const gl::Program& program, int size) {
  glUseProgram(program.id());
  for (std::size_t unit = 0; unit < bound.textures.size(); ++unit) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
    glBindTexture(bound.textures[unit].first, bound.textures[unit].second);
  }
  glUniform2f(program.uniform("u_size"), static_cast<float>(size), static_cast<float>(size));
  if (bound.set_uniforms) bound.set_uniforms(program);
}

/// Counted fetches per pixel of a pass: mean and max over a kCountSide² pass.
std::pair<double, int> count_fetches(const Bound& bound) {
  const gl::Framebuffer target(kCountSide, kCountSide, GL_RGBA32F);
  use(bound, bound.counting, kCountSide);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  const std::vector<float> pixels = target.read_rgba();
  double sum = 0.0;
  int most = 0;
  for (std::size_t p = 0; p < pixels.size(); p += 4) {
    sum += pixels[p];
    most = std::max(most, static_cast<int>(pixels[p]));
  }
  return {sum / (pixels.size() / 4), most};
}

/// A cubemap of kEnvironmentSide² RGBA16F faces with every mip level (glGenerateMipmap's box
/// filter: a prefiltered chain as far as the texture's cost goes), a procedural sky.
gl::Texture environment_map(std::uint64_t& bytes) {
  GLuint id = 0;
  glGenTextures(1, &id);
  gl::Texture texture(id);
  glBindTexture(GL_TEXTURE_CUBE_MAP, id);
  std::vector<float> texels(static_cast<std::size_t>(kEnvironmentSide) * kEnvironmentSide * 4);
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < kEnvironmentSide; ++y)
      for (int x = 0; x < kEnvironmentSide; ++x) {
        const double u = (x + 0.5) / kEnvironmentSide * 2.0 - 1.0, v = (y + 0.5) / kEnvironmentSide * 2.0 - 1.0;
        const Vec3 d = glm::normalize(face == 0   ? Vec3{1, -v, -u}
                                      : face == 1 ? Vec3{-1, -v, u}
                                      : face == 2 ? Vec3{u, 1, v}
                                      : face == 3 ? Vec3{u, -1, -v}
                                      : face == 4 ? Vec3{u, -v, 1}
                                                  : Vec3{-u, -v, -1});
        const double up = std::max(d.y, 0.0), sun = std::pow(std::max(glm::dot(d, kSun.direction), 0.0), 64.0);
        float* t = &texels[(static_cast<std::size_t>(y) * kEnvironmentSide + x) * 4];
        t[0] = static_cast<float>(0.2 + 0.3 * up + 4.0 * sun);
        t[1] = static_cast<float>(0.25 + 0.4 * up + 3.8 * sun);
        t[2] = static_cast<float>(0.3 + 0.6 * up + 3.5 * sun);
        t[3] = 1.0f;
      }
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, 0, GL_RGBA16F, kEnvironmentSide, kEnvironmentSide, 0, GL_RGBA,
                 GL_FLOAT, texels.data());
  }
  glGenerateMipmap(GL_TEXTURE_CUBE_MAP);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  bytes = 0;
  for (int side = kEnvironmentSide; side >= 1; side /= 2) bytes += 6ull * side * side * 8;  // RGBA16F
  return texture;
}

/// The DFG table as engines upload it: the first two channels (dfg_fc, dfg_e) as RG16F, texel grid.
gl::Texture dfg_texture(const tables::ParamTable& table, std::uint64_t& bytes) {
  const std::vector<std::uint16_t> all = exporting::param_half_texels(table);
  const std::size_t channels = table.channels.size(), texels = table.entries();
  std::vector<std::uint16_t> rg(2 * texels);
  for (std::size_t m = 0; m < texels; ++m) {
    rg[2 * m] = all[m * channels];
    rg[2 * m + 1] = all[m * channels + 1];
  }
  GLuint id = 0;
  glGenTextures(1, &id);
  gl::Texture texture(id);
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RG16F, table.axes[1].count, table.axes[0].count, 0, GL_RG, GL_HALF_FLOAT,
               rg.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  bytes = rg.size() * 2;
  return texture;
}

ShaderPass named(std::string name, std::string what, std::string table_set = "", std::string define = "") {
  ShaderPass pass;
  pass.name = std::move(name);
  pass.what = std::move(what);
  pass.table_set = std::move(table_set);
  pass.define = std::move(define);
  return pass;
}

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

}  // namespace

ShadersBenchResult run_shaders_benchmark(const ShadersBenchOptions& options) {
  if (options.size < 16 || options.size > 8192)
    throw InputError("--size " + std::to_string(options.size) + " is not allowed; allowed: 16 to 8192 pixels");
  if (options.frames < 1 || options.frames > 10000)
    throw InputError("--frames " + std::to_string(options.frames) + " is not allowed; allowed: 1 to 10000");
  const ModelPtr lobe = parse_model(options.model);
  const Material material = scene::material_of("0.8*lambert + 0.2*" + lobe->spec());
  exporting::glsl_model_f(*lobe);  // the point light needs the lobe's f in GLSL: refuse early

  std::string error;
  const auto context = gl::make_context(gl::Api::core43, options.platform, error);
  if (!context) throw std::runtime_error("bench shaders: no OpenGL 4.3 context: " + error);
  ShadersBenchResult result;
  result.context = context->info();
  result.timer = result.context.software ? "wall time (glFinish)" : "GL_TIME_ELAPSED";
  result.size = options.size;
  result.frames = options.frames;
  result.points = options.points_side * options.points_side;
  result.model = lobe->spec();

  scene::TableStore store;
  store.cache_dir = options.cache_dir;
  store.command_line = join;
  std::vector<std::unique_ptr<Bound>> bound;
  std::vector<gl::Texture> textures;  // alive until the end
  auto add_pass = [&](ShaderPass pass, const std::string& body, const std::string& shade) {
    auto b = std::make_unique<Bound>();
    std::string log;
    b->timed = gl::link_program(gl::fullscreen_vertex_shader(gl::Api::core43),
                                fragment_source(pass.define, false, body, shade), log);
    check_program(b->timed, log, pass.name);
    b->counting = gl::link_program(gl::fullscreen_vertex_shader(gl::Api::core43),
                                   fragment_source(pass.define, true, body, shade), log);
    check_program(b->counting, log, pass.name + " (counting)");
    result.passes.push_back(std::move(pass));
    bound.push_back(std::move(b));
    return bound.back().get();
  };

  // A: Lambert under the point light and the ambient Ganzfeld, the scene shader's closed forms.
  {
    const Scene scene = scene_of(scene::material_of("lambert"), {kSun, kAmbient});
    const scene::ShadingPlan plan = scene::plan_material(scene.materials[0], scene.lights, {}, store);
    add_pass(named("A",
                   "Lambert + point light + ambient (the scene shader of `lambert` under a collimated light "
                   "and a Ganzfeld: closed forms)"),
             exporting::glsl_scene_shader(scene, plan, "bench shaders: A"), "gz_scene_radiance(0, n, j)");
  }
  // S: GGX point light + split-sum IBL.
  {
    tables::PresetOptions preset;
    const int samples = options.quick ? kQuickDfgSamples : kDfgSamples;
    preset.resolution = {samples, samples};
    const tables::ParamTable dfg = tables::bake_preset(*parse_model("ggx"), preset);
    std::uint64_t environment_bytes = 0, dfg_bytes = 0;
    glActiveTexture(GL_TEXTURE0);
    textures.push_back(environment_map(environment_bytes));
    glActiveTexture(GL_TEXTURE1);
    textures.push_back(dfg_texture(dfg, dfg_bytes));
    ShaderPass pass =
        named("S", "GGX point light (height-correlated Smith, Schlick) + split-sum IBL: a " +
                       std::to_string(kEnvironmentSide) +
                       "² RGBA16F cubemap with mips, one RG16F fetch "
                       "of a " +
                       std::to_string(samples) + "² DFG table (`bake preset dfg --model ggx`), 9 SH coefficients");
    pass.value_bytes = environment_bytes + dfg_bytes;
    Bound* b = add_pass(std::move(pass), kSplitSum, "gz_split_sum(n, j)");
    b->textures = {{GL_TEXTURE_CUBE_MAP, textures[textures.size() - 2].id()}, {GL_TEXTURE_2D, textures.back().id()}};
    b->set_uniforms = [](const gl::Program& p) {
      glUniform1i(p.uniform("u_environment"), 0);
      glUniform1i(p.uniform("u_dfg"), 1);
      const float sh[27] = {0.8f,  0.85f, 0.9f,  0.2f,  0.25f, 0.3f,  0.1f,  0.1f,  0.12f,
                            0.05f, 0.04f, 0.03f, 0.02f, 0.02f, 0.02f, 0.01f, 0.01f, 0.01f,
                            0.03f, 0.03f, 0.04f, 0.01f, 0.01f, 0.01f, 0.02f, 0.02f, 0.02f};
      glUniform3fv(p.uniform("u_sh"), 9, sh);
      glUniform3f(p.uniform("u_light_direction"), static_cast<float>(kSun.direction.x),
                  static_cast<float>(kSun.direction.y), static_cast<float>(kSun.direction.z));
      glUniform3f(p.uniform("u_light_irradiance"), 1.0f, 0.95f, 0.9f);
      glUniform3f(p.uniform("u_base_color"), 0.6f, 0.6f, 0.6f);
      glUniform1f(p.uniform("u_roughness"), 0.5f);
      glUniform1f(p.uniform("u_f0"), 0.04f);
      glUniform1f(p.uniform("u_max_lod"), std::log2(static_cast<float>(kEnvironmentSide)));
    };
  }
  // T: every table set, every variant of its GLSL.
  const gl::LookupPoints points_g = gl::lookup_points(Law::g, options.points_side, kShaderPointSeed);
  const gl::LookupPoints points_h = gl::lookup_points(Law::h, options.points_side, kShaderPointSeed);
  int set_number = 0;
  for (const TableSet& set : table_sets(options.quick)) {
    ++set_number;
    const Scene scene = scene_of(material, {kSun, kSky, kAmbient});
    const scene::ShadingPlan plan = scene::plan_material(scene.materials[0], scene.lights, set.options, store);
    const std::string glsl = exporting::glsl_scene_shader(scene, plan, "bench shaders: " + set.label);
    for (const std::string& define : variants(glsl)) {
      ShaderPass pass =
          named("T" + std::to_string(set_number) + (define.empty() ? "" : " " + define), "", set.label, define);
      std::vector<std::pair<GLenum, GLuint>> units;
      std::vector<std::pair<std::string, int>> samplers;
      for (const scene::PlannedTable& t : plan.tables) {
        const tables::Table& table = *t.table;
        LawLookup law;
        law.law = table.law;
        law.scheme = exporting::lookup_scheme(table);
        law.lookup_error = table.lookup_error;
        law.value_bytes = tables::value_bytes(table);
        const gl::LookupPoints& points = table.law == Law::g ? points_g : points_h;
        std::string lookup_error;
        const gl::Lookups lookups =
            gl::table_function_at_points(table, points, gl::Api::core43, define, true, lookup_error);
        if (lookups.values.empty())
          throw std::runtime_error("bench shaders: the lookup of " + table.model + " does not run: " + lookup_error);
        law.points = static_cast<int>(lookups.values.size());
        law.fetches_min = *std::min_element(lookups.fetches.begin(), lookups.fetches.end());
        law.fetches_max = *std::max_element(lookups.fetches.begin(), lookups.fetches.end());
        // A table whose bound covers the hardware filter: the closest of the full-precision lookup and
        // the two 8-bit emulations (`sample --hardware-filter`), since a GPU's filter does one of them.
        const bool filtered = table.filter == tables::Filter::hardware;
        for (std::size_t p = 0; p < lookups.values.size(); ++p) {
          double difference = std::abs(lookups.values[p] - tables::sample(table, points.x[p]).value);
          if (filtered)
            for (tables::WeightRounding r : {tables::WeightRounding::nearest, tables::WeightRounding::truncate})
              difference =
                  std::min(difference, std::abs(lookups.values[p] - tables::sample(table, points.x[p], r).value));
          law.max_difference = std::max(law.max_difference, difference);
        }
        pass.laws.push_back(law);
        pass.value_bytes += law.value_bytes;
        const int unit = static_cast<int>(units.size());
        textures.push_back(gl::upload_table(table, unit, true));
        units.push_back({table.law == Law::g ? GL_TEXTURE_3D : GL_TEXTURE_2D, textures.back().id()});
        samplers.push_back({exporting::glsl_sampler_name(t.request.spec, table.law), unit});
      }
      pass.what = "0.8 lambert + 0.2 `" + lobe->spec() +
                  "` under the point light, a sky and a Ganzfeld (the scene "
                  "shader: f closed form, g and h from the tables)";
      Bound* b = add_pass(std::move(pass), glsl, "gz_scene_radiance(0, n, j)");
      b->textures = units;
      b->set_uniforms = [samplers](const gl::Program& p) {
        for (const auto& [name, unit] : samplers) glUniform1i(p.uniform(name.c_str()), unit);
      };
    }
  }

  // Fetches per pixel, then the timed frames, interleaved across the passes.
  const gl::VertexArray vertices;
  for (std::size_t k = 0; k < bound.size(); ++k)
    std::tie(result.passes[k].fetches_mean, result.passes[k].fetches_max) = count_fetches(*bound[k]);
  const gl::Framebuffer target(options.size, options.size, GL_RGBA16F);
  if (!target.complete()) throw std::runtime_error("bench shaders: the RGBA16F framebuffer is not complete");
  GLuint query = 0;
  glGenQueries(1, &query);
  for (int frame = -kWarmupFrames; frame < options.frames; ++frame)
    for (std::size_t k = 0; k < bound.size(); ++k) {
      use(*bound[k], bound[k]->timed, options.size);
      glFinish();
      const util::Stopwatch watch;
      if (!result.context.software) glBeginQuery(GL_TIME_ELAPSED, query);
      glDrawArrays(GL_TRIANGLES, 0, 3);
      if (!result.context.software) glEndQuery(GL_TIME_ELAPSED);
      glFinish();
      double milliseconds = 1e3 * watch.seconds();
      if (!result.context.software) {
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &nanoseconds);
        milliseconds = 1e-6 * static_cast<double>(nanoseconds);
      }
      if (frame >= 0) result.passes[k].milliseconds.push_back(milliseconds);
    }
  glDeleteQueries(1, &query);
  if (const GLenum status = glGetError(); status != GL_NO_ERROR)
    throw std::runtime_error("bench shaders: GL error " + std::to_string(status));
  bound.clear();
  return result;
}

// ---------------------------------------------------------------------------------------------
// Markdown

namespace {

double median_of(const ShaderPass& pass) { return util::median(pass.milliseconds); }

std::string verdict(bool met) { return met ? "**met**" : "**missed**"; }

}  // namespace

std::string shaders_section(const ShadersBenchResult& result) {
  return result.context.software ? "shaders-software" : "shaders-gpu";
}

std::string shaders_markdown(const ShadersBenchResult& r, const std::string& command) {
  const ShaderPass& a = r.passes.at(0);
  const ShaderPass& s = r.passes.at(1);
  const double ma = median_of(a), ms = median_of(s);
  std::ostringstream md;
  md << "## Shading cost in a fragment shader: " << r.context.gl_renderer << "\n\n"
     << "<!-- generated by `" << command << "`; do not edit -->\n\n"
     << "Generated by `" << command << "` on " << today_utc() << " (UTC). GL_RENDERER `" << r.context.gl_renderer
     << "`, GL_VERSION `" << r.context.gl_version << "`, GL_VENDOR `" << r.context.gl_vendor << "`, through the "
     << r.context.platform << " platform (" << r.context.egl_vendor
     << (r.context.device.empty() ? "" : "; device: " + r.context.device) << "); host: " << util::machine_description()
     << ". The machine is shared with other work; the passes' frames are interleaved, so a change of load hits "
        "every pass alike.\n\n"
     << "Each pass shades " << r.size << "×" << r.size
     << " pixels into an RGBA16F target, every pixel its own normal (the hemisphere facing the viewer, "
        "octahedrally mapped onto the square) and view. Times: "
     << r.timer << " per frame, the median and the range of " << r.frames << " frames after " << kWarmupFrames
     << " warm-up frames"
     << (r.context.software ? " (a software renderer's timer queries miss the rasterization, so the wall time "
                              "around the draw and glFinish is the honest figure)"
                            : "")
     << ". Fetches: the texture calls each pixel executed, counted by the shader itself over a " << kCountSide << "² "
     << "pass (mean, and max where it differs). Value bytes: what the pass's textures hold.\n\n"
     << "| pass | what | fetches / pixel | value bytes | ms per frame (median) | min … max | ÷ A | ÷ S |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const ShaderPass& p : r.passes) {
    const auto [lo, hi] = std::minmax_element(p.milliseconds.begin(), p.milliseconds.end());
    std::string what = p.what;
    if (!p.table_set.empty()) {
      what = p.table_set + (p.define.empty() ? ", texelFetch" : ", `" + p.define + "`") + ": ";
      for (const LawLookup& l : p.laws) what += std::string(to_string(l.law)) + " " + l.scheme + "; ";
      what.resize(what.size() - 2);
    }
    std::string fetches = significant(p.fetches_mean, 4);
    if (p.fetches_max != static_cast<int>(std::lround(p.fetches_mean)))
      fetches += " (max " + std::to_string(p.fetches_max) + ")";
    md << "| " << p.name << " | " << what << " | " << fetches << " | " << p.value_bytes << " | "
       << significant(median_of(p), 4) << " | " << significant(*lo, 4) << " … " << significant(*hi, 4) << " | "
       << significant(median_of(p) / ma) << " | " << significant(median_of(p) / ms) << " |\n";
  }
  md << "\nT passes shade 0.8 `lambert` + 0.2 `" << r.model
     << "` under a collimated light, a hemispherical sky and a Ganzfeld with the scene shader `export-glsl --scene` "
        "writes (f of each lobe in closed form, Lambert's g and h in closed form, the lobe's g and h from its "
        "tables): A with the glossy lobe's three terms on top. Each table set is a bake request; its schemes are "
        "what `bake` made of it (the tables' own metadata), and each variant is one the exported GLSL offers.\n\n"
     << "### The lookups against `ganzfeld sample`\n\n"
     << "Each table's exported function at " << r.points
     << " seeded points (i·n, j·n, φ uniform, in random frames, i and j of random lengths), read back from an "
        "RGBA32F target, against tables::sample at the same points (what `ganzfeld sample` prints; for a table "
        "whose bound covers the hardware filter, the closest of that and the two 8-bit filter-weight emulations, "
        "`sample --hardware-filter`), beside the error the table states.\n\n"
     << "| pass | law | scheme | stated lookup error | fetches per lookup | max \\|shader − sample\\| | within the "
        "stated error |\n|---|---|---|---|---|---|---|\n";
  for (const ShaderPass& p : r.passes)
    for (const LawLookup& l : p.laws)
      md << "| " << p.name << " | " << to_string(l.law) << " | " << l.scheme << " | " << significant(l.lookup_error)
         << " | " << l.fetches_max
         << (l.fetches_min != l.fetches_max ? " (min " + std::to_string(l.fetches_min) + ")" : "") << " | "
         << significant(l.max_difference) << " | " << (l.max_difference <= l.lookup_error ? "yes" : "**no**") << " |\n";

  md << "\n### GPU-cost targets\n\n"
     << "The targets of the tables' GPU cost, judged on this renderer"
     << (r.context.software ? " (a CPU rasterizer: its ratios are not a GPU's; a GPU's section, where one was at "
                              "hand, stands beside this one)"
                            : "")
     << ": scene shading with one fetch per law ≤ 1.5 × A and ≤ S; a scheme whose tables state ≤ 1e-4 ≤ 3 × A. "
        "Every qualifying pass is judged.\n\n"
     << "| target | pass | measured | verdict |\n|---|---|---|---|\n";
  bool one_fetch = false, accurate = false;
  for (const ShaderPass& p : r.passes) {
    if (p.laws.empty()) continue;
    const double ratio_a = median_of(p) / ma, ratio_s = median_of(p) / ms;
    const bool single =
        std::all_of(p.laws.begin(), p.laws.end(), [](const LawLookup& l) { return l.fetches_max == 1; });
    const bool fine =
        std::all_of(p.laws.begin(), p.laws.end(), [](const LawLookup& l) { return l.lookup_error <= 1e-4; });
    if (single) {
      one_fetch = true;
      md << "| one fetch per law: ≤ 1.5 × A | " << p.name << " | " << significant(ratio_a) << " × A | "
         << verdict(ratio_a <= 1.5) << " |\n"
         << "| one fetch per law: ≤ S | " << p.name << " | " << significant(ratio_s) << " × S | "
         << verdict(ratio_s <= 1.0) << " |\n";
    }
    if (fine) {
      accurate = true;
      md << "| stated ≤ 1e-4: ≤ 3 × A | " << p.name << " | " << significant(ratio_a) << " × A | "
         << verdict(ratio_a <= 3.0) << " |\n";
    }
  }
  if (!one_fetch)
    md << "| one fetch per law: ≤ 1.5 × A and ≤ S | none | no table set has one fetch per law | **missed** |\n";
  if (!accurate) md << "| stated ≤ 1e-4: ≤ 3 × A | none | no table set states ≤ 1e-4 | **missed** |\n";
  return md.str();
}

}  // namespace ganzfeld::bench
