// 64-bit FNV-1a, the one hash ganzfeld names things by: cache file names (tables/cache.h) and
// the content digest of a measured model's data file (Model::content_digest,
// docs/lut-format.md). Not cryptographic: it guards against stale files, not against forgery.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ganzfeld::util {

inline constexpr std::uint64_t kFnv1aOffsetBasis = 0xcbf29ce484222325ull;

/// 64-bit FNV-1a of the bytes, continuing from `hash`: hashing a file in pieces gives the hash
/// of the whole file.
std::uint64_t fnv1a_64(std::string_view bytes, std::uint64_t hash = kFnv1aOffsetBasis) noexcept;

/// The 16 lower-case hex digits of `hash`.
std::string hex16(std::uint64_t hash);

/// "fnv1a64:" + hex16(hash): how ganzfeld names the bytes of a data file.
std::string content_digest(std::uint64_t hash);
/// content_digest(fnv1a_64(bytes)).
std::string content_digest_of(std::string_view bytes);
/// Whether `text` has the form content_digest gives.
bool is_content_digest(std::string_view text) noexcept;

}  // namespace ganzfeld::util
