// The string attributes of a ganzfeld table's OpenEXR header (docs/lut-format.md), read by name;
// every refusal is one line naming the file. Shared by the readers of format versions 1–2
// (tables/exr_io.cpp) and 3 (tables/param_io.cpp).
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfStringAttribute.h>

#include "util/error.h"

namespace ganzfeld::tables {

struct ExrAttributes {
  std::string path;     ///< the file, named in every refusal: "table 'PATH': why"
  std::string prefix;   ///< of every attribute's name: "ganzfeld." when the callers give keys
  std::string missing;  ///< what a missing attribute says about the file, after its name

  [[noreturn]] void refuse(const std::string& why) const { throw InputError("table '" + path + "': " + why); }

  /// The string attribute prefix + key; refused when missing.
  std::string attribute(const Imf::Header& header, const std::string& key) const {
    const auto* a = header.findTypedAttribute<Imf::StringAttribute>(prefix + key);
    if (!a) refuse("missing string attribute " + prefix + key + missing);
    return a->value();
  }

  /// The attribute as a finite number >= 0, all of its text.
  double number(const Imf::Header& header, const std::string& key) const {
    const std::string text = attribute(header, key);
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(x) || x < 0.0)
      refuse(prefix + key + " '" + text + "' is not a finite number >= 0");
    return x;
  }
};

}  // namespace ganzfeld::tables
