// The viewer's request-head scan and verdict (request_head.h).
#include "request_head.h"

#include <algorithm>
#include <cctype>

namespace msh::view {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

}  // namespace

int RequestHeadScanner::scan(std::string& pending, std::string& head) {
  for (std::size_t p; (p = pending.find("\r\n", scanned_)) != std::string::npos;) {
    if (p == scanned_ && lines_ > 0 && pending.compare(p - 2, 2, "\r\n") == 0) {  // "\r\n\r\n"
      head = pending.substr(0, p + 2);
      pending.erase(0, p + 2);
      scanned_ = 0, lines_ = 0;
      return kComplete;
    }
    if (++lines_ > max_lines_ + 1) return 431;  // the request line + the header lines
    scanned_ = p + 2;
    if (scanned_ > max_bytes_) return 431;
  }
  if (pending.size() > max_bytes_) return 431;
  return kNeedMore;
}

HeadVerdict judge_head(const std::string& head) {
  HeadVerdict v;
  std::size_t pos = head.find("\r\n");
  const std::string line = head.substr(0, pos);
  const std::string method = line.substr(0, line.find(' '));
  if (method != "GET" && method != "HEAD") {
    v.status = method.empty() ? 400 : 405;
    return v;
  }
  v.head = line + "\r\n";
  for (pos = pos == std::string::npos ? head.size() : pos + 2; pos < head.size();) {
    std::size_t e = head.find("\r\n", pos);
    if (e == std::string::npos) e = head.size();
    const std::string h = head.substr(pos, e - pos);
    pos = e + 2;
    if (h.empty()) break;  // the blank line ending the head
    const std::size_t colon = h.find(':');
    const std::string name = colon == std::string::npos ? "" : lower(trim(h.substr(0, colon)));
    const std::string value = colon == std::string::npos ? "" : trim(h.substr(colon + 1));
    if (name == "transfer-encoding" || (name == "content-length" && value != "0")) {
      v.status = 413;
      return v;
    }
    if (name == "range" || name == "if-range") continue;
    v.head += h + "\r\n";
  }
  v.head += "\r\n";
  return v;
}

}  // namespace msh::view
