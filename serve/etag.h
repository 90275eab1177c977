// Entity tags (RFC 9110, 8.8.3): a response body is named by its content digest, so the tag
// changes exactly when the bytes do and a client may cache a table forever (Cache-Control:
// immutable) and revalidate with If-None-Match.
#pragma once

#include <string>
#include <string_view>

namespace ganzfeld::serve {

/// The strong tag of `bytes`: "\"fnv1a64:<16 hex>\"" (util::content_digest_of, quoted).
std::string strong_etag(std::string_view bytes);

/// Whether an If-None-Match header value matches `etag` (RFC 9110, 13.1.2: "*" or a
/// comma-separated list of tags, compared weakly: a W/ prefix is ignored).
bool if_none_match(std::string_view header, std::string_view etag);

}  // namespace ganzfeld::serve
