// The viewer's own reading of an HTTP/1.1 request head (docs/viewer.md, "Limits"): the incremental scan for
// the head's end within ServerLimits, and the verdict on a complete head. Pure functions on bytes (no
// sockets), so that the server and the fuzz target (fuzz/fuzz_http_head.cpp) run the same code.
#pragma once

#include <cstddef>
#include <string>

namespace msh::view {

// Finds the end of one request head ("\r\n\r\n") in bytes that arrive in pieces. scan() is called after each
// piece is appended to `pending` (which may also hold bytes left over from the previous request):
//  kComplete: the head, its blank line included, is moved from the front of `pending` into `head`;
//  kNeedMore: no complete head yet, within the limits;
//  431: more than max_bytes before the head's end, or more than max_lines header lines.
// A new scanner for every head.
class RequestHeadScanner {
 public:
  static constexpr int kComplete = 0;
  static constexpr int kNeedMore = -1;
  RequestHeadScanner(std::size_t max_bytes, int max_lines) : max_bytes_(max_bytes), max_lines_(max_lines) {}
  int scan(std::string& pending, std::string& head);

 private:
  std::size_t max_bytes_;
  int max_lines_;
  std::size_t scanned_ = 0;  // pending[0, scanned_) holds no "\r\n\r\n"
  int lines_ = 0;            // "\r\n" seen in pending[0, scanned_)
};

// A complete request head judged: status 0 and the head cpp-httplib gets (the request line and the header
// lines, Range and If-Range dropped: answered whole, so no multi-range answer many times a file's size), or
// the status to refuse it with (400: no method; 405: a method other than GET or HEAD; 413: a body announced
// by Transfer-Encoding or a Content-Length other than 0).
struct HeadVerdict {
  int status = 0;
  std::string head;
};
HeadVerdict judge_head(const std::string& head);

}  // namespace msh::view
