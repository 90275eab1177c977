// Bad input at a boundary (spec strings, files, command line, scene JSON). The message is one
// line naming the bad value and what is allowed; cli/run.cpp maps it to exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace ganzfeld {

class InputError : public std::runtime_error {
 public:
  /// Line breaks in the message (from a quoted bad value: a spec, a path, a file's text) become
  /// spaces, so the message stays one line whatever it quotes (found by fuzz/spec_fuzz.cpp).
  explicit InputError(const std::string& message) : std::runtime_error(one_line(message)) {}

 private:
  static std::string one_line(std::string text) {
    for (char& c : text)
      if (c == '\n' || c == '\r') c = ' ';
    return text;
  }
};

/// Work stopped because its caller's cancellation flag was set (CubatureOptions::cancel,
/// tables::BakeOptions::cancel): not a bad input, and nothing was written. The caller set the
/// flag and knows why.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ganzfeld
