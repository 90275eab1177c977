#include "util/literal.h"

#include <cmath>
#include <cstdio>

#include "util/error.h"

namespace ganzfeld {

std::string decimal_literal(double x) {
  if (!std::isfinite(x))
    throw InputError("cannot write the non-finite number " + std::to_string(x) + " into source code");
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.9g", x);
  std::string text = buffer;
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

}  // namespace ganzfeld
