// Bad input at a boundary (spec strings, files, command line, scene JSON). The message is one
// line naming the bad value and what is allowed; cli/main maps it to exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace ganzfeld {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace ganzfeld
