// libFuzzer target: the viewer's reading of request heads (src/view/request_head.h), the code between the
// socket and cpp-httplib. The input is the byte stream of one connection, cut into the pieces recv() would
// return: each 0xFF byte ends a piece (and is dropped). Every piece is appended and scanned, every complete
// head judged, as GuardedServer does. Checked for each head: the scan stops within the limits, and an
// accepted head is GET or HEAD, ends with its blank line, and carries no Range, If-Range,
// Transfer-Encoding or non-zero Content-Length line to cpp-httplib.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>

#include "../src/view/request_head.h"
#include "../src/view/viewer_server.h"

namespace {
using Limits = msh::view::ServerLimits;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

void check_accepted(const std::string& head) {
  if (head.rfind("GET", 0) != 0 && head.rfind("HEAD", 0) != 0) std::abort();
  if (head.size() < 4 || head.compare(head.size() - 4, 4, "\r\n\r\n") != 0) std::abort();
  // Each line after the request line, up to the blank one.
  std::size_t pos = head.find("\r\n") + 2;
  for (;;) {
    const std::size_t e = head.find("\r\n", pos);
    if (e == std::string::npos) std::abort();
    const std::string line = head.substr(pos, e - pos);
    if (line.empty()) break;
    const std::string l = lower(line);
    const std::size_t colon = l.find(':');
    std::string name = colon == std::string::npos ? "" : l.substr(0, colon);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name == "range" || name == "if-range" || name == "transfer-encoding") std::abort();
    if (name == "content-length") {
      std::string value = l.substr(colon + 1);
      value.erase(0, value.find_first_not_of(" \t"));
      value.erase(value.find_last_not_of(" \t") + 1);
      if (value != "0") std::abort();
    }
    pos = e + 2;
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string stream(reinterpret_cast<const char*>(data), size);
  std::string pending;
  std::size_t at = 0;
  for (int served = 0; served < Limits::kKeepAliveRequests && at <= stream.size();) {
    msh::view::RequestHeadScanner scanner(Limits::kMaxHeadBytes, Limits::kMaxHeaderLines);
    int status = msh::view::RequestHeadScanner::kNeedMore;
    std::string head;
    while ((status = scanner.scan(pending, head)) == msh::view::RequestHeadScanner::kNeedMore) {
      if (at >= stream.size()) return 0;  // the client stopped sending: the server closes (or 408)
      std::size_t end = stream.find('\xff', at);
      if (end == std::string::npos) end = stream.size();
      // One recv(): at most what is left of the piece and kMaxHeadBytes + 1 - pending.size() bytes (the
      // scanner refuses a longer pending, so that is at least 1); the rest of the piece comes next.
      const std::size_t n = std::min(end - at, Limits::kMaxHeadBytes + 1 - pending.size());
      pending.append(stream, at, n);
      at += n;
      if (at == end) ++at;  // the piece's end marker
    }
    if (status == 431) return 0;  // refused, connection closed
    if (status != msh::view::RequestHeadScanner::kComplete) std::abort();
    if (head.size() > Limits::kMaxHeadBytes + 2) std::abort();
    // The request line, at most kMaxHeaderLines header lines and the blank line.
    std::size_t crlf = 0;
    for (std::size_t p = 0; (p = head.find("\r\n", p)) != std::string::npos; p += 2) ++crlf;
    if (crlf > std::size_t(Limits::kMaxHeaderLines) + 2) std::abort();
    const msh::view::HeadVerdict v = msh::view::judge_head(head);
    if (v.status != 0) {
      if (v.status != 400 && v.status != 405 && v.status != 413) std::abort();
      return 0;
    }
    check_accepted(v.head);
    ++served;
  }
  return 0;
}
