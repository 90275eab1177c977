#include "export/param_export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <Imath/half.h>

#include "export/glsl.h"
#include "models/registry.h"
#include "util/literal.h"

namespace ganzfeld::exporting {

namespace {

/// A float literal GLSL reads back to the same float.
std::string glsl_float(double x) { return decimal_literal(static_cast<float>(x)); }

/// GLSL for the sample position along one axis (tables::grid_position), `x` the coordinate.
std::string position_glsl(const tables::Axis& axis, tables::Grid grid, const std::string& x, const std::string& n) {
  std::string u =
      "clamp((" + x + " - " + glsl_float(axis.min) + ") / " + glsl_float(axis.max - axis.min) + ", 0.0, 1.0)";
  if (axis.mapping == tables::Mapping::sqrt) u = "sqrt(" + u + ")";
  if (grid == tables::Grid::node) return u + " * (" + n + " - 1.0)";
  return "clamp(" + u + " * " + n + " - 0.5, 0.0, " + n + " - 1.0)";
}

std::string channel_list(const tables::ParamTable& table) {
  std::string list;
  const char* components = "RGBA";
  for (std::size_t c = 0; c < table.channels.size(); ++c)
    list += (c ? ", " : "") + std::string(1, components[c]) + " = " + table.channels[c].name;
  return list;
}

}  // namespace

std::string glsl_param_function_name(const tables::ParamTable& table) {
  return glsl_identifier(table.preset + "_" + table.layout);
}

std::string glsl_param_snippet(const tables::ParamTable& table) {
  tables::check_param_table(table);
  const std::string name = glsl_param_function_name(table);
  std::ostringstream s;
  s << "// ganzfeld parameter table (generated; docs/lut-format.md, version 3): preset " << table.preset << " ("
    << table.layout << ") of " << table.model << "\n// made by: " << table.command << "\n// texture: width "
    << table.axes[1].count << " (cos_theta_i), height " << table.axes[0].count << " (" << table.axes[0].name
    << ", row 0 smallest), " << to_string(table.grid) << "-centred samples; " << channel_list(table)
    << "\n// error: per texel <= " << format_number(table.node_error)
    << " (+ half rounding in a header texture); interpolation between texels not included\n"
    << "vec4 " << name << "(highp sampler2D table, float mu, float " << table.axes[0].name << ") {\n"
    << "  vec2 n = vec2(textureSize(table, 0));\n"
    << "  vec2 s = vec2(" << position_glsl(table.axes[1], table.grid, "mu", "n.x") << ",\n"
    << "                " << position_glsl(table.axes[0], table.grid, table.axes[0].name, "n.y") << ");\n"
    << "  ivec2 k = min(ivec2(floor(s)), ivec2(n) - 2);\n"
    << "  vec2 w = s - vec2(k);\n"
    << "  vec4 lower = mix(texelFetch(table, k, 0), texelFetch(table, k + ivec2(1, 0), 0), w.x);\n"
    << "  vec4 upper = mix(texelFetch(table, k + ivec2(0, 1), 0), texelFetch(table, k + ivec2(1, 1), 0), w.x);\n"
    << "  return mix(lower, upper, w.y);\n}\n";
  return s.str();
}

std::vector<std::uint16_t> param_half_texels(const tables::ParamTable& table) {
  std::vector<std::uint16_t> bits;
  for (std::size_t m = 0; m < table.entries(); ++m)
    for (const tables::Channel& ch : table.channels) bits.push_back(Imath::half(ch.value[m]).bits());
  return bits;
}

double param_half_error(const tables::ParamTable& table) {
  double bound = 0.0;
  for (const tables::Channel& ch : table.channels)
    for (std::size_t m = 0; m < ch.value.size(); ++m) {
      const double rounding = std::abs(static_cast<double>(static_cast<float>(Imath::half(ch.value[m]))) - ch.value[m]);
      bound = std::max(bound, static_cast<double>(ch.error[m]) + rounding);
    }
  return bound;
}

std::string param_c_header(const tables::ParamTable& table, const std::string& symbol) {
  tables::check_param_table(table);
  const tables::Axis &p = table.axes[0], &mu = table.axes[1];
  std::ostringstream s;
  s << "// ganzfeld parameter table as a C array (generated; docs/lut-format.md, version 3): preset " << table.preset
    << " (" << table.layout << ") of " << table.model << "\n// made by: " << table.command
    << "\n// texels: IEEE half bits, row-major (row = " << p.name << " sample, column = cos_theta_i sample), "
    << table.channels.size() << " components per texel: " << channel_list(table) << "; upload as GL_R"
    << (table.channels.size() > 2 ? "GB" : "G") << "16F / GL_HALF_FLOAT\n"
    << "// sample k of N at u = " << (table.grid == tables::Grid::texel ? "(k + 0.5)/N" : "k/(N - 1)") << " ("
    << to_string(table.grid) << "-centred), " << p.name << " and cos_theta_i " << to_string(p.mapping) << "/"
    << to_string(mu.mapping)
    << " over [min, max]\n// error: |texel - exact| <= " << format_number(param_half_error(table))
    << " (the table's per-texel bound + half rounding)\n#pragma once\n#include <stdint.h>\n\n"
    << "enum { " << symbol << "_width = " << mu.count << ", " << symbol << "_height = " << p.count << ", " << symbol
    << "_channels = " << table.channels.size() << ", " << symbol
    << "_texel_centred = " << (table.grid == tables::Grid::texel) << " };\n"
    << "static const float " << symbol << "_mu_min = " << glsl_float(mu.min) << "f, " << symbol
    << "_mu_max = " << glsl_float(mu.max) << "f;\n"
    << "static const float " << symbol << "_" << p.name << "_min = " << glsl_float(p.min) << "f, " << symbol << "_"
    << p.name << "_max = " << glsl_float(p.max) << "f;\n";
  const std::vector<std::uint16_t> bits = param_half_texels(table);
  s << "static const uint16_t " << symbol << "_texels[" << bits.size() << "] = {";
  for (std::size_t k = 0; k < bits.size(); ++k) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "0x%04x", bits[k]);
    s << (k % 12 == 0 ? "\n  " : " ") << buffer << (k + 1 < bits.size() ? "," : "");
  }
  s << "\n};\n";
  return s.str();
}

}  // namespace ganzfeld::exporting
