// rasterizer/: geometry, the three light fields of K&P against their closed forms per pixel,
// tables against the direct reference, image files.
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "models/spec.h"
#include "rasterizer/figure.h"
#include "rasterizer/image.h"
#include "rasterizer/mesh.h"
#include "rasterizer/raster.h"
#include "rasterizer/shading.h"
#include "tables/bake.h"
#include "tables/sample.h"
#include "util/error.h"

namespace ganzfeld::raster {
namespace {

namespace fs = std::filesystem;

/// Pixels are stored as float: a double radiance v in [0, 2] is rounded to within
/// 2 * 2^-24 * 0.5 ulp... i.e. |float(v) - v| <= 2^-24 |v| <= 1.2e-7 for |v| <= 2.
constexpr double kFloatRounding = 1.2e-7;
/// The pixel normal of a sphere is computed twice (by the rasterizer's refinement and by the
/// test's own ray–sphere intersection) along the same ray: both are a few double roundings
/// (~1e-15) of the same expression; 1e-12 leaves room without hiding a real difference.
constexpr double kNormalRounding = 1e-12;

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("ganzfeld_rasterizer_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

ShadingMaterial one_lobe(const std::string& spec, LawSourcePtr laws, const Rgb& color = {1, 1, 1}) {
  ShadingLobe lobe;
  lobe.model = parse_model(spec);
  lobe.laws = std::move(laws);
  lobe.color = color;
  return {lobe};
}

/// A unit sphere at the origin seen from +z, 64x64 pixels.
RenderScene sphere_scene(ShadingMaterial material, std::vector<Light> lights, double background) {
  RenderScene s;
  s.camera.width = s.camera.height = 64;
  s.camera.eye = {0, 0, 4};
  s.camera.fov_deg = 35;
  s.camera.background = {background, background, background};
  s.meshes = {uv_sphere({0, 0, 0}, 1.0, kSphereSegments)};
  s.mesh_material = {0};
  s.materials = {std::move(material)};
  s.lights = std::move(lights);
  return s;
}

/// The exact unit normal of the unit sphere at the origin along the pixel's ray, if it hits.
std::optional<Vec3> analytic_normal(const Camera& camera, int x, int y, const Vec3& center = {0, 0, 0},
                                    double radius = 1.0, double* t_hit = nullptr) {
  const Ray ray = pixel_ray(camera, x, y);
  const Vec3 oc = ray.origin - center;
  const double b = glm::dot(oc, ray.direction), c = glm::dot(oc, oc) - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return std::nullopt;
  const double t = -b - std::sqrt(disc);
  if (t_hit) *t_hit = t;
  return glm::normalize(ray.origin + t * ray.direction - center);
}

/// Checks every pixel: sphere pixels against `expected(n, j)`, background pixels equal the
/// background; every ray that hits the sphere well inside its silhouette must be covered.
template <typename Expected>
void expect_sphere_pixels(const RenderScene& scene, Expected expected, double bound) {
  const GBuffer gb = rasterize(scene.camera, scene.meshes);
  const Image image = shade_image(scene, gb);
  int covered = 0;
  double worst = 0;
  for (int y = 0; y < gb.height; ++y)
    for (int x = 0; x < gb.width; ++x) {
      const float* p = image.at(x, y);
      const std::optional<Vec3> n = analytic_normal(scene.camera, x, y);
      const Vec3 j = -pixel_ray(scene.camera, x, y).direction;
      if (gb.at(x, y).mesh == Fragment::kNone) {
        // The UV sphere (128 segments) is inscribed in the sphere; it misses only rays within
        // 1 - cos(pi/128) = 3e-4 of the silhouette, where j·n is tiny.
        if (n) { EXPECT_LT(glm::dot(*n, j), 0.05) << "uncovered sphere pixel " << x << "," << y; }
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], static_cast<float>(scene.camera.background[c]));
        continue;
      }
      ASSERT_TRUE(n) << "pixel " << x << "," << y << " covered but its ray misses the sphere";
      ++covered;
      const double want = expected(*n, j);
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(p[c] - want));
        EXPECT_NEAR(p[c], want, bound) << "pixel " << x << "," << y;
      }
    }
  EXPECT_GT(covered, 1000);  // the sphere fills most of the 64x64 frame
  ::testing::Test::RecordProperty("max_abs_error", text(worst));
}

// --- the three light fields ----------------------------------------------------------------

TEST(Rasterizer, WhiteLambertSphereIsInvisibleInGanzfeld) {
  // K&P: h_L = 1, so a white Lambertian sphere in a Ganzfeld of radiance N has radiance N
  // everywhere, which is the radiance of the Ganzfeld seen behind it. h is integrated per pixel
  // (not the closed form h = 1, which would only test that N x 1 = N): the bound is N times the
  // cubature tolerance plus float rounding.
  constexpr double N = 0.6, kTol = 1e-10;
  const RenderScene scene = sphere_scene(one_lobe("lambert", direct_laws(parse_model("lambert"), kTol)),
                                         {grey_light(Light::Type::ganzfeld, {0, 1, 0}, N)}, N);
  expect_sphere_pixels(
      scene, [](const Vec3&, const Vec3&) { return N; }, N * kTol + kFloatRounding);
}

TEST(Rasterizer, WhiteLambertSphereFromTableIsInvisibleInGanzfeld) {
  // The same through a baked h table: the bound is N times the table's stored max error (its
  // interpolation error is 0: h_L = 1 is constant) plus float rounding.
  constexpr double N = 0.6;
  tables::BakeOptions options;
  options.resolution = {16};
  options.tolerance = 1e-10;
  auto h = std::make_shared<const tables::Table>(tables::bake(*parse_model("lambert"), Law::h, options));
  const RenderScene scene =
      sphere_scene(one_lobe("lambert", table_laws(nullptr, h)), {grey_light(Light::Type::ganzfeld, {0, 1, 0}, N)}, N);
  expect_sphere_pixels(
      scene, [](const Vec3&, const Vec3&) { return N; }, N * h->node_error + kFloatRounding);
}

TEST(Rasterizer, WhiteHvdEmpiricalSphereIsInvisibleInGanzfeld) {
  // Edwards et al., Figure 2: with C_d = 1 the empirical HVD BRDF conserves energy over incident
  // directions for every viewing direction, so h = 1 and the sphere vanishes in a Ganzfeld, like
  // white Lambert, although its lobes are sharp and it is not reciprocal (its albedo a != 1).
  // Through an h table baked from the law of darkening itself (never from a): the bound is N times
  // the table's stored node error; the table is constant (1) between nodes except in its first
  // cell, j·n < 6e-5, where the specular lump degenerates to a delta (h(horizon) = 1 - F = 0) —
  // which no pixel of this sphere reaches (checked).
  constexpr double N = 0.6;
  tables::BakeOptions options;
  options.resolution = {128};
  options.tolerance = 1e-8;
  const ModelPtr model = parse_model("hvd-empirical:cd=1,f0=0.04,k=0.3,ns=100,nr=10");
  auto h = std::make_shared<const tables::Table>(tables::bake(*model, Law::h, options));
  // Node 1 sits at j·n = 6.2e-5 (89.996°), where the specular lump is an arc 1e-4 by 1e-8 rad:
  // the engine may report it not converged within its budget (it used to return 0.96 ± 1e-8
  // there, before horizon grading; its estimate is not honest yet: 3.7e-8 off against 1.2e-8).
  // Every other node converges and holds h = 1 within its stored error. With the null-rule estimate
  // (integrate/cubature.h) the next node towards the horizon may be declined as well: an honest
  // "not converged" whose achieved error is stored, never one above j·n = 1e-3.
  EXPECT_LE(h->unconverged, 2);
  for (std::size_t k = 0; k < h->value.size(); ++k) {
    if (h->error[k] > 2 * options.tolerance) {
      EXPECT_LT(h->axes[0].node(k), 1e-3) << "node " << k << " not converged";
    }
  }
  for (std::size_t k = 2; k < h->value.size(); ++k)
    EXPECT_LE(std::abs(h->value[k] - 1.0), h->error[k]) << "node " << k << ", j·n = " << h->axes[0].node(k);
  const double first_node = h->axes[0].node(1);
  ShadingMaterial material = one_lobe("lambert", table_laws(nullptr, h));
  material[0].model = model;
  const RenderScene scene = sphere_scene(material, {grey_light(Light::Type::ganzfeld, {0, 1, 0}, N)}, N);
  const GBuffer gb = rasterize(scene.camera, scene.meshes);
  for (const Fragment& f : gb.pixels)
    if (f.mesh != Fragment::kNone) { ASSERT_GT(glm::dot(f.normal, f.view), first_node); }
  expect_sphere_pixels(
      scene, [](const Vec3&, const Vec3&) { return N; }, N * h->node_error + kFloatRounding);
}

TEST(Rasterizer, LambertSphereUnderSkyIsHalfOnePlusCos) {
  // K&P: g_L = (1 + i·n)/2 with i the sky's pole, per pixel with n from the exact sphere.
  // Bound: the closed form is exact; float storage and the normal's rounding remain.
  const Vec3 pole = glm::normalize(Vec3{0.3, 0.8, 0.4});
  const RenderScene scene =
      sphere_scene(one_lobe("lambert", lambert_laws()), {grey_light(Light::Type::hemispherical, pole, 1.0)}, 0.0);
  expect_sphere_pixels(
      scene, [&](const Vec3& n, const Vec3&) { return 0.5 * (1.0 + glm::dot(pole, n)); },
      kFloatRounding + kNormalRounding);
}

TEST(Rasterizer, MinnaertSphereInGanzfeldShowsDarkening) {
  // K&P: h_d = (j·n)^xi; xi = 1. Direct cubature at tolerance 1e-10 (its error estimate bounds
  // the true error: integrate/cubature.h) plus float rounding.
  constexpr double kTol = 1e-10;
  const RenderScene scene = sphere_scene(one_lobe("minnaert:xi=1", direct_laws(parse_model("minnaert:xi=1"), kTol)),
                                         {grey_light(Light::Type::ganzfeld, {0, 1, 0}, 1.0)}, 0.0);
  expect_sphere_pixels(
      scene, [](const Vec3& n, const Vec3& j) { return std::max(glm::dot(n, j), 0.0); },
      kTol + kFloatRounding + kNormalRounding);
}

TEST(Rasterizer, MinnaertSphereFromTableWithinInterpolationBound) {
  // h table of 64 nodes, sqrt mapping: mu = u^2 in the index coordinate u, so linear
  // interpolation of h = mu between nodes Δu = 1/63 apart errs by at most Δu^2/8 max|d²h/du²|
  // = Δu^2/4. Plus the stored error and float rounding.
  const ModelPtr model = parse_model("minnaert:xi=1");
  tables::BakeOptions options;
  options.resolution = {64};
  options.tolerance = 1e-10;
  auto h = std::make_shared<const tables::Table>(tables::bake(*model, Law::h, options));
  const double du = 1.0 / 63;
  const RenderScene scene = sphere_scene(one_lobe("minnaert:xi=1", table_laws(nullptr, h)),
                                         {grey_light(Light::Type::ganzfeld, {0, 1, 0}, 1.0)}, 0.0);
  expect_sphere_pixels(
      scene, [](const Vec3& n, const Vec3& j) { return std::max(glm::dot(n, j), 0.0); },
      du * du / 4 + h->node_error + kFloatRounding + kNormalRounding);
}

TEST(Rasterizer, CollimatedLambertIsCosineOverPi) {
  // H0 (i·n) f_L with f_L = 1/pi; 0 in the body shadow.
  const Vec3 i = glm::normalize(Vec3{1, 1, 1});
  const RenderScene scene = sphere_scene(one_lobe("lambert", lambert_laws()),
                                         {grey_light(Light::Type::collimated, i, std::numbers::pi)}, 0.0);
  expect_sphere_pixels(
      scene, [&](const Vec3& n, const Vec3& j) { return glm::dot(n, j) > 0 ? std::max(glm::dot(i, n), 0.0) : 0.0; },
      kFloatRounding + kNormalRounding);
}

TEST(Rasterizer, TangentFrameIsOrthonormal) {
  for (const Vec3& n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, glm::normalize(Vec3{1, -2, 0.1}), Vec3{1, 0, 0}}) {
    const TangentFrame f(n);
    EXPECT_NEAR(glm::dot(f.t, f.b), 0, 1e-15);
    EXPECT_NEAR(glm::dot(f.t, n), 0, 1e-15);
    EXPECT_NEAR(glm::dot(f.b, n), 0, 1e-15);
    EXPECT_NEAR(glm::length(f.t), 1, 1e-15);
    EXPECT_NEAR(glm::length(f.b), 1, 1e-15);
    EXPECT_NEAR(f.local(n).z, 1, 1e-15);
  }
}

// --- tables against the direct reference ---------------------------------------------------

/// Interpolation error bound of a multilinear table: for f in C², linear interpolation on a
/// cell of width h errs by at most h²/8 max|f''|, and h² f'' is estimated by the second
/// difference of neighbouring nodes (exact for quadratics). Multilinear interpolation is linear
/// interpolation along each axis in turn, each a convex combination, so the errors add over
/// the axes. kSafety covers f'' varying within a cell beyond what the second difference sees.
double interpolation_bound(const tables::Table& t) {
  constexpr double kSafety = 2.0;
  const std::size_t dims = t.axes.size();
  const std::vector<std::size_t> stride = tables::axis_strides(t.axes);
  double total = 0;
  for (std::size_t d = 0; d < dims; ++d) {
    double worst = 0;
    for (std::size_t m = 0; m < t.value.size(); ++m) {
      const std::size_t k = (m / stride[d]) % t.axes[d].count;
      if (k == 0 || k + 1 == static_cast<std::size_t>(t.axes[d].count)) continue;
      worst = std::max(worst, std::abs(t.value[m - stride[d]] - 2.0 * t.value[m] + t.value[m + stride[d]]));
    }
    total += worst / 8;
  }
  return kSafety * total;
}

TEST(Rasterizer, TablesAgreeWithDirectWithinTableErrorPlusInterpolation) {
  // specular:alpha=8 under a sky (N_s) and a Ganzfeld (N_g), 48x48. Per pixel
  //   |tables - direct| <= N_s (max_error_g + interp_g) + N_g (max_error_h + interp_h)
  //                        + (N_s + N_g) tol_direct + float rounding.
  const std::string spec = "specular:alpha=8";
  const ModelPtr model = parse_model(spec);
  constexpr double kTableTol = 1e-7, kDirectTol = 1e-8, Ns = 0.7, Ng = 0.5;
  tables::BakeOptions g_options, h_options;
  g_options.resolution = {24, 24, 16};
  g_options.tolerance = kTableTol;
  h_options.resolution = {64};
  h_options.tolerance = kTableTol;
  auto g = std::make_shared<const tables::Table>(tables::bake(*model, Law::g, g_options));
  auto h = std::make_shared<const tables::Table>(tables::bake(*model, Law::h, h_options));
  const double bound = Ns * (g->node_error + interpolation_bound(*g)) + Ng * (h->node_error + interpolation_bound(*h)) +
                       (Ns + Ng) * kDirectTol + kFloatRounding;
  const std::vector<Light> lights{grey_light(Light::Type::hemispherical, glm::normalize(Vec3{0.2, 1, 0.3}), Ns),
                                  grey_light(Light::Type::ganzfeld, {0, 1, 0}, Ng)};
  RenderScene tables = sphere_scene(one_lobe(spec, table_laws(g, h)), lights, 0.0);
  RenderScene direct = sphere_scene(one_lobe(spec, direct_laws(model, kDirectTol)), lights, 0.0);
  tables.camera.width = tables.camera.height = direct.camera.width = direct.camera.height = 48;
  const Image a = render(tables), b = render(direct);
  double worst = 0;
  for (std::size_t k = 0; k < a.rgb.size(); ++k)
    worst = std::max(worst, static_cast<double>(std::abs(a.rgb[k] - b.rgb[k])));
  RecordProperty("bound", text(bound));
  RecordProperty("max_abs_difference", text(worst));
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.0);   // the two sources really differ: the comparison is not vacuous
  EXPECT_LT(bound, 0.02);  // and the bound is tight enough to mean something
}

// --- geometry --------------------------------------------------------------------------------

TEST(Rasterizer, NearerSphereWinsWhateverTheOrder) {
  const Vec3 ca{0, 0, 0}, cb{0.7, 0.2, 1.5};
  const double ra = 1.0, rb = 0.6;
  for (bool swap : {false, true}) {
    RenderScene s = sphere_scene(one_lobe("lambert", lambert_laws()), {}, 0);
    s.meshes = {uv_sphere(ca, ra, kSphereSegments), uv_sphere(cb, rb, kSphereSegments)};
    if (swap) std::swap(s.meshes[0], s.meshes[1]);
    const std::uint32_t a_index = swap ? 1 : 0, b_index = swap ? 0 : 1;
    const GBuffer gb = rasterize(s.camera, s.meshes);
    int both = 0;
    for (int y = 0; y < gb.height; ++y)
      for (int x = 0; x < gb.width; ++x) {
        double ta = 0, tb = 0;
        const bool hit_a = analytic_normal(s.camera, x, y, ca, ra, &ta).has_value();
        const bool hit_b = analytic_normal(s.camera, x, y, cb, rb, &tb).has_value();
        const std::uint32_t got = gb.at(x, y).mesh;
        if (hit_a && hit_b && got != Fragment::kNone) {
          ++both;
          EXPECT_EQ(got, tb < ta ? b_index : a_index) << x << "," << y;
        }
        if (got == a_index) { EXPECT_TRUE(hit_a); }
        if (got == b_index) { EXPECT_TRUE(hit_b); }
      }
    EXPECT_GT(both, 100);  // the spheres overlap on screen
  }
}

TEST(Rasterizer, InterpolationIsPerspectiveCorrect) {
  // A large tilted quad: the interpolated world position must lie on the pixel's ray (affine
  // screen-space interpolation would not), and its normal is the quad's.
  Mesh quad;
  quad.positions = {{-3, -1, -6}, {3, -1, -6}, {3, -1, 2}, {-3, -1, 2}};
  quad.normals.assign(4, Vec3{0, 1, 0});
  quad.triangles = {{0, 2, 1}, {0, 3, 2}};
  Camera camera;
  camera.width = camera.height = 40;
  camera.eye = {0, 0.5, 3};
  camera.fov_deg = 60;
  const GBuffer gb = rasterize(camera, {quad});
  int covered = 0;
  for (int y = 0; y < gb.height; ++y)
    for (int x = 0; x < gb.width; ++x) {
      const Fragment& f = gb.at(x, y);
      if (f.mesh == Fragment::kNone) continue;
      ++covered;
      const Ray ray = pixel_ray(camera, x, y);
      const Vec3 d = f.position - ray.origin;
      EXPECT_LT(glm::length(glm::cross(d, ray.direction)) / glm::length(d), 1e-12);
      EXPECT_NEAR(f.position.y, -1.0, 1e-12);
      EXPECT_NEAR(f.normal.y, 1.0, 1e-15);
    }
  EXPECT_GT(covered, 200);
}

TEST(Rasterizer, DeterministicForAnyThreadCount) {
  const RenderScene scene = sphere_scene(one_lobe("specular:alpha=8", lambert_laws()),
                                         {grey_light(Light::Type::collimated, {1, 1, 1}, 3.0)}, 0.1);
  Image one, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = render(scene);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    many = render(scene);
  }
  EXPECT_EQ(one.rgb, many.rgb);
}

TEST(Rasterizer, RefusesZeroSizeImage) {
  Camera camera;
  camera.width = 0;
  EXPECT_THROW(rasterize(camera, {}), InputError);
  camera.width = 10;
  camera.height = -1;
  EXPECT_THROW(rasterize(camera, {}), InputError);
  EXPECT_THROW(Image(0, 10), InputError);
  TempDir dir;
  EXPECT_THROW(write_image(Image{}, (dir.path / "empty.png").string()), InputError);
  EXPECT_FALSE(fs::exists(dir.path / "empty.png"));
}

// --- meshes ----------------------------------------------------------------------------------

TEST(Rasterizer, UvSphereIsInscribedWithRadialNormals) {
  const Mesh m = uv_sphere({1, 2, 3}, 2.0, 16);
  ASSERT_EQ(m.positions.size(), m.normals.size());
  for (std::size_t k = 0; k < m.positions.size(); ++k) {
    EXPECT_NEAR(glm::length(m.positions[k] - Vec3{1, 2, 3}), 2.0, 1e-12);
    EXPECT_NEAR(glm::length(m.normals[k] - (m.positions[k] - Vec3{1, 2, 3}) / 2.0), 0.0, 1e-12);
  }
  EXPECT_THROW(uv_sphere({0, 0, 0}, 0.0, 16), InputError);
  EXPECT_THROW(uv_sphere({0, 0, 0}, 1.0, 2), InputError);
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

TEST(Rasterizer, LoadsObjCubeWithNormals) {
  TempDir dir;
  const fs::path path = dir.path / "cube.obj";
  write_text(path,
             "# unit cube, quads, v//vn\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 2 0 0\n"
             "vt 0 0\n"
             "f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1//3 2//3 6//3 5//3\n"
             "f 4/1/4 8/1/4 7/1/4 3/1/4\nf 1//5 5//5 8//5 4//5\nf -7//-1 -6//-1 -2//-1 -5//-1\n");
  const Mesh m = load_obj(path.string());
  EXPECT_EQ(m.triangles.size(), 12u);  // 6 quads, fan-triangulated
  EXPECT_EQ(m.positions.size(), 24u);  // one vertex per (position, normal) pair
  for (const Vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0, 1e-15);
  // Rendered from outside, the cube is visible.
  Camera camera;
  camera.width = camera.height = 32;
  camera.eye = {3, 2.5, 4};
  camera.target = {0.5, 0.5, 0.5};
  const GBuffer gb = rasterize(camera, {m});
  EXPECT_NE(gb.at(16, 16).mesh, Fragment::kNone);
}

TEST(Rasterizer, LoadsObjTetrahedronWithoutNormals) {
  TempDir dir;
  const fs::path path = dir.path / "tet.obj";
  write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2/1 3/1 4/1\n");
  const Mesh m = load_obj(path.string());
  ASSERT_EQ(m.triangles.size(), 4u);
  ASSERT_EQ(m.normals.size(), 4u);
  const Vec3 centroid{0.25, 0.25, 0.25};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(glm::length(m.normals[k]), 1.0, 1e-15);
    EXPECT_GT(glm::dot(m.normals[k], m.positions[k] - centroid), 0.0);  // outward: faces wound outward
  }
}

TEST(Rasterizer, RefusesMissingAndMalformedObj) {
  TempDir dir;
  auto message = [&](const std::string& name, const std::string& text) -> std::string {
    const fs::path path = dir.path / name;
    if (!text.empty()) write_text(path, text);
    try {
      load_obj(path.string());
    } catch (const InputError& e) { return e.what(); }
    return "no error";
  };
  const std::string missing = message("missing.obj", "");
  EXPECT_NE(missing.find("missing.obj"), std::string::npos) << missing;
  const std::string cases[][3] = {
      {"short_v.obj", "v 0 0 0\nv 1 0\n", "line 2"},
      {"few_corners.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "line 4"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "line 5"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4"},
      {"word.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "line 4"},
      {"bad_normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n", "line 5"},
      {"no_faces.obj", "v 0 0 0\n", "no faces"},
  };
  for (const auto& c : cases) {
    const std::string m = message(c[0], c[1]);
    EXPECT_NE(m.find(c[0]), std::string::npos) << m;
    EXPECT_NE(m.find(c[2]), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// --- images ----------------------------------------------------------------------------------

TEST(Rasterizer, WritesAndReadsExrAndPng) {
  TempDir dir;
  Image image(5, 3);
  for (std::size_t k = 0; k < image.rgb.size(); ++k) image.rgb[k] = static_cast<float>(k) / 20.0f;  // some > 1
  write_image(image, (dir.path / "a.exr").string());
  EXPECT_EQ(read_image((dir.path / "a.exr").string()).rgb, image.rgb);  // linear floats, exactly
  write_image(image, (dir.path / "a.PNG").string());
  const Image png = read_image((dir.path / "a.PNG").string());
  for (std::size_t k = 0; k < image.rgb.size(); ++k) {
    // 8-bit sRGB of the linear value clamped to [0, 1].
    EXPECT_EQ(srgb_byte(png.rgb[k]), srgb_byte(image.rgb[k]));
  }
  EXPECT_EQ(srgb_byte(0.0), 0);
  EXPECT_EQ(srgb_byte(1.0), 255);
  EXPECT_EQ(srgb_byte(7.0), 255);
  EXPECT_EQ(srgb_byte(0.21586), 128);  // ((128/255 + 0.055)/1.055)^2.4
}

TEST(Rasterizer, RefusesBadOutputAndLeavesNoFile) {
  TempDir dir;
  const Image image(4, 4, {0.5, 0.5, 0.5});
  auto leftovers = [&] { return std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}); };
  EXPECT_THROW(write_image(image, (dir.path / "a.bmp").string()), InputError);
  EXPECT_THROW(write_image(image, (dir.path / "no_such_dir" / "a.png").string()), InputError);
  // A file where a directory is expected.
  write_text(dir.path / "file", "x");
  EXPECT_THROW(write_image(image, (dir.path / "file" / "a.exr").string()), InputError);
  EXPECT_EQ(leftovers(), 1);
  // The target is an existing directory: the rename fails after the temporary file was written;
  // it must be gone.
  fs::create_directory(dir.path / "taken.png");
  write_text(dir.path / "taken.png" / "keep", "x");
  EXPECT_THROW(write_image(image, (dir.path / "taken.png").string()), InputError);
  EXPECT_EQ(leftovers(), 2);  // "file" and "taken.png", no temporary
}

// --- a prepared material: lobes' tables summed -------------------------------------------------

/// A material's radiance summed lobe by lobe, light by light, from tables::sample (what shade()
/// computed before materials were prepared: rasterizer/shading.h).
Rgb lobe_by_lobe(const ShadingMaterial& material, const std::vector<Light>& lights, const Vec3& n,
                 const Vec3& j_world) {
  const TangentFrame frame(n);
  const Vec3 j = frame.local(j_world);
  Vec3 jc = j;
  if (jc.z < 0.0) jc = glm::normalize(Vec3{j.x, j.y, 0.0});
  Rgb out{0, 0, 0};
  for (const Light& light : lights) {
    const Vec3 i = frame.local(glm::normalize(light.direction));
    for (const ShadingLobe& lobe : material) {
      double value = 0.0;
      if (light.type == Light::Type::collimated) value = i.z > 0.0 && j.z > 0.0 ? i.z * lobe.model->f(i, j) : 0.0;
      else if (light.type == Light::Type::hemispherical) value = lobe.laws->g(i, jc);
      else value = lobe.laws->h(jc);
      for (int c = 0; c < 3; ++c) out[c] += lobe.weight * lobe.color[c] * light.intensity[c] * value;
    }
  }
  return out;
}

// Two lobes whose tables share a lookup are looked up once from their summed entries; a third
// with other axes, a Lambert lobe and a direct lobe are added apart. The laws are linear, so the
// sum equals the lobes' own lookups summed, up to double rounding of the sums (kSumRounding).
TEST(Rasterizer, PreparedMaterialSumsTheTablesOfLobesThatShareALookup) {
  constexpr double kSumRounding = 1e-13;  // ~10 roundings of 2^-53 on radiances of order 1
  auto table = [](const char* spec, Law law, std::vector<int> resolution) {
    tables::BakeOptions options;
    options.resolution = std::move(resolution);
    options.tolerance = 1e-5;
    return std::make_shared<const tables::Table>(tables::bake(*parse_model(spec), law, options));
  };
  ShadingMaterial material;
  auto add = [&](const char* spec, double weight, const Rgb& color, LawSourcePtr laws) {
    material.push_back({weight, color, parse_model(spec), std::move(laws)});
  };
  add("minnaert:xi=1", 0.4, {0.2, 0.4, 0.8},
      table_laws(table("minnaert:xi=1", Law::g, {9, 9, 5}), table("minnaert:xi=1", Law::h, {17})));
  add("specular:alpha=8", 0.3, {1, 0.9, 0.8},
      table_laws(table("specular:alpha=8", Law::g, {9, 9, 5}), table("specular:alpha=8", Law::h, {17})));
  add("asperity:alpha=4", 0.1, {0.5, 0.1, 0.1},
      table_laws(table("asperity:alpha=4", Law::g, {7, 9, 5}), table("asperity:alpha=4", Law::h, {13})));
  add("lambert", 0.1, {0.3, 0.3, 0.3}, lambert_laws());
  add("backscatter:alpha=2", 0.1, {0.9, 0.9, 0.7}, direct_laws(parse_model("backscatter:alpha=2"), 1e-6));
  const std::vector<Light> lights{grey_light(Light::Type::collimated, {1, 1, 1}, 1.0),
                                  {Light::Type::hemispherical, {0.2, 0.9, 0.4}, {0.3, 0.5, 0.7}},
                                  {Light::Type::hemispherical, {-0.5, 0.1, -0.3}, {0.2, 0.2, 0.1}},
                                  {Light::Type::ganzfeld, {0, 0, 1}, {0.1, 0.2, 0.3}}};
  const MaterialShader shader(material, lights);
  for (const auto& light : shader.lights())
    if (light.type != Light::Type::collimated) {
      EXPECT_EQ(light.tables.size(), 2u) << "minnaert and specular share one lookup, asperity has its own";
      EXPECT_EQ(light.lobes.size(), 2u) << "lambert and the direct lobe are evaluated apart";
    }
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double largest = 0.0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 n = glm::normalize(Vec3{unit(random), unit(random), unit(random)});
    Vec3 j = glm::normalize(Vec3{unit(random), unit(random), unit(random)});
    if (k % 10 == 0) j = glm::normalize(j - (glm::dot(j, n) + 0.01) * n);  // just below the horizon
    const Rgb expected = lobe_by_lobe(material, lights, n, j), got = shader.radiance(n, j, TangentFrame(n).t);
    for (int c = 0; c < 3; ++c) {
      largest = std::max(largest, std::abs(got[c] - expected[c]));
      EXPECT_NEAR(got[c], expected[c], kSumRounding * (1.0 + std::abs(expected[c])))
          << "point " << k << " channel " << c;
    }
  }
  std::printf("prepared material against lobe by lobe: max difference %.3g\n", largest);
}

// --- the figure ------------------------------------------------------------------------------

TEST(Rasterizer, PanelHasFourQuadrantsAndLambertIsInvisibleInGanzfeld) {
  FigureOptions options;
  options.size = 48;
  const Image panel = koenderink_pont_panel("lambert", options);
  const int gap = figure_gap(48);
  ASSERT_EQ(panel.width, 2 * 48 + gap);
  // Bottom-right quadrant: a white Lambertian sphere in the Ganzfeld equals the background.
  for (int y = 48 + gap; y < panel.height; ++y)
    for (int x = 48 + gap; x < panel.width; ++x) EXPECT_EQ(panel.at(x, y)[0], static_cast<float>(kFieldRadiance));
  // Top-right: lit from the upper right, so the upper-right of the sphere is brighter.
  const float upper_right = panel.at(48 + gap + 30, 17)[0], lower_left = panel.at(48 + gap + 17, 30)[0];
  EXPECT_GT(upper_right, lower_left);
  EXPECT_THROW(koenderink_pont_panel("lambert:xi=1", options), InputError);
}

}  // namespace
}  // namespace ganzfeld::raster
