#include "export/glsl_f.h"

#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

#include "export/glsl.h"
#include "models/mixture.h"
#include "models/registry.h"
#include "util/error.h"

namespace ganzfeld::exporting {

namespace {

/// Every lobe of a mixture, or the model itself.
std::vector<const Model*> lobes_of(const Model& model) {
  std::vector<const Model*> out;
  if (const auto* mixture = dynamic_cast<const Mixture*>(&model)) {
    for (const Lobe& lobe : mixture->lobes()) out.push_back(lobe.model.get());
  } else {
    out.push_back(&model);
  }
  return out;
}

/// "lambert, minnaert, ...": the registered models that need no data file.
std::string analytic_models() {
  std::string names;
  for (const ModelInfo& info : model_catalogue())
    if (info.make || info.file_optional) names += (names.empty() ? "" : ", ") + info.name;
  return names;
}

/// The three functions of one (non-mixture) model, and its mirror delta's reflectance if it has one.
std::string single_f(const Model& model, const GlslF& f, const std::optional<GlslF>& mirror) {
  const std::string name = glsl_f_name(model.spec());
  std::ostringstream s;
  s << "// f of " << model.spec() << " in its local frame (Model::glsl_f); i, j unit.\n"
    << "float " << name << "_local(vec3 i, vec3 j) {\n"
    << f.body << "}\n"
    << "float " << name << "(vec3 i, vec3 j, vec3 n, vec3 t) {\n"
    << "  return " << name << "_local(gz_to_local(i, n, t), gz_to_local(j, n, t));\n}\n";
  if (model.traits().isotropic)
    s << "float " << name << "(vec3 i, vec3 j, vec3 n) { return " << name << "(i, j, n, gz_any_tangent(n)); }\n";
  if (mirror)
    s << "// the reflectance of the mirror delta of " << model.spec() << " at c = j.n (Model::mirror_reflectance)\n"
      << "float " << glsl_mirror_name(model.spec()) << "(float c) {\n"
      << mirror->body << "}\n";
  return s.str();
}

}  // namespace

std::string glsl_f_name(const std::string& spec) { return glsl_identifier("f_" + spec); }
std::string glsl_mirror_name(const std::string& spec) { return glsl_identifier("mirror_" + spec); }

bool has_glsl_f(const Model& model) {
  for (const Model* lobe : lobes_of(model))
    if (!lobe->glsl_f()) return false;
  return true;
}

std::string glsl_model_f(const Model& model) {
  std::vector<std::string> helpers{"gz_frame"};
  std::vector<std::tuple<const Model*, GlslF, std::optional<GlslF>>> bodies;
  std::set<std::string> emitted;
  for (const Model* lobe : lobes_of(model)) {
    std::optional<GlslF> f = lobe->glsl_f();
    if (!f)
      throw InputError("no GLSL form of f for model '" + lobe->spec() +
                       "' (its f is read from a data file; the viewer asks the service for it); available: the "
                       "analytic models (" +
                       analytic_models() + ") and their mixtures");
    if (!emitted.insert(glsl_f_name(lobe->spec())).second) continue;
    helpers.insert(helpers.end(), f->helpers.begin(), f->helpers.end());
    std::optional<GlslF> mirror = lobe->glsl_mirror_reflectance();
    if (mirror) helpers.insert(helpers.end(), mirror->helpers.begin(), mirror->helpers.end());
    bodies.emplace_back(lobe, std::move(*f), std::move(mirror));
  }
  std::string out = glsl_helpers(helpers);
  for (const auto& [lobe, f, mirror] : bodies) out += single_f(*lobe, f, mirror);
  const auto* mixture = dynamic_cast<const Mixture*>(&model);
  if (!mixture) return out;
  // f of a mixture is the weighted sum of its lobes' f (models/mixture.h; weights normalized).
  std::string sum4, sum3, mirror_sum;
  for (const Lobe& lobe : mixture->lobes()) {
    const std::string weight = decimal_literal(lobe.weight) + " * ";
    const std::string term = weight + glsl_f_name(lobe.model->spec());
    sum4 += (sum4.empty() ? "" : " + ") + term + "(i, j, n, t)";
    sum3 += (sum3.empty() ? "" : " + ") + term + "(i, j, n)";
    if (lobe.model->glsl_mirror_reflectance())
      mirror_sum += (mirror_sum.empty() ? "" : " + ") + weight + glsl_mirror_name(lobe.model->spec()) + "(c)";
  }
  const std::string name = glsl_f_name(model.spec());
  out += "// f of the mixture " + model.spec() + "\n" + "float " + name + "(vec3 i, vec3 j, vec3 n, vec3 t) { return " +
         sum4 + "; }\n";
  if (model.traits().isotropic) out += "float " + name + "(vec3 i, vec3 j, vec3 n) { return " + sum3 + "; }\n";
  if (!mirror_sum.empty())  // the weighted sum of the lobes' mirror reflectances (Mixture::mirror_reflectance)
    out += "float " + glsl_mirror_name(model.spec()) + "(float c) { return " + mirror_sum + "; }\n";
  return out;
}

}  // namespace ganzfeld::exporting
