#include "serve/request_head.h"

#include <algorithm>
#include <cctype>

namespace ganzfeld::serve {

namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

HeadScan refused(HeadScan scan, int status, std::string message) {
  scan.verdict = HeadScan::Verdict::refused;
  scan.status = status;
  scan.message = std::move(message);
  return scan;
}

/// A '\n' not after '\r', a '\r' not before '\n', or a NUL: ends lines two ways, or hides bytes.
bool has_bare_line_break(std::string_view text) {
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '\0') return true;
    if (text[k] == '\n' && (k == 0 || text[k - 1] != '\r')) return true;
    if (text[k] == '\r' && k + 1 < text.size() && text[k + 1] != '\n') return true;
  }
  return false;
}

}  // namespace

HeadScan scan_head(std::string_view buffer, std::size_t max_bytes) {
  HeadScan scan;
  std::size_t start = 0;
  while (buffer.substr(start, 2) == "\r\n") start += 2;
  const std::string_view rest = buffer.substr(start);
  scan.request_line = std::string(rest.substr(0, std::min(rest.find("\r\n"), std::size_t{200})));
  const std::size_t end = rest.find("\r\n\r\n");
  const std::string_view head = end == std::string_view::npos ? rest : rest.substr(0, end + 4);
  if (has_bare_line_break(head))
    return refused(scan, 400, "malformed request head: every line must end in CRLF, without NUL bytes (RFC 9112, 2.2)");
  if (head.size() > max_bytes)
    return refused(scan, 431, "request head larger than " + std::to_string(max_bytes) + " bytes");
  if (end == std::string_view::npos) return scan;

  std::string kept;
  std::size_t line_start = head.find("\r\n") + 2;
  kept.append(head.substr(0, line_start));
  while (line_start < end + 2) {
    const std::size_t line_end = head.find("\r\n", line_start);
    const std::string_view line = head.substr(line_start, line_end - line_start);
    line_start = line_end + 2;
    if (line.front() == ' ' || line.front() == '\t')
      return refused(scan, 400, "malformed request head: folded header lines are not allowed (RFC 9112, 5.2)");
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos || colon == 0)
      return refused(scan, 400, "malformed request head: a header line without a field name and ':'");
    const std::string_view name = line.substr(0, colon);
    if (name.find_first_of(" \t") != std::string_view::npos)
      return refused(scan, 400, "malformed request head: white space before ':' in a header field (RFC 9112, 5.1)");
    const std::string field = lower(name);
    const std::string_view value = trimmed(line.substr(colon + 1));
    if (field == "transfer-encoding" ||
        (field == "content-length" && value.find_first_not_of('0') != std::string_view::npos))
      return refused(scan, 413,
                     "a request with a body: only GET and HEAD are served and their requests carry none; "
                     "the connection is closed");
    if (field == "range" || field == "if-range") continue;  // every answer is the whole body
    kept.append(line);
    kept.append("\r\n");
  }
  kept.append("\r\n");
  scan.verdict = HeadScan::Verdict::complete;
  scan.consumed = start + end + 4;
  scan.head = std::move(kept);
  return scan;
}

}  // namespace ganzfeld::serve
