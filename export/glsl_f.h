// f of a model as GLSL functions of world-space directions (docs/shaders.md), built from the
// model's own GLSL f (Model::glsl_f, models/glsl.h) and nothing else:
//   float gz_f_<spec>_local(vec3 i, vec3 j)            the model's body in its local frame
//   float gz_f_<spec>(vec3 i, vec3 j, vec3 n, vec3 t)  world space: n the unit normal, t the tangent
//                                                      (its part across n is the local +x axis)
//   float gz_f_<spec>(vec3 i, vec3 j, vec3 n)          isotropic models only (any tangent)
//   float gz_mirror_<spec>(float c)                    models with a mirror delta only (he-torrance,
//                                                      Model::glsl_mirror_reflectance): its reflectance
//                                                      rho at c = j.n, which f excludes
// i towards the source, j towards the eye, unit; 0 when either lies below the horizon. A mixture
// is the weighted sum of its lobes' functions (each emitted once). The helpers the bodies call
// come first, each in its own #ifndef guard, so several snippets can share one shader.
#pragma once

#include <string>

#include "models/model.h"

namespace ganzfeld::exporting {

/// gz_f_<spec>: the name of the function of world-space directions.
std::string glsl_f_name(const std::string& spec);

/// gz_mirror_<spec>: the name of the mirror delta's reflectance.
std::string glsl_mirror_name(const std::string& spec);

/// Whether the model (every lobe of a mixture) has a GLSL f.
bool has_glsl_f(const Model& model);

/// The functions above (helpers first). Throws InputError naming the model, why it has none, and
/// which models have one.
std::string glsl_model_f(const Model& model);

}  // namespace ganzfeld::exporting
