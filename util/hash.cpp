#include "util/hash.h"

#include <cstdio>

namespace ganzfeld::util {

namespace {
constexpr std::string_view kDigestPrefix = "fnv1a64:";
}

std::uint64_t fnv1a_64(std::string_view bytes, std::uint64_t hash) noexcept {
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ull;  // the 64-bit FNV prime
  }
  return hash;
}

std::string hex16(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string content_digest(std::uint64_t hash) { return std::string(kDigestPrefix) + hex16(hash); }

std::string content_digest_of(std::string_view bytes) { return content_digest(fnv1a_64(bytes)); }

bool is_content_digest(std::string_view text) noexcept {
  if (text.size() != kDigestPrefix.size() + 16 || !text.starts_with(kDigestPrefix)) return false;
  for (char c : text.substr(kDigestPrefix.size()))
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

}  // namespace ganzfeld::util
