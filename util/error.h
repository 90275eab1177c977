// Bad input at a boundary (spec strings, files, command line, scene JSON, requests). The message
// is one line naming the bad value and what is allowed; cli/run.cpp maps it to exit code 2, the
// service to 400.
//
// Library code names parameters, never a front end's flags: a message is pieces of text and
// Named parameters ({"max_error", "0.5"}), and each front end spells them as its user writes
// them (the command line's `--max-error 0.5`, a query's `max_error=0.5`, a JSON path in a
// library file). what() spells them as a query does.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace ganzfeld {

/// A parameter named in an input error, with the value it was given ("" when the message names
/// the parameter alone), in the library's words: lower case with underscores (max_error, res).
struct Named {
  std::string parameter;
  std::string value{};
};

class InputError : public std::runtime_error {
 public:
  using Piece = std::variant<std::string, Named>;
  /// How a front end writes a parameter its user gave.
  using Spelling = std::function<std::string(const Named&)>;

  /// A message in words alone.
  explicit InputError(const std::string& message) : InputError(std::vector<Piece>{message}) {}
  /// A message of text and Named parameters; the first one named is the parameter refused.
  explicit InputError(std::vector<Piece> pieces)
      : std::runtime_error(words(pieces, query_spelling)), pieces_(std::move(pieces)) {}

  /// The parameter refused and its value: the first one the message names ("" for none).
  const Named& refused() const noexcept {
    for (const Piece& piece : pieces_)
      if (const Named* named = std::get_if<Named>(&piece)) return *named;
    static const Named none{};
    return none;
  }

  /// The message with each parameter as `spell` writes it.
  std::string worded(const Spelling& spell) const { return words(pieces_, spell); }

  /// The same error with parameter `from` named `to` (a front end whose parameter stands for
  /// the library's: the command line's --res-g gives the library's res).
  InputError renamed(const std::string& from, const std::string& to) const {
    std::vector<Piece> pieces = pieces_;
    for (Piece& piece : pieces)
      if (Named* named = std::get_if<Named>(&piece); named && named->parameter == from) named->parameter = to;
    return InputError(std::move(pieces));
  }

  /// A query's spelling, what(): max_error=0.5, or the name alone.
  static std::string query_spelling(const Named& named) {
    return named.value.empty() ? named.parameter : named.parameter + "=" + named.value;
  }
  /// The command line's spelling, as its --help shows flags: --max-error 0.5, or the flag alone.
  static std::string flag_spelling(const Named& named) {
    std::string flag = "--" + named.parameter;
    for (char& c : flag)
      if (c == '_') c = '-';
    return named.value.empty() ? flag : flag + " " + named.value;
  }

 private:
  /// Line breaks (from a quoted bad value: a spec, a path, a file's text) become spaces, so the
  /// message stays one line whatever it quotes (fuzz/spec_fuzz.cpp).
  static std::string words(const std::vector<Piece>& pieces, const Spelling& spell) {
    std::string text;
    for (const Piece& piece : pieces)
      text += std::holds_alternative<Named>(piece) ? spell(std::get<Named>(piece)) : std::get<std::string>(piece);
    for (char& c : text)
      if (c == '\n' || c == '\r') c = ' ';
    return text;
  }

  std::vector<Piece> pieces_;
};

/// Work stopped because its caller's cancellation flag was set (CubatureOptions::cancel,
/// tables::BakeOptions::cancel): not a bad input, and nothing was written. The caller set the
/// flag and knows why.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ganzfeld
