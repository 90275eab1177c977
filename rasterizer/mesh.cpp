#include "rasterizer/mesh.h"

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <utility>

#include "util/error.h"

namespace ganzfeld::raster {

Mesh uv_sphere(const Vec3& center, double radius, int segments) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InputError("sphere radius " + std::to_string(radius) + " is invalid; allowed: a finite number > 0");
  if (segments < 3 || segments > 4096)
    throw InputError("sphere segments " + std::to_string(segments) + " is invalid; allowed: 3..4096");
  const int slices = segments, stacks = std::max(2, segments / 2);
  Mesh mesh;
  mesh.exact_sphere = Sphere{center, radius};
  // Rings k = 0..stacks from the north pole (+y) to the south pole; the poles are single vertices.
  auto ring_start = [&](int k) -> std::uint32_t { return 1 + static_cast<std::uint32_t>((k - 1) * slices); };
  auto add = [&](const Vec3& n) {
    mesh.normals.push_back(n);
    mesh.positions.push_back(center + radius * n);
  };
  add({0, 1, 0});
  for (int k = 1; k < stacks; ++k) {
    const double theta = std::numbers::pi * k / stacks;
    for (int s = 0; s < slices; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / slices;
      add({std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)});
    }
  }
  add({0, -1, 0});
  const auto south = static_cast<std::uint32_t>(mesh.positions.size() - 1);
  for (int s = 0; s < slices; ++s) {
    const auto s0 = static_cast<std::uint32_t>(s), s1 = static_cast<std::uint32_t>((s + 1) % slices);
    mesh.triangles.push_back({0, ring_start(1) + s0, ring_start(1) + s1});
    for (int k = 1; k + 1 < stacks; ++k) {
      const std::uint32_t a = ring_start(k), b = ring_start(k + 1);
      mesh.triangles.push_back({a + s0, b + s0, b + s1});
      mesh.triangles.push_back({a + s0, b + s1, a + s1});
    }
    mesh.triangles.push_back({ring_start(stacks - 1) + s0, south, ring_start(stacks - 1) + s1});
  }
  return mesh;
}

void compute_normals(Mesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), Vec3{0, 0, 0});
  for (const auto& t : mesh.triangles) {
    // The cross product's length is twice the area: summing it weights faces by area.
    const Vec3 face =
        glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (auto v : t) mesh.normals[v] += face;
  }
  for (Vec3& n : mesh.normals) {
    const double len = glm::length(n);
    n = len > 0.0 ? n / len : Vec3{0, 0, 1};
  }
}

namespace {

struct Corner {
  long v = 0;
  long vn = -1;  ///< -1: none
};

class ObjParser {
 public:
  explicit ObjParser(std::string path) : path_(std::move(path)) {}

  Mesh parse() {
    std::ifstream in(path_);
    if (!in) throw InputError("cannot read OBJ file '" + path_ + "': missing or not readable");
    std::string line;
    while (std::getline(in, line)) {
      ++line_no_;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      std::istringstream words(line);
      std::string key;
      if (!(words >> key)) continue;
      if (key == "v") positions_.push_back(vector3(words, "v"));
      else if (key == "vn") normals_.push_back(normal(words));
      else if (key == "f") face(words);
      // vt, o, g, s, usemtl, mtllib, l, p ...: not needed for shading.
    }
    if (in.bad()) throw InputError("cannot read OBJ file '" + path_ + "': read error");
    if (faces_.empty()) throw InputError("OBJ file '" + path_ + "' has no faces (f statements)");
    return build();
  }

 private:
  [[noreturn]] void refuse(const std::string& why) const {
    throw InputError("OBJ file '" + path_ + "' line " + std::to_string(line_no_) + ": " + why);
  }

  Vec3 vector3(std::istringstream& words, const char* key) {
    double x, y, z;
    if (!(words >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      refuse(std::string("'") + key + "' needs three finite numbers");
    return {x, y, z};
  }

  Vec3 normal(std::istringstream& words) {
    const Vec3 n = vector3(words, "vn");
    const double len = glm::length(n);
    if (!(len > 0.0)) refuse("'vn' is the zero vector");
    return n / len;
  }

  /// A 1-based (or negative, relative) index into a list of `count` items.
  long index(const std::string& text, std::size_t count, const char* what) {
    std::size_t used = 0;
    long k = 0;
    try {
      k = std::stol(text, &used);
    } catch (const std::exception&) { refuse("face corner '" + text + "' is not an index"); }
    if (used != text.size()) refuse("face corner '" + text + "' is not an index");
    const long resolved = k < 0 ? static_cast<long>(count) + k : k - 1;
    if (k == 0 || resolved < 0 || resolved >= static_cast<long>(count))
      refuse(std::string(what) + " index " + text + " is out of range; " + std::to_string(count) + " defined so far");
    return resolved;
  }

  void face(std::istringstream& words) {
    std::vector<Corner> corners;
    std::string word;
    while (words >> word) {
      // v, v/vt, v//vn, v/vt/vn
      const auto s1 = word.find('/');
      Corner c;
      c.v = index(word.substr(0, s1), positions_.size(), "vertex");
      if (s1 != std::string::npos) {
        const auto s2 = word.find('/', s1 + 1);
        if (s2 != std::string::npos) {
          const std::string n = word.substr(s2 + 1);
          if (n.empty()) refuse("face corner '" + word + "' has an empty normal index");
          c.vn = index(n, normals_.size(), "normal");
        }
      }
      corners.push_back(c);
    }
    if (corners.size() < 3) refuse("'f' needs at least 3 corners");
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) faces_.push_back({corners[0], corners[k], corners[k + 1]});
  }

  Mesh build() const {
    Mesh mesh;
    bool all_normals = true;
    for (const auto& f : faces_)
      for (const auto& c : f) all_normals = all_normals && c.vn >= 0;
    if (!all_normals) {
      mesh.positions = positions_;
      for (const auto& f : faces_)
        mesh.triangles.push_back({static_cast<std::uint32_t>(f[0].v), static_cast<std::uint32_t>(f[1].v),
                                  static_cast<std::uint32_t>(f[2].v)});
      compute_normals(mesh);
      return mesh;
    }
    // One mesh vertex per distinct (position, normal) pair.
    std::map<std::pair<long, long>, std::uint32_t> vertex;
    for (const auto& f : faces_) {
      std::array<std::uint32_t, 3> t{};
      for (int k = 0; k < 3; ++k) {
        const auto [it, fresh] =
            vertex.try_emplace({f[k].v, f[k].vn}, static_cast<std::uint32_t>(mesh.positions.size()));
        if (fresh) {
          mesh.positions.push_back(positions_[f[k].v]);
          mesh.normals.push_back(normals_[f[k].vn]);
        }
        t[k] = it->second;
      }
      mesh.triangles.push_back(t);
    }
    return mesh;
  }

  std::string path_;
  long line_no_ = 0;
  std::vector<Vec3> positions_, normals_;
  std::vector<std::array<Corner, 3>> faces_;
};

}  // namespace

Mesh load_obj(const std::string& path) { return ObjParser(path).parse(); }

}  // namespace ganzfeld::raster
