// Numbers written into generated source (GLSL snippets and the GLSL f of models, C headers): one way
// to print them.
#pragma once

#include <string>

namespace ganzfeld {

/// A decimal literal of x with 9 significant digits, which GLSL, C and C++ read back as the float
/// nearest to x (exactly x when x is a float), with a decimal point where %g would print a whole
/// number ("1.0", not "1": GLSL would read an int, and C's "1f" is no literal at all). C and C++
/// float literals append "f". Throws InputError for a number that is not finite.
std::string decimal_literal(double x);

}  // namespace ganzfeld
