// The viewer server against hostile clients (`microshadow view`, docs/viewer.md "Limits"; issue 35, item 3),
// on loopback with plain sockets, no browser: clients trickling their request head a byte a second neither
// block a normal GET nor hold a worker past the head deadline (408); a 50 MB POST and a GET announcing a body
// are refused at once (405, 413) without the server's resident memory growing; 10 000 header lines or a 20
// KiB line get 431; other methods 405 with Allow; a Range header is ignored; a symbolic link in --root
// leading out of it (to /etc/passwd, to /etc, to a file beside the root) serves nothing, a link within it is
// served, and a root given through a link is served. The server runs as a child process (`view --root` of a
// tiny copy: index.html and data/manifest.json are all --root checks, so it starts in a fraction of a
// second); its memory is read from /proc/<pid>/status.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "../src/view/request_head.h"
#include "../src/view/viewer_server.h"
#include "support/cli_test_util.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using msh::test::http_get;
using msh::test::url_port;
using msh::view::ServerLimits;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A field of /proc/<pid>/status in kB (VmRSS, VmHWM); -1 if absent.
long proc_kb(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return -1;
}

// Resets the peak resident size (VmHWM) of `pid` to its current one (Linux >= 4.0); false if not allowed.
bool reset_peak_rss(pid_t pid) {
  std::ofstream out("/proc/" + std::to_string(pid) + "/clear_refs");
  out << "5";
  out.flush();
  return bool(out);
}

// What one request got: the answer's first bytes (status line, headers, a body if short), how long the status
// line took from the first byte sent, how many body bytes went out, and the server's largest VmRSS sampled
// while sending.
struct Exchange {
  std::string answer;
  double ms = -1;
  std::size_t body_sent = 0;
  long max_rss_kb = -1;
  std::string status() const { return answer.substr(0, answer.find("\r\n")); }
};

// Sends `head` and then `body_bytes` bytes ('a') on a non-blocking socket, reading whenever the server
// answers; stops at the answer's end (the server closed), an error, or `timeout_ms`. VmRSS of `pid` is
// sampled every 64 KiB sent.
Exchange exchange(int port, const std::string& head, std::size_t body_bytes, pid_t pid,
                  int timeout_ms = 5000) {
  Exchange x;
  const int fd = msh::test::connect_loopback(port);
  if (fd < 0) return {"connect failed"};
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  const std::string chunk(65536, 'a');
  std::size_t head_sent = 0;
  bool writing = true;
  const auto t0 = Clock::now();
  while (ms_since(t0) < timeout_ms) {
    pollfd p{fd, short(POLLIN | (writing ? POLLOUT : 0)), 0};
    if (poll(&p, 1, 50) < 0) break;
    if (p.revents & (POLLIN | POLLHUP | POLLERR)) {
      char buf[65536];
      const ssize_t n = read(fd, buf, sizeof(buf));
      if (n > 0) {
        if (x.ms < 0) x.ms = ms_since(t0);
        x.answer.append(buf, std::size_t(n));
        continue;
      }
      if (n == 0 || (errno != EAGAIN && errno != EINTR)) break;  // closed (or reset) by the server
    }
    if (writing && (p.revents & POLLOUT)) {
      ssize_t n;
      if (head_sent < head.size()) {
        n = send(fd, head.data() + head_sent, head.size() - head_sent, MSG_NOSIGNAL);
        if (n > 0) head_sent += std::size_t(n);
      } else {
        n = send(fd, chunk.data(), std::min(chunk.size(), body_bytes - x.body_sent), MSG_NOSIGNAL);
        if (n > 0) x.body_sent += std::size_t(n);
        if (n > 0 && x.body_sent / 65536 != (x.body_sent - std::size_t(n)) / 65536)
          x.max_rss_kb = std::max(x.max_rss_kb, proc_kb(pid, "VmRSS"));
      }
      if (n < 0 && errno != EAGAIN && errno != EINTR) writing = false;  // the server closed its side
      if (head_sent == head.size() && x.body_sent == body_bytes) writing = false;
    }
  }
  close(fd);
  return x;
}

class ViewerLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = msh::test::scratch_dir("viewer_limits");
    // A minimal served copy (all --root checks for) with links in and out of it, served through a link to it.
    fs::create_directories(dir / "root" / "data");
    std::ofstream(dir / "root" / "index.html") << "<!doctype html><title>viewer</title>\n";
    std::ofstream(dir / "root" / "data" / "manifest.json") << "{}\n";
    std::ofstream(dir / "secret.txt") << "secret beside the root\n";
    fs::create_symlink("/etc/passwd", dir / "root" / "passwd");
    fs::create_directory_symlink("/etc", dir / "root" / "etc");
    fs::create_symlink(dir / "secret.txt", dir / "root" / "secret.txt");
    fs::create_symlink("../secret.txt", dir / "root" / "data" / "up.txt");
    fs::create_symlink("index.html", dir / "root" / "inner.html");
    fs::create_directory_symlink(dir / "root", dir / "root-link");
    server = msh::test::start_view({"--root", (dir / "root-link").string(), "--port", "0"}, dir);
    ASSERT_FALSE(server.url.empty());
    port = url_port(server.url);
    host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  }
  void TearDown() override {
    EXPECT_EQ(msh::test::stop_view(server, SIGTERM), 0) << msh::test::slurp(server.err);
    fs::remove_all(dir);
  }
  fs::path dir;
  msh::test::ViewServer server;
  int port = 0;
  std::string host;
};

// kSlow clients each trickle one byte of a request head per second: a normal GET still answers at once, and
// each slow client gets 408 and is closed once its head is kHeadSeconds late.
TEST_F(ViewerLimits, SlowClientsDoNotBlockOthers) {
  constexpr int kSlow = 8;
  static_assert(kSlow < ServerLimits::kWorkers);
  const std::string slow_head = "GET /index.html HTTP/1.1\r\n" + host + "X-Slow: " + std::string(64, 'a');
  struct Slow {
    int fd = -1;
    Clock::time_point opened;
    double closed_ms = -1;  // when the server closed it (-1: not within the trickle)
    std::string got;
  };
  std::vector<Slow> slow(kSlow);
  for (auto& s : slow) {
    s.fd = msh::test::connect_loopback(port);
    ASSERT_GE(s.fd, 0);
    s.opened = Clock::now();
  }
  // Trickles for at most kHeadSeconds + 4 s (the old server never closed them).
  std::thread trickle([&] {
    const auto t0 = Clock::now();
    for (std::size_t i = 0; ms_since(t0) < (ServerLimits::kHeadSeconds + 4) * 1000.0; ++i) {
      bool open = false;
      for (auto& s : slow) {
        if (s.closed_ms >= 0) continue;
        pollfd p{s.fd, POLLIN, 0};
        if (poll(&p, 1, 0) > 0) {
          char buf[1024];
          const ssize_t n = recv(s.fd, buf, sizeof(buf), MSG_DONTWAIT);
          if (n > 0) s.got.append(buf, std::size_t(n));
          if (n == 0 || (n < 0 && errno != EAGAIN)) s.closed_ms = ms_since(s.opened);
          if (s.closed_ms >= 0) continue;
        }
        if (send(s.fd, &slow_head[i % slow_head.size()], 1, MSG_NOSIGNAL | MSG_DONTWAIT) < 0 &&
            errno == EPIPE)
          s.closed_ms = ms_since(s.opened);
        open = open || s.closed_ms < 0;
      }
      if (!open) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(i == 0 ? 100 : 1000));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // all accepted, each holding a worker
  // A normal GET on its own connection, waiting at most 5 s for the answer.
  const Exchange x = exchange(port, "GET /index.html HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", 0,
                              server.pid, 5000);
  trickle.join();
  EXPECT_NE(x.status().find(" 200 "), std::string::npos) << "'" << x.status() << "' after " << x.ms << " ms";
  EXPECT_GE(x.ms, 0);
  EXPECT_LT(x.ms, 2000) << "a normal GET waited behind " << kSlow << " slow clients";
  std::printf("normal GET with %d slow clients: %.1f ms\n", kSlow, x.ms);
  double latest = 0;
  for (auto& s : slow) {
    EXPECT_GE(s.closed_ms, 0) << "a slow client was not closed";
    EXPECT_LT(s.closed_ms, (ServerLimits::kHeadSeconds + 2) * 1000.0);
    EXPECT_EQ(s.got.rfind("HTTP/1.1 408 ", 0), 0u) << s.got;
    latest = std::max(latest, s.closed_ms);
    close(s.fd);
  }
  std::printf("slow clients closed by the server after at most %.0f ms\n", latest);
}

// A 50 MB POST (405) and a GET announcing 50 MB (413) are answered right after their head; the server reads
// none of the body into memory (its peak resident size grows by less than 8 MB).
TEST_F(ViewerLimits, RequestBodiesAreRefusedUnread) {
  constexpr std::size_t kBody = 50u << 20;
  const long rss0 = proc_kb(server.pid, "VmRSS");
  ASSERT_GT(rss0, 0);
  const bool peak = reset_peak_rss(server.pid);
  long worst = rss0;
  for (const auto& [head, want] : std::vector<std::pair<std::string, std::string>>{
           {"POST /upload HTTP/1.1\r\n" + host + "Content-Length: " + std::to_string(kBody) + "\r\n\r\n",
            " 405 "},
           // The sweep's case: a Host the server refuses (403) still had its body read.
           {"POST / HTTP/1.1\r\nHost: evil.example\r\nContent-Length: " + std::to_string(kBody) + "\r\n\r\n",
            " 405 "},
           {"GET /index.html HTTP/1.1\r\n" + host + "Content-Length: " + std::to_string(kBody) + "\r\n\r\n",
            " 413 "},
           {"GET /index.html HTTP/1.1\r\n" + host + "Transfer-Encoding: chunked\r\n\r\n", " 413 "}}) {
    const Exchange x = exchange(port, head, kBody, server.pid);
    EXPECT_NE(x.status().find(want), std::string::npos) << head.substr(0, 40) << ": '" << x.status() << "'";
    EXPECT_GE(x.ms, 0);
    EXPECT_LT(x.ms, 1000) << head.substr(0, 40);
    if (want == " 405 ") {
      EXPECT_NE(x.answer.find("\r\nAllow: GET, HEAD\r\n"), std::string::npos) << x.answer;
    }
    worst = std::max(worst, x.max_rss_kb);
    std::printf("%s: '%s' after %.1f ms, %zu body bytes sent\n", head.substr(0, head.find("\r\n")).c_str(),
                x.status().c_str(), x.ms, x.body_sent);
  }
  if (peak) worst = std::max(worst, proc_kb(server.pid, "VmHWM"));
  worst = std::max(worst, proc_kb(server.pid, "VmRSS"));
  std::printf("server VmRSS %ld kB before; peak %ld kB (%s): +%ld kB\n", rss0, worst,
              peak ? "VmHWM after clear_refs" : "sampled", worst - rss0);
  EXPECT_LT(worst - rss0, 8 * 1024) << "the server buffered a request body";
  // Still serving.
  EXPECT_NE(http_get(server.url, "/index.html").first.find(" 200 "), std::string::npos);
}

// 10 000 header lines, or one line of 20 KiB: 431 at once.
TEST_F(ViewerLimits, OversizedHeadsGet431) {
  std::string many = "GET /index.html HTTP/1.1\r\n" + host;
  for (int i = 0; i < 10000; ++i) many += "X-H" + std::to_string(i) + ": v\r\n";
  many += "\r\n";
  const std::string longline =
      "GET /index.html HTTP/1.1\r\n" + host + "X-Long: " + std::string(20 * 1024, 'a') + "\r\n\r\n";
  for (const std::string* head : std::vector<const std::string*>{&many, &longline}) {
    const Exchange x = exchange(port, *head, 0, server.pid);
    EXPECT_NE(x.status().find(" 431 "), std::string::npos) << "'" << x.status() << "'";
    EXPECT_LT(x.ms, 1000);
    std::printf("head of %zu bytes: '%s' after %.1f ms\n", head->size(), x.status().c_str(), x.ms);
  }
  // At the limit: kMaxHeaderLines header lines (Host and Connection included) are served, one more is not.
  std::string full = "GET /index.html HTTP/1.1\r\n" + host + "Connection: close\r\n";
  for (int i = 2; i < ServerLimits::kMaxHeaderLines; ++i) full += "X-H" + std::to_string(i) + ": v\r\n";
  EXPECT_NE(exchange(port, full + "\r\n", 0, server.pid).status().find(" 200 "), std::string::npos);
  EXPECT_NE(exchange(port, full + "X-One-More: v\r\n\r\n", 0, server.pid).status().find(" 431 "),
            std::string::npos);
}

// Methods other than GET and HEAD: 405 with Allow; HEAD answers without a body; Range is ignored; two
// requests on one keep-alive connection are both answered.
TEST_F(ViewerLimits, MethodsRangeAndKeepAlive) {
  for (const char* m : {"DELETE", "PUT", "OPTIONS", "PATCH", "TRACE", "CONNECT"}) {
    const Exchange x =
        exchange(port, std::string(m) + " /index.html HTTP/1.1\r\n" + host + "\r\n", 0, server.pid);
    EXPECT_NE(x.status().find(" 405 "), std::string::npos) << m << ": " << x.status();
    EXPECT_NE(x.answer.find("\r\nAllow: GET, HEAD\r\n"), std::string::npos) << x.answer;
  }
  const std::string index = msh::test::slurp(dir / "root" / "index.html");
  const Exchange h =
      exchange(port, "HEAD /index.html HTTP/1.1\r\n" + host + "Connection: close\r\n\r\n", 0, server.pid);
  EXPECT_NE(h.status().find(" 200 "), std::string::npos) << h.status();
  EXPECT_EQ(h.answer.substr(h.answer.find("\r\n\r\n") + 4), "");
  const Exchange r = exchange(
      port, "GET /index.html HTTP/1.1\r\n" + host + "Range: bytes=0-1,0-1,0-1\r\nConnection: close\r\n\r\n",
      0, server.pid);
  EXPECT_NE(r.status().find(" 200 "), std::string::npos) << r.status();
  EXPECT_EQ(r.answer.substr(r.answer.find("\r\n\r\n") + 4), index);
  const std::string get = "GET /index.html HTTP/1.1\r\n" + host + "\r\n";
  const Exchange two =
      exchange(port, get + get.substr(0, get.size() - 2) + "Connection: close\r\n\r\n", 0, server.pid);
  std::size_t answers = 0;
  for (std::size_t p = 0; (p = two.answer.find("HTTP/1.1 200 ", p)) != std::string::npos; ++p) ++answers;
  EXPECT_EQ(answers, 2u) << two.answer;
}

// Links leading out of the root serve nothing (404); a link within it, and the root given through a link, do.
TEST_F(ViewerLimits, SymlinksOutOfTheRootServeNothing) {
  for (const char* p : {"/passwd", "/etc/passwd", "/etc/hostname", "/secret.txt", "/data/up.txt"}) {
    const auto [status, body] = http_get(server.url, p);
    EXPECT_NE(status.find(" 404 "), std::string::npos) << p << ": " << status;
    EXPECT_EQ(body.find("root:"), std::string::npos) << p;
    EXPECT_EQ(body.find("beside the root"), std::string::npos) << p;
  }
  const std::string index = msh::test::slurp(dir / "root" / "index.html");
  for (const char* p : {"/", "/index.html", "/inner.html"}) {
    const auto [status, body] = http_get(server.url, p);
    EXPECT_NE(status.find(" 200 "), std::string::npos) << p << ": " << status;
    EXPECT_EQ(body, index) << p;
  }
  EXPECT_NE(http_get(server.url, "/data/manifest.json").first.find(" 200 "), std::string::npos);
}

}  // namespace

// The head scan and verdict as pure functions (src/view/request_head.h; what fuzz/fuzz_http_head.cpp
// drives): a head arriving in pieces, pipelined heads, the line and byte limits, and judge_head on any
// string.
TEST(RequestHead, ScansPiecesAndPipelinedHeadsWithinTheLimits) {
  using msh::view::RequestHeadScanner;
  const std::string a = "GET /a HTTP/1.1\r\nHost: x\r\n\r\n", b = "HEAD /b HTTP/1.1\r\n\r\n";
  std::string pending, head;
  RequestHeadScanner s(ServerLimits::kMaxHeadBytes, ServerLimits::kMaxHeaderLines);
  const std::string stream = a + b;
  for (std::size_t i = 0; i + 1 < a.size(); ++i) {  // one byte at a time: no head before its last byte
    pending += stream[i];
    ASSERT_EQ(s.scan(pending, head), RequestHeadScanner::kNeedMore) << i;
  }
  pending += stream.substr(a.size() - 1);  // a's last byte and all of b in one piece
  ASSERT_EQ(s.scan(pending, head), RequestHeadScanner::kComplete);
  EXPECT_EQ(head, a);
  RequestHeadScanner s2(ServerLimits::kMaxHeadBytes, ServerLimits::kMaxHeaderLines);
  ASSERT_EQ(s2.scan(pending, head), RequestHeadScanner::kComplete);
  EXPECT_EQ(head, b);
  EXPECT_TRUE(pending.empty());

  // Limits: 100 header lines pass, 101 get 431; a head over the byte limit gets 431 before its end.
  auto with_lines = [](int n) {
    std::string h = "GET / HTTP/1.1\r\n";
    for (int i = 0; i < n; ++i) h += "X: 1\r\n";
    return h + "\r\n";
  };
  for (const auto& [lines, want] : {std::pair{100, RequestHeadScanner::kComplete}, std::pair{101, 431}}) {
    std::string p = with_lines(lines), h;
    EXPECT_EQ(RequestHeadScanner(ServerLimits::kMaxHeadBytes, ServerLimits::kMaxHeaderLines).scan(p, h), want)
        << lines;
  }
  std::string big = "GET / HTTP/1.1\r\nX: " + std::string(ServerLimits::kMaxHeadBytes, 'a'), h;
  EXPECT_EQ(RequestHeadScanner(ServerLimits::kMaxHeadBytes, ServerLimits::kMaxHeaderLines).scan(big, h), 431);

  // The verdict: Range dropped, bodies and other methods refused; a string that is not a whole head (no
  // CRLF, or no blank line) ends, where the first version looped on it.
  using msh::view::judge_head;
  EXPECT_EQ(judge_head("GET / HTTP/1.1\r\nRange: bytes=0-1\r\nHost: x\r\n\r\n").head,
            "GET / HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(judge_head("GET / HTTP/1.1\r\nContent-Length: 3\r\n\r\n").status, 413);
  EXPECT_EQ(judge_head("GET / HTTP/1.1\r\ntransfer-encoding : chunked\r\n\r\n").status, 413);
  EXPECT_EQ(judge_head("GET / HTTP/1.1\r\nContent-Length: 0\r\n\r\n").status, 0);
  EXPECT_EQ(judge_head("PUT / HTTP/1.1\r\n\r\n").status, 405);
  EXPECT_EQ(judge_head(" / HTTP/1.1\r\n\r\n").status, 400);
  EXPECT_EQ(judge_head("GET / HTTP/1.1").head, "GET / HTTP/1.1\r\n\r\n");
  EXPECT_EQ(judge_head("GET / HTTP/1.1\r\nHost: x").head, "GET / HTTP/1.1\r\nHost: x\r\n\r\n");
}
