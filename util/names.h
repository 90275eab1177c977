// Enumerations named in files, flags and requests (encodings, mappings, laws, ...): one table of
// names per enumeration serves both directions, and an unknown name is refused in one line that
// lists the allowed ones in the table's order.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>

#include "util/error.h"

namespace ganzfeld::util {

/// An enumerator and its name.
template <class Enum>
using EnumName = std::pair<Enum, const char*>;

/// The name of `value` in `names`; "?" for an enumerator the table lacks.
template <class Enum, std::size_t N>
constexpr const char* name_of(const std::array<EnumName<Enum>, N>& names, Enum value) noexcept {
  for (const auto& [enumerator, name] : names)
    if (enumerator == value) return name;
  return "?";
}

/// The enumerator called `text`; throws InputError "unknown WHAT 'TEXT'; allowed: a, b, c".
template <class Enum, std::size_t N>
Enum parse_name(const std::array<EnumName<Enum>, N>& names, const std::string& what, const std::string& text) {
  std::string allowed;
  for (const auto& [enumerator, name] : names) {
    if (text == name) return enumerator;
    allowed += (allowed.empty() ? "" : ", ") + std::string(name);
  }
  throw InputError("unknown " + what + " '" + text + "'; allowed: " + allowed);
}

}  // namespace ganzfeld::util
