// The browser tests' shared helpers (test_viewer_browser, test_three_browser, test_three_directional_browser,
// test_gltf_validator): where their parts are, whether node, its npm packages and headless chromium can run,
// a `microshadow view ...` process, a node driver run against a served folder, and plain-socket HTTP GETs.
// Header-only; needs MSH_CLI_PATH and MSH_BINARY_DIR.
#pragma once

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "support/cli_test_util.h"

namespace msh::test {

// The node drivers and their npm packages (`npm ci` in tests/browser), three.js as integrations/three
// installs it, and the built-in plaster's cache that the viewer and three.js tests share (generated once).
inline const std::filesystem::path kBrowserDir = std::filesystem::path(MSH_SOURCE_DIR) / "tests" / "browser";
inline const std::filesystem::path kThreeDir =
    std::filesystem::path(MSH_SOURCE_DIR) / "integrations" / "three" / "node_modules" / "three";
inline const std::filesystem::path kViewerCache = std::filesystem::path(MSH_BINARY_DIR) / "viewer_cache";

inline std::string chromium_path() {
  const char* e = std::getenv("MSH_CHROMIUM");
  return e && *e ? e : "/usr/bin/chromium";
}

// Why node with the npm package `package` (npm ci in browser_dir) cannot run here ("" = it can).
inline std::string missing_node_package(const std::filesystem::path& browser_dir,
                                        const std::string& package) {
  if (std::system("node --version > /dev/null 2>&1") != 0) return "no node on PATH (Debian package nodejs)";
  if (!std::filesystem::exists(browser_dir / "node_modules" / package / "package.json"))
    return package + " is not installed: run `npm ci` in tests/browser (scripts/install-deps.sh does)";
  return "";
}

// Why headless chromium with playwright-core (npm ci in browser_dir) cannot run here ("" = it can).
inline std::string missing_browser_driver(const std::filesystem::path& browser_dir) {
  if (access(chromium_path().c_str(), X_OK) != 0)
    return "no chromium at " + chromium_path() + " (Debian package chromium)";
  return missing_node_package(browser_dir, "playwright-core");
}

// The same for kBrowserDir, and three.js installed in integrations/three (kThreeDir).
inline std::string missing_three_browser() {
  const std::string why = missing_browser_driver(kBrowserDir);
  if (!why.empty()) return why;
  if (!std::filesystem::exists(kThreeDir / "package.json"))
    return "three is not installed: run `npm ci` in integrations/three (scripts/install-deps.sh does)";
  return "";
}

// Fails the test with `why` unless MSH_ALLOW_NO_BROWSER=1 (then skips); nothing when why is empty.
#define MSH_REQUIRE_BROWSER(why_expr)                                             \
  do {                                                                            \
    const std::string why_ = (why_expr);                                          \
    if (!why_.empty()) {                                                          \
      const char* allow_ = std::getenv("MSH_ALLOW_NO_BROWSER");                   \
      if (allow_ && std::string(allow_) == "1") GTEST_SKIP() << why_;             \
      FAIL() << why_ << " (set MSH_ALLOW_NO_BROWSER=1 to skip the browser test)"; \
    }                                                                             \
  } while (0)

// A `microshadow view ...` process with stdout/stderr in files; the URL from its first line.
struct ViewServer {
  pid_t pid = -1;
  std::filesystem::path out, err;
  std::string url;
};

inline ViewServer start_view(const std::vector<std::string>& args, const std::filesystem::path& dir) {
  ViewServer s;
  s.out = dir / "server.out";
  s.err = dir / "server.err";
  s.pid = fork();
  if (s.pid == 0) {
    if (!freopen(s.out.c_str(), "w", stdout) || !freopen(s.err.c_str(), "w", stderr)) _exit(127);
    std::vector<char*> argv;
    std::vector<std::string> all = {MSH_CLI_PATH, "view"};
    all.insert(all.end(), args.begin(), args.end());
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(MSH_CLI_PATH, argv.data());
    _exit(127);
  }
  // The server prints its URL once it serves (the default tables bake at start-up: seconds; the plaster is
  // generated on the first run only).
  for (int i = 0; i < 3000; ++i) {
    const std::string o = slurp(s.out);
    const auto p = o.find("http://");
    if (p != std::string::npos && o.find(' ', p) != std::string::npos) {
      s.url = o.substr(p, o.find(' ', p) - p);
      return s;
    }
    int status = 0;
    if (waitpid(s.pid, &status, WNOHANG) == s.pid) {
      s.pid = -1;
      ADD_FAILURE() << "the server exited: " << slurp(s.err);
      return s;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ADD_FAILURE() << "the server printed no URL in 300 s";
  return s;
}

// The signal (Ctrl-C by default), then the exit code (−1: did not exit in 30 s, or not normally).
inline int stop_view(ViewServer& s, int sig = SIGINT) {
  if (s.pid <= 0) return -1;
  kill(s.pid, sig);
  for (int i = 0; i < 300; ++i) {
    int status = 0;
    if (waitpid(s.pid, &status, WNOHANG) == s.pid) {
      s.pid = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(s.pid, SIGKILL);
  waitpid(s.pid, nullptr, 0);
  s.pid = -1;
  return -1;
}

// Serves `root` (`microshadow view --root ROOT --port 0`), runs `node SCRIPT --url URL ARGS --chromium PATH`
// in kBrowserDir with its output in dir/node.out, then stops the server with Ctrl-C: "" when the server
// printed its URL, the driver exited 0 and so did the server; else what failed, with its output.
inline std::string serve_and_drive(const std::filesystem::path& root, const std::string& script,
                                   const std::string& args, const std::filesystem::path& dir) {
  ViewServer server = start_view({"--root", root.string(), "--port", "0"}, dir);
  if (server.url.empty()) return "the server printed no URL: " + slurp(server.err);
  const std::filesystem::path out = dir / "node.out";
  const std::string cmd = "cd " + kBrowserDir.string() + " && node " + script + " --url " + server.url + " " +
                          args + " --chromium " + chromium_path() + " > " + out.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const int code = stop_view(server);
  std::string why;
  if (code != 0) why = "the server exited " + std::to_string(code) + ": " + slurp(server.err);
  if (rc != 0) why += (why.empty() ? "" : "\n") + std::string("the driver failed: ") + slurp(out);
  return why;
}

inline int url_port(const std::string& url) { return std::stoi(url.substr(url.rfind(':') + 1)); }

// A TCP connection to 127.0.0.1:port (-1 when refused).
inline int connect_loopback(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

// GET path over a plain socket (HTTP/1.0) with this Host header (nullopt: none): the status line and the
// body.
inline std::pair<std::string, std::string> http_get_host(const std::string& url, const std::string& path,
                                                         const std::optional<std::string>& host) {
  const int fd = connect_loopback(url_port(url));
  if (fd < 0) return {"connect failed", ""};
  const std::string req = "GET " + path + " HTTP/1.0\r\n" + (host ? "Host: " + *host + "\r\n" : "") + "\r\n";
  if (write(fd, req.data(), req.size()) != ssize_t(req.size())) {
    close(fd);
    return {"write failed", ""};
  }
  std::string resp;
  char buf[65536];
  for (ssize_t n; (n = read(fd, buf, sizeof(buf))) > 0;) resp.append(buf, std::size_t(n));
  close(fd);
  const auto eol = resp.find("\r\n"), body = resp.find("\r\n\r\n");
  return {resp.substr(0, eol), body == std::string::npos ? "" : resp.substr(body + 4)};
}

// GET path with the Host header a browser sends for the URL.
inline std::pair<std::string, std::string> http_get(const std::string& url, const std::string& path) {
  return http_get_host(url, path, "127.0.0.1:" + std::to_string(url_port(url)));
}

}  // namespace msh::test
