#include "lut/plan.h"

#include <algorithm>

namespace ganzfeld::lut {

bool has_closed_form(const std::string& spec, Law law) {
  return (law == Law::g || law == Law::h) && spec == "lambert";
}

std::vector<TableRequest> tables_needed(const Scene& scene) {
  bool sky = false, ganzfeld = false;
  for (const Light& light : scene.lights) {
    sky = sky || light.type == Light::Type::hemispherical;
    ganzfeld = ganzfeld || light.type == Light::Type::ganzfeld;
  }
  std::vector<bool> used(scene.materials.size(), false);
  for (const SceneObject& object : scene.objects)
    if (object.material < used.size()) used[object.material] = true;

  std::vector<TableRequest> out;
  auto request = [&](Law law) {
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
      if (!used[m]) continue;
      for (const MaterialLobe& lobe : scene.materials[m].lobes) {
        if (has_closed_form(lobe.spec, law) || !lobe.model->traits().isotropic) continue;
        TableRequest r{lobe.spec, law, lobe.model};
        if (std::find(out.begin(), out.end(), r) == out.end()) out.push_back(std::move(r));
      }
    }
  };
  if (sky) request(Law::g);
  if (ganzfeld) request(Law::h);
  return out;
}

}  // namespace ganzfeld::lut
