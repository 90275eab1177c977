// ganzfeld's small text data files (the tabulated BRDF of docs/measured.md, the Beard–Maxwell
// first-surface table of docs/models.md): a magic first line, '#' comments anywhere, blank lines
// skipped, "key: v1 v2 ..." lines of numbers. Errors are InputErrors naming the file, the line
// and the problem.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "util/error.h"

namespace ganzfeld {

/// The whole file, byte for byte; throws InputError "cannot read WHAT" when it cannot be opened.
std::string read_text_file(const std::string& path, const std::string& what);

class TextDataReader {
 public:
  /// `what` names the file in messages, e.g. "tabulated BRDF 'm.tab'".
  TextDataReader(const std::string& text, std::string what);

  /// Advances to the next line with content (comments stripped); false at the end.
  bool next_line();
  const std::string& line() const { return line_; }
  /// An InputError "WHAT, line N: why".
  InputError error(const std::string& why) const;

  /// The first line must start with `magic`.
  void expect_magic(const char* magic);
  /// Reads the next line as "key: v1 v2 ...": at least one value, each in [lo, hi] (`unit` is
  /// appended to the range in messages), strictly increasing when `increasing`.
  std::vector<double> read_values(const char* key, double lo, double hi, const char* unit, bool increasing);

 private:
  std::istringstream in_;
  std::string what_, line_;
  int line_number_ = 0;
};

}  // namespace ganzfeld
