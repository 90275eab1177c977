#include "models/text_data.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "models/registry.h"  // format_number

namespace ganzfeld {

std::string read_text_file(const std::string& path, const std::string& what) {
  // Not a device or FIFO: /dev/zero would be read for ever, a FIFO block.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError("cannot read " + what + ": not a regular file");
  std::ifstream in(path, std::ios::binary);  // the bytes as they are: models hash them (content_digest)
  if (!in) throw InputError("cannot read " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TextDataReader::TextDataReader(const std::string& text, std::string what) : in_(text), what_(std::move(what)) {}

bool TextDataReader::next_line() {
  while (std::getline(in_, line_)) {
    ++line_number_;
    const auto hash = line_.find('#');
    if (hash != std::string::npos) line_.erase(hash);
    if (line_.find_first_not_of(" \t\r") != std::string::npos) return true;
  }
  return false;
}

InputError TextDataReader::error(const std::string& why) const {
  return InputError(what_ + ", line " + std::to_string(line_number_) + ": " + why);
}

void TextDataReader::expect_magic(const char* magic) {
  if (!next_line() || line_.substr(0, std::strlen(magic)) != magic)
    throw error(std::string("expected the first line '") + magic + "'");
}

std::vector<double> TextDataReader::read_values(const char* key, double lo, double hi, const char* unit,
                                                bool increasing) {
  if (!next_line()) throw error(std::string("missing the '") + key + ":' line");
  std::istringstream ls(line_);
  std::string word;
  ls >> word;
  if (word != std::string(key) + ":") throw error(std::string("expected '") + key + ": VALUES...', got '" + word + "'");
  std::vector<double> values;
  double v;
  while (ls >> v) values.push_back(v);
  if (!ls.eof()) throw error(std::string("a value of ") + key + " is not a number");
  if (values.empty()) throw error(std::string(key) + " has no values");
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!(values[k] >= lo && values[k] <= hi))
      throw error(std::string(key) + " value " + format_number(values[k]) + " is outside [" + format_number(lo) + ", " +
                  format_number(hi) + "]" + unit);
    if (increasing && k > 0 && !(values[k] > values[k - 1]))
      throw error(std::string(key) + " values must increase strictly");
  }
  return values;
}

}  // namespace ganzfeld
