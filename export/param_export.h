// Parameter tables (format version 3: the DFG and Kulla–Conty presets, tables/preset.h) for
// real-time shaders: a GLSL lookup that reproduces tables::sample_param, and the table as a C
// header of half floats with its axis constants, the way engines embed their DFG arrays.
//
// Texture: width = cos_theta_i samples, height = parameter samples (row 0 = the smallest
// parameter), one texel component per channel in the table's channel order (R = channel 0, G =
// channel 1, B = channel 2): GL_RG16F or GL_RGB16F with GL_HALF_FLOAT from the header's array.
//
// GLSL (4.30 core and ES 3.00), for a table of preset P and layout L:
//   vec4 gz_P_L(highp sampler2D table, float mu, float x)   // x on the table's parameter axis
// per axis: t = clamp((x − min)/(max − min), 0, 1), u = t (linear) or sqrt(t) (sqrt), the sample
// position s = u N − 0.5 clamped to [0, N − 1] (texel grid) or u (N − 1) (node grid), then the
// bilinear blend of the 4 texels by texelFetch: the same steps as sample_param, in float. On a
// texel grid this equals what texture(table, vec2(u_mu, u_x)) returns with GL_LINEAR filtering
// and clamp-to-edge, up to the hardware's weight precision.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tables/param_table.h"

namespace ganzfeld::exporting {

/// "gz_<preset>_<layout>", e.g. gz_dfg_filament.
std::string glsl_param_function_name(const tables::ParamTable& table);

/// A comment with the table's metadata, then the lookup function (a self-contained snippet).
std::string glsl_param_snippet(const tables::ParamTable& table);

/// The texels as IEEE half bits, row-major (row = parameter sample), channels interleaved.
std::vector<std::uint16_t> param_half_texels(const tables::ParamTable& table);

/// Bound of |header texel − exact| over the table: the table's per-texel bound plus the rounding
/// of the value to half, the largest over all texels and channels.
double param_half_error(const tables::ParamTable& table);

/// The C header: metadata comment, dimensions, axis constants and the half texels under `symbol`.
std::string param_c_header(const tables::ParamTable& table, const std::string& symbol);

}  // namespace ganzfeld::exporting
