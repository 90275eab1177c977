#include "serve/field.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "models/registry.h"
#include "rasterizer/mesh.h"
#include "rasterizer/shading.h"

namespace ganzfeld::serve {

namespace {

RequestError bad(const std::string& message) { return RequestError(400, message); }

/// A number in [lo, hi] (400 naming the parameter and the range otherwise); `fallback` when absent.
double in_range(const Query& query, const std::string& name, double lo, double hi, double fallback,
                const std::string& unit = "") {
  const double x = number(query, name).value_or(fallback);
  if (x < lo || x > hi)
    throw bad(name + "=" + format_number(x) + " is out of range; allowed: [" + format_number(lo) + ", " +
              format_number(hi) + "]" + unit);
  return x;
}

int integer_in(const Query& query, const std::string& name, int lo, int hi, int fallback) {
  const double x = in_range(query, name, lo, hi, fallback);
  if (x != std::floor(x))
    throw bad(name + "=" + format_number(x) + " is not an integer; allowed: " + std::to_string(lo) + " to " +
              std::to_string(hi));
  return static_cast<int>(x);
}

/// A direction X,Y,Z of non-zero length, normalized.
Vec3 direction_of(const std::string& name, const std::string& text) {
  std::vector<double> v;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(x)) v.clear(), at = text.size() + 1;
    else v.push_back(x), at = comma + 1;
  }
  const Vec3 d = v.size() == 3 ? Vec3{v[0], v[1], v[2]} : Vec3{0, 0, 0};
  if (!(glm::length(d) > 0.0) || !std::isfinite(glm::length(d)))
    throw bad(name + "='" + text + "' is not a direction; expected X,Y,Z, three finite numbers not all 0");
  return glm::normalize(d);
}

}  // namespace

FGridQuery parse_fgrid(const Query& query, const DataFiles& data) {
  check_names(query, "/api/fgrid", {"model", "theta", "phi", "res", "adjoint"});
  FGridQuery q;
  q.model = parse_served_model(required(query, "model", "merl:file=NAME"), Limits{}, data);
  const double theta = in_range(query, "theta", 0.0, 90.0, 45.0, " degrees") * std::numbers::pi / 180.0;
  const double phi = in_range(query, "phi", 0.0, 360.0, 180.0, " degrees") * std::numbers::pi / 180.0;
  q.fixed = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
  q.res = integer_in(query, "res", 4, 128, 32);
  const std::string adjoint = text_of(query, "adjoint").value_or("0");
  if (adjoint != "0" && adjoint != "1") throw bad("adjoint='" + adjoint + "' is not allowed; allowed: 0, 1");
  q.adjoint = adjoint == "1";
  return q;
}

nlohmann::ordered_json fgrid_json(const FGridQuery& q, const DataFiles& data) {
  const int nt = q.res, np = 2 * q.res;
  std::vector<double> values(static_cast<std::size_t>(nt) * np);
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < np; ++b) {
      const double theta = (a + 0.5) / nt * std::numbers::pi / 2, phi = (b + 0.5) / np * 2.0 * std::numbers::pi;
      const Vec3 k{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      values[static_cast<std::size_t>(a) * np + b] = q.adjoint ? q.model->f(k, q.fixed) : q.model->f(q.fixed, k);
    }
  return {{"model", data.display(q.model->spec())},
          {"res", q.res},
          {"fixed", {q.fixed.x, q.fixed.y, q.fixed.z}},
          {"adjoint", q.adjoint},
          {"values", values}};
}

SphereQuery parse_sphere(const Query& query, const DataFiles& data) {
  check_names(query, "/api/sphere", {"model", "law", "dir", "size", "along", "tol"});
  SphereQuery q;
  q.model = parse_served_model(required(query, "model", "merl:file=NAME"), Limits{}, data);
  const std::string law = required(query, "law", "f (one of f, g, h)");
  if (law != "f" && law != "g" && law != "h") throw bad("law='" + law + "' is not allowed; allowed: f, g, h");
  q.law = law == "f" ? Law::f : law == "g" ? Law::g : Law::h;
  if (q.law != Law::h) q.light = direction_of("dir", required(query, "dir", "0.5,0.5,0.7"));
  q.size = integer_in(query, "size", 8, q.law == Law::f ? kMaxSphereSide : kMaxCubatureSphereSide, 64);
  const std::string along = text_of(query, "along").value_or("latitude");
  if (along != "latitude" && along != "longitude")
    throw bad("along='" + along + "' is not allowed; allowed: latitude, longitude");
  q.tangent.latitude = along == "latitude";
  q.tolerance = in_range(query, "tol", 1e-8, 1e-2, 1e-5);
  q.key = "sphere|" + q.model->spec() + "|" + q.model->content_digest() + "|" + law + "|" + format_number(q.light.x) +
          "," + format_number(q.light.y) + "," + format_number(q.light.z) + "|" + std::to_string(q.size) + "|" + along +
          "|" + format_number(q.tolerance);
  return q;
}

nlohmann::ordered_json sphere_json(const SphereQuery& q, const DataFiles& data) {
  // The figure's camera and sphere (rasterizer/figure.cpp), one light of unit intensity.
  raster::RenderScene scene;
  scene.camera.width = scene.camera.height = q.size;
  scene.camera.eye = {0, 0, 6};
  scene.camera.fov_deg = 25.0;
  scene.camera.background = {0, 0, 0};
  scene.meshes.push_back(raster::uv_sphere({0, 0, 0}, 1.0, raster::kSphereSegments));
  scene.mesh_material = {0};
  scene.mesh_tangent = {q.tangent};
  const Light::Type type = q.law == Law::f   ? Light::Type::collimated
                           : q.law == Law::g ? Light::Type::hemispherical
                                             : Light::Type::ganzfeld;
  scene.lights = {grey_light(type, q.light, 1.0)};
  scene.materials = {
      {{1.0, {1, 1, 1}, q.model, q.law == Law::f ? nullptr : raster::direct_laws(q.model, q.tolerance)}}};
  const raster::GBuffer gb = raster::rasterize(scene.camera, scene.meshes);
  const raster::Image image = raster::shade_image(scene, gb);
  std::vector<float> value(static_cast<std::size_t>(q.size) * q.size), mask(value.size());
  for (int y = 0; y < q.size; ++y)
    for (int x = 0; x < q.size; ++x) {
      const raster::Fragment& f = gb.at(x, y);
      const std::size_t k = static_cast<std::size_t>(y) * q.size + x;
      value[k] = image.at(x, y)[0];
      mask[k] = f.mesh == raster::Fragment::kNone ? 0.0f : glm::dot(f.normal, f.view) > 0.05 ? 1.0f : 0.5f;
    }
  return {{"model", data.display(q.model->spec())},
          {"law", to_string(q.law)},
          {"width", q.size},
          {"height", q.size},
          {"value", value},
          {"mask", mask}};
}

}  // namespace ganzfeld::serve
