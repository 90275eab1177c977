// The scene file (examples/default.json), parsed with nlohmann-json and validated at the boundary:
// every refusal is one line "scene 'FILE': KEY.PATH = VALUE ...; allowed: ...".
// Unknown keys are errors (Mitsuba's habit); missing optional keys take the defaults of
// scene/scene.h; a present key of the wrong type is an error, never a silent default.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "scene/json_file.h"
#include "util/error.h"

namespace ganzfeld {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;  // keeps the file's order of materials

/// Longest excerpt of a bad value quoted in a message.
constexpr std::size_t kMaxQuoted = 60;
/// Camera limits (scene/scene.h): image sides in pixels, vertical field of view in degrees.
constexpr long long kMaxImageSide = 16384;
constexpr double kMaxFovDeg = 180.0;

std::string one_line(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return text;
}

std::string quote(const Json& value) {
  std::string text = value.dump();
  if (text.size() > kMaxQuoted) text = text.substr(0, kMaxQuoted - 3) + "...";
  return text;
}

std::string join(std::initializer_list<const char*> names) {
  std::string s;
  for (const char* n : names) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

class Parser {
 public:
  explicit Parser(std::string path, std::optional<std::string> text = std::nullopt)
      : path_(std::move(path)), text_(std::move(text)) {}

  Scene parse() {
    const Json doc = read_json();
    if (!doc.is_object()) fail("", doc, "the scene must be a JSON object with keys camera, materials, objects, lights");
    check_keys(doc, "", {"camera", "materials", "objects", "lights"});
    Scene scene;
    if (doc.contains("camera")) scene.camera = camera(doc["camera"], "camera");
    std::map<std::string, std::size_t> by_name;
    if (doc.contains("materials")) {
      const Json& materials = doc["materials"];
      if (!materials.is_object())
        fail("materials", materials, "expected an object mapping material names to materials");
      for (const auto& [name, value] : materials.items()) {
        by_name[name] = scene.materials.size();
        scene.materials.push_back(material(name, value, "materials." + name));
      }
    }
    if (doc.contains("objects")) {
      const Json& objects = doc["objects"];
      if (!objects.is_array()) fail("objects", objects, "expected an array of objects");
      for (std::size_t k = 0; k < objects.size(); ++k)
        scene.objects.push_back(object(objects[k], "objects[" + std::to_string(k) + "]", by_name));
    }
    if (doc.contains("lights")) {
      const Json& lights = doc["lights"];
      if (!lights.is_array()) fail("lights", lights, "expected an array of lights");
      for (std::size_t k = 0; k < lights.size(); ++k)
        scene.lights.push_back(light(lights[k], "lights[" + std::to_string(k) + "]"));
    }
    return scene;
  }

 private:
  std::string path_;
  std::optional<std::string> text_;  ///< the file's text when parsed from memory

  [[noreturn]] void refuse(const std::string& why) const {
    throw InputError("scene '" + path_ + "': " + one_line(why));
  }
  [[noreturn]] void fail(const std::string& key, const Json& value, const std::string& allowed) const {
    refuse((key.empty() ? std::string("top level") : key) + " = " + quote(value) + " is not allowed; " + allowed);
  }

  Json read_json() const { return scene::read_json_file("scene", path_, text_); }

  void check_keys(const Json& object, const std::string& where, std::initializer_list<const char*> allowed) const {
    for (const auto& item : object.items()) {
      const std::string& key = item.key();  // not a structured binding: clang < 16 cannot capture those
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }))
        refuse((where.empty() ? "unknown top-level key '" : "unknown key '" + where + ".") + key +
               "'; allowed: " + join(allowed));
    }
  }

  double number(const Json& value, const std::string& key) const {
    if (!value.is_number()) fail(key, value, "expected a number");
    return value.get<double>();
  }

  double non_negative(const Json& value, const std::string& key) const {
    const double x = number(value, key);
    if (!std::isfinite(x) || x < 0.0) fail(key, value, "expected a finite number >= 0");
    return x;
  }

  Vec3 point(const Json& value, const std::string& key) const {
    if (!value.is_array() || value.size() != 3 || !std::all_of(value.begin(), value.end(), [](const Json& v) {
          return v.is_number() && std::isfinite(v.get<double>());
        }))
      fail(key, value, "expected [x, y, z], three finite numbers");
    return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
  }

  /// A direction: three finite numbers, not all zero; returned normalized.
  Vec3 direction(const Json& value, const std::string& key) const {
    const Vec3 v = point(value, key);
    const double length = glm::length(v);
    if (!(length > 0.0) || !std::isfinite(length))
      fail(key, value, "expected a direction [x, y, z] of non-zero length");
    return v / length;
  }

  /// An RGB triple of finite numbers >= 0; a single number stands for grey.
  Rgb rgb(const Json& value, const std::string& key) const {
    const std::string allowed = "expected [r, g, b] (or one number for grey), finite and >= 0";
    if (value.is_number()) {
      const double x = value.get<double>();
      if (!std::isfinite(x) || x < 0.0) fail(key, value, allowed);
      return {x, x, x};
    }
    if (!value.is_array() || value.size() != 3) fail(key, value, allowed);
    Rgb out{};
    for (std::size_t c = 0; c < 3; ++c) {
      const Json& v = value[c];
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0)
        fail(key + "[" + std::to_string(c) + "]", v, allowed);
      out[c] = v.get<double>();
    }
    return out;
  }

  const Json& object_at(const Json& value, const std::string& key, const std::string& what) const {
    if (!value.is_object()) fail(key, value, "expected " + what);
    return value;
  }

  Camera camera(const Json& value, const std::string& key) const {
    object_at(value, key, "an object with width, height, eye, target, up, fov_deg, background");
    check_keys(value, key, {"width", "height", "eye", "target", "up", "fov_deg", "background"});
    Camera c;
    auto side = [&](const char* name, int& out) {
      if (!value.contains(name)) return;
      const Json& v = value[name];
      const std::string k = key + "." + name;
      const std::string allowed = "expected an integer in [1, " + std::to_string(kMaxImageSide) + "]";
      if (!v.is_number_integer()) fail(k, v, allowed);
      const long long n =
          v.is_number_unsigned()
              ? static_cast<long long>(std::min<std::uint64_t>(v.get<std::uint64_t>(), kMaxImageSide + 1))
              : v.get<long long>();
      if (n < 1 || n > kMaxImageSide) fail(k, v, allowed);
      out = static_cast<int>(n);
    };
    side("width", c.width);
    side("height", c.height);
    if (value.contains("eye")) c.eye = point(value["eye"], key + ".eye");
    if (value.contains("target")) c.target = point(value["target"], key + ".target");
    if (value.contains("up")) c.up = direction(value["up"], key + ".up");
    if (value.contains("fov_deg")) {
      c.fov_deg = number(value["fov_deg"], key + ".fov_deg");
      if (!(c.fov_deg > 0.0 && c.fov_deg < kMaxFovDeg))
        fail(key + ".fov_deg", value["fov_deg"], "expected degrees in (0, 180), exclusive");
    }
    if (value.contains("background")) c.background = rgb(value["background"], key + ".background");
    const Vec3 view = c.target - c.eye;
    if (!(glm::length(view) > 0.0))
      refuse(key + ".eye and " + key + ".target are the same point; the camera needs a view direction");
    if (!(glm::length(glm::cross(glm::normalize(view), glm::normalize(c.up))) > 1e-9))
      refuse(key + ".up is parallel to the view direction (target - eye); allowed: any other direction");
    return c;
  }

  /// Appends the lobes of `spec` (a single model or a partitive mixture) with weight `weight`
  /// and colour `color`: a mixture's normalized weights multiply `weight`.
  void add_lobes(Material& m, const Json& spec, double weight, const Rgb& color, const std::string& key) const {
    if (!spec.is_string()) fail(key, spec, "expected a model spec string, e.g. \"specular:alpha=8\"");
    std::vector<Lobe> lobes;
    try {
      lobes = parse_lobes(spec.get<std::string>());
    } catch (const InputError& e) { refuse(key + " = " + quote(spec) + ": " + e.what()); }
    for (const Lobe& lobe : lobes) {
      MaterialLobe out;
      out.weight = weight * lobe.weight;
      out.model = lobe.model;
      out.spec = lobe.model->spec();
      out.color = color;
      m.lobes.push_back(std::move(out));
    }
  }

  Material material(const std::string& name, const Json& value, const std::string& key) const {
    object_at(value, key, "an object {\"model\": SPEC, \"color\": [r, g, b]} or {\"lobes\": [...]}");
    Material m;
    m.name = name;
    const bool has_model = value.contains("model"), has_lobes = value.contains("lobes");
    if (has_model == has_lobes)
      refuse(key +
             " needs exactly one of \"model\" (a spec, with optional \"color\") or \"lobes\" (a list of "
             "{weight, model, color})");
    if (has_model) {
      check_keys(value, key, {"model", "color"});
      const Rgb color = value.contains("color") ? rgb(value["color"], key + ".color") : Rgb{1, 1, 1};
      add_lobes(m, value["model"], 1.0, color, key + ".model");
    } else {
      check_keys(value, key, {"lobes"});
      const Json& lobes = value["lobes"];
      if (!lobes.is_array() || lobes.empty())
        fail(key + ".lobes", lobes, "expected a non-empty array of {\"weight\", \"model\", \"color\"}");
      for (std::size_t k = 0; k < lobes.size(); ++k) {
        const std::string lkey = key + ".lobes[" + std::to_string(k) + "]";
        const Json& lobe = lobes[k];
        object_at(lobe, lkey, "an object {\"weight\": W, \"model\": SPEC, \"color\": [r, g, b]}");
        check_keys(lobe, lkey, {"weight", "model", "color"});
        if (!lobe.contains("model")) refuse(lkey + " has no \"model\"; expected a model spec, e.g. \"lambert\"");
        double weight = 1.0;
        if (lobe.contains("weight")) {
          weight = number(lobe["weight"], lkey + ".weight");
          if (!std::isfinite(weight) || weight <= 0.0)
            fail(lkey + ".weight", lobe["weight"], "expected a finite number > 0");
        }
        const Rgb color = lobe.contains("color") ? rgb(lobe["color"], lkey + ".color") : Rgb{1, 1, 1};
        add_lobes(m, lobe["model"], weight, color, lkey + ".model");
      }
    }
    // Partitive mixture (K&P): the weights of a material sum to 1.
    double total = 0.0;
    for (const MaterialLobe& l : m.lobes) total += l.weight;
    if (!(total > 0.0) || !std::isfinite(total))
      refuse(key + ": the lobe weights do not sum to a finite positive number");
    for (MaterialLobe& l : m.lobes) l.weight /= total;
    return m;
  }

  SceneObject object(const Json& value, const std::string& key,
                     const std::map<std::string, std::size_t>& materials) const {
    object_at(value, key, "an object {\"shape\": \"sphere\"|\"mesh\", ..., \"material\": NAME}");
    SceneObject o;
    if (!value.contains("shape")) refuse(key + " has no \"shape\"; allowed: sphere, mesh");
    const Json& shape = value["shape"];
    if (shape == "sphere") {
      o.shape = SceneObject::Shape::sphere;
      check_keys(value, key, {"shape", "center", "radius", "material", "tangent"});
      if (value.contains("center")) o.center = point(value["center"], key + ".center");
      if (value.contains("radius")) {
        o.radius = number(value["radius"], key + ".radius");
        if (!std::isfinite(o.radius) || o.radius <= 0.0)
          fail(key + ".radius", value["radius"], "expected a finite number > 0");
      }
    } else if (shape == "mesh") {
      o.shape = SceneObject::Shape::mesh;
      check_keys(value, key, {"shape", "path", "material", "tangent"});
      if (!value.contains("path")) refuse(key + " (a mesh) has no \"path\"; expected the path of an OBJ file");
      const Json& p = value["path"];
      if (!p.is_string() || p.get<std::string>().empty())
        fail(key + ".path", p, "expected the path of an OBJ file (relative to the scene file's directory)");
      const fs::path mesh(p.get<std::string>());
      o.mesh_path = (mesh.is_absolute() ? mesh : fs::path(path_).parent_path() / mesh).lexically_normal().string();
    } else {
      fail(key + ".shape", shape, "allowed: sphere, mesh");
    }
    if (!value.contains("material")) refuse(key + " has no \"material\"; expected the name of one of \"materials\"");
    const Json& name = value["material"];
    if (!name.is_string()) fail(key + ".material", name, "expected the name of one of \"materials\"");
    const auto found = materials.find(name.get<std::string>());
    if (found == materials.end()) {
      std::string defined;
      for (const auto& [n, index] : materials) defined += (defined.empty() ? "" : ", ") + n;
      refuse(key + ".material = " + quote(name) +
             " is not defined; defined materials: " + (defined.empty() ? "none" : defined));
    }
    o.material = found->second;
    if (value.contains("tangent")) o.tangent = tangent(value["tangent"], key + ".tangent");
    return o;
  }

  TangentRule tangent(const Json& value, const std::string& key) const {
    object_at(value, key, "an object {\"axis\": [x, y, z], \"along\": \"latitude\" | \"longitude\"}");
    check_keys(value, key, {"axis", "along"});
    TangentRule rule;
    if (value.contains("axis")) rule.axis = direction(value["axis"], key + ".axis");
    if (value.contains("along")) {
      const Json& along = value["along"];
      if (along != "latitude" && along != "longitude") fail(key + ".along", along, "allowed: latitude, longitude");
      rule.latitude = along == "latitude";
    }
    return rule;
  }

  Light light(const Json& value, const std::string& key) const {
    const char* allowed_types = "allowed: collimated, hemispherical, ganzfeld";
    object_at(value, key, "an object {\"type\": \"collimated\"|\"hemispherical\"|\"ganzfeld\", ...}");
    if (!value.contains("type")) refuse(key + " has no \"type\"; " + allowed_types);
    const Json& type = value["type"];
    Light l;
    if (type == "collimated") {
      l.type = Light::Type::collimated;
      check_keys(value, key, {"type", "direction", "irradiance"});
      if (value.contains("direction")) l.direction = direction(value["direction"], key + ".direction");
      if (value.contains("irradiance")) l.intensity = rgb(value["irradiance"], key + ".irradiance");
    } else if (type == "hemispherical") {
      l.type = Light::Type::hemispherical;
      check_keys(value, key, {"type", "pole", "radiance"});
      if (value.contains("pole")) l.direction = direction(value["pole"], key + ".pole");
      if (value.contains("radiance")) l.intensity = rgb(value["radiance"], key + ".radiance");
    } else if (type == "ganzfeld") {
      l.type = Light::Type::ganzfeld;
      check_keys(value, key, {"type", "radiance"});
      if (value.contains("radiance")) l.intensity = rgb(value["radiance"], key + ".radiance");
    } else {
      fail(key + ".type", type, allowed_types);
    }
    return l;
  }
};

}  // namespace

Vec3 brush_tangent(const Vec3& n, const TangentRule& rule) {
  const Vec3 t = rule.latitude ? glm::cross(rule.axis, n) : rule.axis - glm::dot(rule.axis, n) * n;
  if (glm::dot(t, t) > 1e-12 * glm::dot(rule.axis, rule.axis)) return glm::normalize(t);
  return std::abs(n.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0};
}

Scene load_scene(const std::string& path) { return Parser(path).parse(); }

Scene load_scene_text(const std::string& text, const std::string& path) { return Parser(path, text).parse(); }

}  // namespace ganzfeld
