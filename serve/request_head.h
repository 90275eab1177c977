// The request head as it arrives on a connection, judged before cpp-httplib parses it
// (serve/connection_loop.h reads heads; http.cpp hands complete ones to httplib): where it ends,
// what is refused without a worker, and what is removed. The service answers GET and HEAD, whose
// requests carry no body, so a head is all a request is:
//   - a head that announces a body (Content-Length other than 0, or any Transfer-Encoding) is
//     refused with 413 and its connection closed: the body is never read, and never parsed as
//     the next request (request smuggling behind a proxy, RFC 9112 11.2);
//   - lines must end in CRLF, and header fields may not be folded or have space before their
//     colon (RFC 9112 2.2, 5.1, 5.2): 400, since two parsers could read such a head two ways;
//   - a head larger than the limit: 431 (RFC 6585 5);
//   - Range and If-Range fields are removed: every answer is the whole body (RFC 9110 14.2: a
//     server may ignore Range), so no partial body goes out under the whole body's ETag;
//   - empty lines before the request line are skipped (RFC 9112 2.2).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ganzfeld::serve {

struct HeadScan {
  enum class Verdict { incomplete, complete, refused };
  Verdict verdict = Verdict::incomplete;
  std::size_t consumed = 0;  ///< complete: bytes of the buffer the head took (leading empty lines included)
  std::string head;          ///< complete: the head, through its empty line, without Range and If-Range
  int status = 0;            ///< refused: 400, 413 or 431
  std::string message;       ///< refused: one line naming what is wrong and what is allowed
  std::string request_line;  ///< the first line as far as it arrived (for the access log)
};

/// Judges the bytes received so far on a connection (the head starts the buffer).
HeadScan scan_head(std::string_view buffer, std::size_t max_bytes);

}  // namespace ganzfeld::serve
