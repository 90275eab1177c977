#include "serve/etag.h"

#include "util/hash.h"

namespace ganzfeld::serve {

std::string strong_etag(std::string_view bytes) {
  std::string tag(1, '"');  // appended, not "\"" + string: g++ 12 warns falsely (-Wrestrict) on that
  tag += util::content_digest_of(bytes);
  tag += '"';
  return tag;
}

bool if_none_match(std::string_view header, std::string_view etag) {
  const auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
  };
  if (trim(header) == "*") return true;
  while (!header.empty()) {
    const std::size_t comma = header.find(',');
    std::string_view tag = trim(header.substr(0, comma));
    if (tag.substr(0, 2) == "W/") tag.remove_prefix(2);
    if (!tag.empty() && tag == etag) return true;
    if (comma == std::string_view::npos) break;
    header.remove_prefix(comma + 1);
  }
  return false;
}

}  // namespace ganzfeld::serve
