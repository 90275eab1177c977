// f in GLSL, written once per model beside its C++ f (Model::glsl_f): the one way a model gets a
// shader form. export/glsl_f.h wraps it in functions of world-space directions for the viewer,
// `export-glsl --scene` and /api/glsl; tests/gl_f_test.cpp holds it against Model::f for every
// registered model at its defaults and its parameters' ends, on Mesa's llvmpipe.
//
// A GlslF is the body of
//   float f(vec3 i, vec3 j)
// in the model's local frame (n = +z, the tangent = +x, the bitangent = +y; i towards the source,
// j towards the eye, both unit: the frame and conventions of models/model.h), written step for
// step as the model's f (the same branches, clamps and floors, its constants as float literals:
// decimal_literal, util/literal.h),
// in the common subset of GLSL ES 3.00 and GLSL 4.30 core. It may call the helpers below by name;
// the exporter emits each helper it names (and what they call) once, before the body.
//
// GLSL leaves the accuracy of its transcendental functions to the implementation (GLSL ES 3.00
// §4.5.1: exp2/log2 "3 ULP" at best, pow "inherited from exp2(y log2(x))", asin/acos/atan
// unspecified), so the helpers that need more (gz_log1p, gz_pow1m, gz_asin, gz_acos, gz_atan2,
// gz_expm1, gz_erfc) are Cephes' single-precision kernels (S. Moshier, the Cephes Math Library:
// asinf.c, atanf.c, log1p via atanh, erfcf.c's rational forms) written with +, *, /, sqrt and
// the exp/log GLSL guarantees to a few ulps.
#pragma once

#include <string>
#include <vector>

#include "util/literal.h"

namespace ganzfeld {

struct GlslF {
  std::string body;                  ///< statements of float f(vec3 i, vec3 j), local frame
  std::vector<std::string> helpers;  ///< names of the helpers it calls (glsl_helper_names)
  /// The largest exponent the body applies to a quantity it cannot compute without rounding
  /// (Lafortune's pow(Cx ix jx + Cy iy jy + Cz iz jz, n): no rewriting removes the rounding of
  /// the sum): float's relative error of f grows with it. 0 where every power is taken of an
  /// exactly formed quantity (gz_pow_pair). tests/gl_f_test.cpp allows for it.
  double power = 0.0;
  /// Whether the body divides differences of O(1) arc integrals by sin(beta_i) sin(beta_j), beta the
  /// elevation of a direction's projection on the y-z plane (Poulin-Fournier's cylinders across +x,
  /// models/poulin_fournier.h): float's rounding of those integrals grows as 1/(sin beta_i sin beta_j)
  /// towards grazing projections. tests/gl_f_test.cpp allows for it.
  bool divides_by_cross_section_elevations = false;
};

/// The first statement of every body, as of every f: 0 when either direction is strictly below
/// the horizon.
inline constexpr const char* kGlslBelowHorizon = "  if (i.z < 0.0 || j.z < 0.0) return 0.0;\n";

/// Every helper's name, in the order they are emitted.
std::vector<std::string> glsl_helper_names();

/// The code of the named helpers and of the helpers they call, each once, dependencies first,
/// each inside its own #ifndef guard (so snippets emitted separately can share one shader).
/// Throws std::logic_error for an unknown name (a model naming a helper that does not exist).
std::string glsl_helpers(const std::vector<std::string>& names);

}  // namespace ganzfeld
