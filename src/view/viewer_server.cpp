// The browser viewer's content and HTTP server (docs/viewer.md). cpp-httplib (header-only) serves it.
#include "viewer_server.h"

#include <Imath/half.h>
#include <arpa/inet.h>
#include <fmt/format.h>
#include <httplib.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/texture_gen.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <thread>
#include <vector>

#include "request_head.h"
#include "shader_source.h"

namespace fs = std::filesystem;

namespace msh::view {
namespace {

// The built-in texture set: gen-material --kind plaster --size 512 (other options default, so with the
// directional channels).
constexpr int kPlasterSize = 512;

struct Blob {
  std::string bytes, type;
};

std::string read_bytes(const fs::path& p) {
  require_regular_file(p);
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(fmt::format("cannot read '{}'", p.string()));
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string mime_type(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".gltf") return "model/gltf+json";
  if (ext == ".png") return "image/png";
  if (ext == ".glsl" || ext == ".txt" || ext == ".md") return "text/plain; charset=utf-8";
  return "application/octet-stream";
}

// A request path whose every component is a plain name (no "..", no hidden files, no odd characters).
bool safe_relative_path(const std::string& p) {
  static const std::regex component("[A-Za-z0-9_][A-Za-z0-9_.-]*");
  if (p.empty()) return false;
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = std::min(p.find('/', start), p.size());
    if (!std::regex_match(p.substr(start, end - start), component)) return false;
    if (p.compare(start, end - start, "..") == 0) return false;
    start = end + 1;
  }
  return true;
}

// The built-in plaster, generated once into cache/viewer-plaster-512 (written beside it, then renamed).
fs::path ensure_plaster(const fs::path& cache) {
  // "-d21": with the 21 directional channels of the view correction (a cache written before lacks them).
  const fs::path dir = cache / fmt::format("viewer-plaster-{}-d21", kPlasterSize);
  if (fs::exists(dir / "material.json")) return dir;
  std::error_code ec;
  fs::create_directories(cache, ec);
  if (ec)
    throw InputError(fmt::format("cannot create the cache directory '{}': {}", cache.string(), ec.message()));
  fmt::print(stderr, "microshadow view: generating the built-in plaster texture set ({}x{}, once) in '{}'\n",
             kPlasterSize, kPlasterSize, dir.string());
  render::GenOptions g;
  g.kind = "plaster";
  g.size = kPlasterSize;
  g.directional_view = true;
  const render::TextureSet set = render::generate_texture_set(g);
  const fs::path tmp = cache / fmt::format("viewer-plaster-{}-d21.tmp-{}", kPlasterSize, ::getpid());
  fs::remove_all(tmp, ec);
  render::write_texture_set(tmp, set);
  fs::rename(tmp, dir, ec);
  if (ec) {  // another process won the race: keep its copy
    fs::remove_all(tmp, ec);
    if (!fs::exists(dir / "material.json"))
      throw InputError(fmt::format("cannot write the built-in plaster into '{}'", dir.string()));
  }
  return dir;
}

uint16_t half_bits(float f) { return Imath::half(f).bits(); }

// The directional channels (occlusion/directional.h) as the page samples them: a 2D array texture of
// RGBA16F layers, channels 4k..4k+3 in layer k (9 channels: three layers, the third holding channel 8 in R;
// 21 with the view correction: six, the last holding channel 20 in R), with its box mip chain
// (render::box_mip_chain: the mean of a channel is the coarse texel's own channel, so the GPU's trilinear
// fetch is right at every scale). One blob: level after level, each layer after layer, rows of RGBA half
// floats (little-endian).
nlohmann::json add_directional(const fs::path& file, std::map<std::string, Blob>& data) {
  const render::Texture fine = render::load_directional_channels(file);  // InputError naming the file
  const std::vector<render::Texture> chain = render::box_mip_chain(fine);
  const int channels = fine.channels(), layers = (channels + 3) / 4;
  std::string bytes;
  nlohmann::json levels = nlohmann::json::array();
  for (const render::Texture& t : chain) {
    levels.push_back({t.width(), t.height()});
    for (int layer = 0; layer < layers; ++layer)
      for (int y = 0; y < t.height(); ++y)
        for (int x = 0; x < t.width(); ++x)
          for (int c = 0; c < 4; ++c) {
            const int k = 4 * layer + c;
            const uint16_t b = half_bits(k < channels ? t.at(x, y, k) : 0.0f);
            bytes.push_back(char(b & 0xff));
            bytes.push_back(char(b >> 8));
          }
  }
  const std::string url = "data/material/directional.f16";
  data[url] = {std::move(bytes), "application/octet-stream"};
  return {{"url", url},
          {"layers", layers},
          {"channels", channels},
          {"levels", levels},
          {"encoding", "float16-le"}};
}

// The texture set's PNG files, validated (each decodes; the browser reads PNG only).
void add_material(const fs::path& dir, bool builtin, std::map<std::string, Blob>& data, nlohmann::json& man) {
  const fs::path mj = dir / "material.json";
  if (!fs::is_regular_file(mj))
    throw InputError(
        fmt::format("'{}' is not a texture set: no material.json (make one with microshadow "
                    "gen-material --out DIR)",
                    dir.string()));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_bytes(mj));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("'{}': not valid JSON ({})", mj.string(), e.what()));
  }
  nlohmann::json m = {
      {"name", builtin ? fmt::format("plaster (built-in, {}²)", kPlasterSize) : dir.string()}};
  for (const char* key : {"base_color", "normal", "roughness", "metallic", "micro_occlusion"}) {
    const bool optional = std::string(key) == "metallic";
    if (!j.contains(key) || !j[key].is_string()) {
      if (optional) continue;
      throw InputError(fmt::format("'{}' has no \"{}\" texture", mj.string(), key));
    }
    const fs::path f = dir / j[key].get<std::string>();
    if (!fs::is_regular_file(f))
      throw InputError(fmt::format("'{}': the {} texture '{}' is missing", mj.string(), key, f.string()));
    std::string ext = f.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".png")
      throw InputError(
          fmt::format("'{}': the viewer reads PNG textures only (browsers decode no EXR)", f.string()));
    (void)io::read_image(f);  // InputError naming the file if it does not decode
    const std::string url = fmt::format("data/material/{}.png", key);
    data[url] = {read_bytes(f), "image/png"};
    m[key] = url;
  }
  if (j.contains("height_texels") && j["height_texels"].is_number()) m["height_texels"] = j["height_texels"];
  if (j.contains("directional") && j["directional"].is_string()) {
    m["directional"] = add_directional(dir / j["directional"].get<std::string>(), data);
    // The view correction's channels too: what the directional-view forms (texel "directional_view") read.
    if (m["directional"]["channels"] == directional::kViewChannels) m["directional_view"] = true;
  }
  man["material"] = m;
}

// Raw little-endian half floats (IEEE binary16), x fastest, channels interleaved.
std::string to_half_bytes(const io::Volume& v) {
  std::string out(v.data.size() * 2, '\0');
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    const uint16_t b = half_bits(v.data[i]);
    out[2 * i] = char(b & 0xff);
    out[2 * i + 1] = char(b >> 8);
  }
  return out;
}

// The GLSL cone sampler (shaders/glsl/micro_shadowing.glsl) has the baker's default warps as constants.
bool default_cone_params(const lut::ConeLayoutParams& c) {
  const lut::ConeLayoutParams d;
  return c.roughness_min == d.roughness_min && c.roughness_max == d.roughness_max &&
         c.roughness_power == d.roughness_power && c.warp_scale == d.warp_scale && c.nl_warp == d.nl_warp &&
         c.nv_warp == d.nv_warp && c.nv_scale == d.nv_scale && c.top_scale == d.top_scale;
}

void add_lut(const std::string& name, const lut::MicroShadowingLut& t, const std::string& sidecar,
             const std::string& source, std::map<std::string, Blob>& data, nlohmann::json& man) {
  const std::string url = fmt::format("data/{}.f16", name), side = fmt::format("data/{}.json", name);
  data[url] = {to_half_bytes(t.volume), "application/octet-stream"};
  data[side] = {sidecar, "application/json"};
  const auto& v = t.volume;
  man["luts"][name] = {{"url", url},
                       {"sidecar", side},
                       {"source", source},
                       {"layout", lut::layout_name(t.layout)},
                       {"size", {v.width, v.height, v.depth}},
                       {"channels", v.channels},
                       {"roughness_slabs", t.n_rough},
                       {"n_dot_v_size", t.n_rough > 0 ? v.depth / t.n_rough : v.depth},
                       {"harmonics", t.harmonics},
                       {"encoding", "float16-le"}};
}

// The three default tables (cone layout: 3D, the 2D N·V = 1 slice, azimuth-aware with 3 harmonics); --lut
// replaces the one of its kind.
void add_luts(const ViewerOptions& o, std::map<std::string, Blob>& data, nlohmann::json& man) {
  struct Slot {
    const char* name;
    bool two_d;
    int harmonics;
  };
  std::string user_slot;
  std::unique_ptr<lut::MicroShadowingLut> user;
  if (!o.lut.empty()) {
    user = std::make_unique<lut::MicroShadowingLut>(lut::load_micro_shadowing_lut(o.lut));
    if (user->layout != lut::LutLayout::Cone)
      throw InputError(
          fmt::format("'{}' is a seed-layout table; the viewer samples cone-layout tables "
                      "(bake micro-shadowing --layout cone, the default)",
                      o.lut.string()));
    if (!default_cone_params(user->cone))
      throw InputError(
          fmt::format("'{}' was baked with non-default cone warps or roughness range; the "
                      "viewer's GLSL (shaders/glsl/micro_shadowing.glsl) has the defaults as "
                      "constants",
                      o.lut.string()));
    const int n_nv = user->volume.depth / std::max(1, user->n_rough);
    user_slot = user->harmonics > 0 ? "lut_azimuth" : n_nv == 1 ? "lut2d" : "lut3d";
    if (user_slot == "lut_azimuth" && n_nv == 1)
      throw InputError(
          fmt::format("'{}': a 2D azimuth-aware table is not supported by the viewer", o.lut.string()));
  }
  for (const Slot s : {Slot{"lut3d", false, 0}, Slot{"lut2d", true, 0}, Slot{"lut_azimuth", false, 3}}) {
    if (s.name == user_slot) {
      add_lut(s.name, *user, read_bytes(lut::sidecar_path(o.lut)), o.lut.string(), data, man);
      continue;
    }
    lut::BakeOptions b = lut::default_bake_options(lut::LutLayout::Cone, s.harmonics);
    b.two_d = s.two_d;
    add_lut(s.name, *lut::default_micro_shadowing_lut(s.two_d, s.harmonics), lut::sidecar_json(b),
            "default (baked at start-up)", data, man);
  }
}

// *.glsl in dir, sorted (the page concatenates them in this order; each file has include guards).
std::vector<std::string> glsl_files(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && e.path().extension() == ".glsl") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

struct Content {
  std::map<std::string, Blob> data;  // "data/..." in memory
  nlohmann::json manifest;           // without "glsl" (listed per request)
};

void check_assets(const fs::path& assets) {
  if (!fs::is_regular_file(assets / "web" / "index.html") || !fs::is_directory(assets / "shaders" / "glsl"))
    throw InputError(fmt::format("the viewer's files (web/index.html, shaders/glsl/) are not under '{}'",
                                 assets.string()));
}

Content build_content(const ViewerOptions& o) {
  check_assets(o.assets);
  Content c;
  c.manifest = {{"version", MSH_VERSION}};
  const bool builtin = o.material.empty();
  if (!builtin) add_material(o.material, false, c.data, c.manifest);  // cheap checks first
  add_luts(o, c.data, c.manifest);
  if (builtin)
    add_material(ensure_plaster(o.cache.empty() ? default_cache_dir() : o.cache), true, c.data, c.manifest);
  return c;
}

// The regular file `rel` (a safe_relative_path) under `base`, every symbolic link resolved, if it stays
// inside base's own canonical path; nothing otherwise (a link out of the folder, a missing file, not a
// regular file).
std::optional<fs::path> contained_file(const fs::path& base, const std::string& rel) {
  std::error_code ec;
  const fs::path root = fs::canonical(base, ec);
  if (ec) return std::nullopt;
  const fs::path file = fs::canonical(root / rel, ec);
  if (ec) return std::nullopt;
  const auto [r, f] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  if (r != root.end() || !fs::is_regular_file(file, ec)) return std::nullopt;
  return file;
}

// ---- The request guard (ServerLimits in viewer_server.h, docs/viewer.md "Limits") ----
// cpp-httplib 0.11 reads a request line and header lines of any length and any number, one recv at a time
// with a per-read timeout (a client trickling a byte a second holds a worker forever), and reads a request
// body before answering a handler-less method. So the viewer reads each request head itself, with a deadline
// for the whole head, and hands httplib only a complete head it accepts (httplib::Server::process_request on
// a stream holding that head: no body byte is ever read).

using Clock = std::chrono::steady_clock;
using Limits = ServerLimits;

// Waits until `fd` is ready for `events` (POLLIN or POLLOUT) or `deadline` passes (then false), in slices of
// at most 100 ms so that `stop()` (checked between slices) ends the wait early.
bool wait_ready(int fd, short events, Clock::time_point deadline, const std::function<bool()>& stop) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0 || (stop && stop())) return false;
    pollfd p{fd, events, 0};
    const int r = ::poll(&p, 1, int(std::min<long long>(left, 100)));
    if (r > 0) return true;  // ready, or an error / hang-up the next recv or send reports
    if (r < 0 && errno != EINTR) return false;
  }
}

const char* refusal_text(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 413:
      return "Payload Too Large";
    default:
      return "Request Header Fields Too Large";
  }
}

std::string refusal_body(int status) {
  switch (status) {
    case 405:
      return "method not allowed: the viewer serves GET and HEAD only\n";
    case 413:
      return "payload too large: the viewer takes no request body\n";
    case 408:
      return fmt::format("request timeout: the request head must arrive within {} s\n", Limits::kHeadSeconds);
    case 431:
      return fmt::format("request header fields too large: at most {} bytes and {} header lines\n",
                         Limits::kMaxHeadBytes, Limits::kMaxHeaderLines);
    default:
      return "bad request\n";
  }
}

// A stream over one accepted request head (read) and the socket (write, each answer taken by the client
// within kAnswerSeconds of its first byte; the handler's own time, e.g. a first bake or a slow machine
// preparing a large file, does not count): what httplib::Server::process_request parses and answers.
class HeadStream final : public httplib::Stream {
 public:
  HeadStream(socket_t sock, std::string head) : sock_(sock), head_(std::move(head)) {}
  bool is_readable() const override { return pos_ < head_.size(); }
  bool is_writable() const override {
    if (!started_) started_ = true, deadline_ = Clock::now() + std::chrono::seconds(Limits::kAnswerSeconds);
    return wait_ready(sock_, POLLOUT, deadline_, nullptr);
  }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, head_.size() - pos_);
    std::memcpy(ptr, head_.data() + pos_, n);
    pos_ += n;
    return ssize_t(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    ssize_t n;
    do n = ::send(sock_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
    while (n < 0 && errno == EINTR);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return 0;  // write_data tries again
    return n;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override { address(true, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address(false, ip, port); }
  socket_t socket() const override { return sock_; }

 private:
  void address(bool peer, std::string& ip, int& port) const {
    sockaddr_storage a{};
    socklen_t len = sizeof(a);
    const int r = peer ? getpeername(sock_, reinterpret_cast<sockaddr*>(&a), &len)
                       : getsockname(sock_, reinterpret_cast<sockaddr*>(&a), &len);
    char buf[INET6_ADDRSTRLEN] = "";
    port = 0;
    if (r == 0 && a.ss_family == AF_INET) {
      const auto* in = reinterpret_cast<const sockaddr_in*>(&a);
      inet_ntop(AF_INET, &in->sin_addr, buf, sizeof(buf));
      port = ntohs(in->sin_port);
    } else if (r == 0 && a.ss_family == AF_INET6) {
      const auto* in = reinterpret_cast<const sockaddr_in6*>(&a);
      inet_ntop(AF_INET6, &in->sin6_addr, buf, sizeof(buf));
      port = ntohs(in->sin6_port);
    }
    ip = buf;
  }

  socket_t sock_;
  std::string head_;
  std::size_t pos_ = 0;
  mutable bool started_ = false;
  mutable Clock::time_point deadline_;
};

// httplib's server with the request guard: every accepted connection goes through process_and_close_socket
// (virtual in httplib::Server), which reads and judges each request head before httplib sees it.
class GuardedServer final : public httplib::Server {
 private:
  bool stopping() const { return svr_sock_ == INVALID_SOCKET; }

  // Reads the next request head into `head` (bytes past it stay in `pending`): 0, or the status to refuse
  // with (431, 408), or -1 when the client closed or sent nothing before the deadline (closed quietly).
  int read_head(socket_t sock, std::string& pending, std::string& head) const {
    const Clock::time_point deadline = Clock::now() + std::chrono::seconds(Limits::kHeadSeconds);
    RequestHeadScanner scanner(Limits::kMaxHeadBytes, Limits::kMaxHeaderLines);
    char buf[4096];
    for (;;) {
      // The head so far: complete, or over a limit?
      if (const int status = scanner.scan(pending, head); status != RequestHeadScanner::kNeedMore)
        return status;
      if (!wait_ready(sock, POLLIN, deadline, [this] { return stopping(); }))
        return pending.empty() ? -1 : 408;
      ssize_t n;
      do
        n = ::recv(sock, buf, std::min(sizeof(buf), Limits::kMaxHeadBytes + 1 - pending.size()),
                   MSG_DONTWAIT);
      while (n < 0 && errno == EINTR);
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) continue;
      if (n <= 0) return -1;
      pending.append(buf, std::size_t(n));
    }
  }

  // The refusal (one line of text, Connection: close); then the connection is closed after reading and
  // discarding what the client still sends for at most 0.5 s or 1 MiB, so that it sees the answer rather than
  // a reset.
  static void refuse(socket_t sock, int status) {
    const std::string body = refusal_body(status);
    const std::string msg = fmt::format(
        "HTTP/1.1 {} {}\r\nContent-Type: text/plain\r\nContent-Length: {}\r\nCache-Control: no-store\r\n{}"
        "Connection: close\r\n\r\n{}",
        status, refusal_text(status), body.size(), status == 405 ? "Allow: GET, HEAD\r\n" : "", body);
    const Clock::time_point deadline = Clock::now() + std::chrono::seconds(1);
    for (std::size_t off = 0; off < msg.size() && wait_ready(sock, POLLOUT, deadline, nullptr);) {
      const ssize_t n = ::send(sock, msg.data() + off, msg.size() - off, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) break;
      if (n > 0) off += std::size_t(n);
    }
    ::shutdown(sock, SHUT_WR);
    const Clock::time_point drain = Clock::now() + std::chrono::milliseconds(500);
    char buf[4096];
    for (std::size_t total = 0; total < (1u << 20) && wait_ready(sock, POLLIN, drain, nullptr);) {
      const ssize_t n = ::recv(sock, buf, sizeof(buf), MSG_DONTWAIT);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) break;
      if (n > 0) total += std::size_t(n);
    }
  }

  bool process_and_close_socket(socket_t sock) override {
    std::string pending;
    bool ok = true;
    for (int served = 0; served < Limits::kKeepAliveRequests && !stopping(); ++served) {
      std::string head;
      int status = read_head(sock, pending, head);
      if (status < 0) break;
      HeadVerdict v;
      if (status == 0) {
        v = judge_head(head);
        status = v.status;
      }
      if (status != 0) {
        refuse(sock, status);
        break;
      }
      HeadStream strm(sock, std::move(v.head));
      bool closed = false;
      ok = process_request(strm, served + 1 == Limits::kKeepAliveRequests, closed, nullptr);
      if (!ok || closed) break;
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return ok;
  }
};

void check_host(const std::string& host) {
  if (!is_loopback_host(host))
    throw InputError(
        fmt::format("--host must be a loopback address (127.0.0.1, ::1 or localhost): the viewer "
                    "serves this machine only; got '{}'",
                    host));
}

}  // namespace

bool is_loopback_host(const std::string& host) {
  if (host == "localhost" || host == "::1" || host == "[::1]") return true;
  static const std::regex v4("127\\.([0-9]{1,3})\\.([0-9]{1,3})\\.([0-9]{1,3})");
  std::smatch m;
  if (!std::regex_match(host, m, v4)) return false;
  for (int i = 1; i <= 3; ++i)
    if (std::stoi(m[i].str()) > 255) return false;
  return true;
}

fs::path default_cache_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "microshadow";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "microshadow";
  return fs::temp_directory_path() / "microshadow";
}

bool is_allowed_host_header(const std::string& host_header, int port) {
  std::string h = host_header;
  std::transform(h.begin(), h.end(), h.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  // "[v6]:port" or "name:port"; the port part is optional only for port 80 (browsers omit the default).
  const std::size_t colon = h.rfind(':');
  const bool bracketed = !h.empty() && h.front() == '[';
  const std::size_t end = bracketed ? h.find(']') + 1 : colon == std::string::npos ? h.size() : colon;
  if (end == 0 || end > h.size()) return false;
  const std::string name = h.substr(0, end), rest = h.substr(end);
  if (rest.empty() ? port != 80 : rest != fmt::format(":{}", port)) return false;
  return name == "localhost" || name == "[::1]" ||
         (name.find(':') == std::string::npos && is_loopback_host(name));
}

std::string bump_methods_js() {
  std::string out =
      "// Generated by `microshadow view` from the bump-terminator registry (include/microshadow/occlusion/\n"
      "// bump_terminator.h, bump::kMethods). Not in the source tree. { id, label, glsl, requires? } with "
      "glsl\n"
      "// a float expression over vec3 ng (geometric normal), ns (normal-mapped), wl (towards the light), "
      "world\n"
      "// space, and bool u_bump_hemi (hemisphere test); requires the GLSL function it calls.\n"
      "export const BUMP_TERMINATOR_METHODS = [\n";
  for (const bump::MethodInfo& i : bump::kMethods) {
    nlohmann::ordered_json e = {
        {"id", std::string(i.name)}, {"label", std::string(i.label)}, {"glsl", std::string(i.glsl)}};
    if (!i.requires_fn.empty()) e["requires"] = std::string(i.requires_fn);
    out += "  " + e.dump() + ",\n";
  }
  return out + "];\n";
}

std::string methods_js(const std::vector<occlusion::MicroShadowingMethodInfo>& methods) {
  using J = nlohmann::ordered_json;
  // The manifest's material key a texel form needs: the 9 channels, or the view correction's 21.
  const auto texel_key = [](const occlusion::MicroShadowingMethodInfo& m) {
    return m.texel_channels > directional::kDirectionalChannels ? "directional_view" : "directional";
  };
  const auto cpp = [](const std::string& method, const occlusion::MicroShadowingGlsl& g) {
    J c = {{"method", method}};
    if (g.phi) c["phi"] = true;
    if (g.samples) c["samples"] = true;
    if (g.frame) c["frame"] = true;
    if (g.two_stage) c["two_stage"] = true;
    if (g.texel) c["texel"] = true;
    return c;
  };
  std::string out =
      "// Generated by `microshadow view` from the micro-shadowing registry\n"
      "// (include/microshadow/occlusion/runtime/micro_shadowing_methods.h, `microshadow methods --json`):\n"
      "// a term added there with a GLSL form appears here with no viewer edit. Not in the source tree.\n"
      "//\n"
      "// Single terms, one entry per GLSL form: { id, label, glsl, requires?, lut?, cpp }\n"
      "//   id       the registry name + the form's id_suffix; label likewise with label_suffix\n"
      "//   glsl     a GLSL ES 3.00 float expression over vis, nl, nv, rough, alpha (= rough^2), cos_phi "
      "(relative\n"
      "//            azimuth of v and l), vec3 v, l (shading frame, n = +z), int u_samples, the LUT "
      "samplers\n"
      "//            u_lut3d, u_lut2d, u_lut_az with u_lut3d_slabs, u_lut2d_slabs, u_lut_az_slabs,\n"
      "//            u_lut_az_harmonics\n"
      "//   requires the GLSL function it calls (left out of the menus when the shader files lack it)\n"
      "//   lut      the table it samples (manifest \"luts\" key; left out when the server has none)\n"
      "//   area_cap the term's form for a spherical-cap light (over vis, nl_cap, rho, nv, rough), where it "
      "has\n"
      "//            one (the three.js module's rect-area lights)\n"
      "//   texel    \"directional\": reads the texture set's directional channels (dir_c0, dir_c1, dir_c8, "
      "l_t,\n"
      "//            n_t; left out when the texture set has none); \"directional_view\": the 21 of the view\n"
      "//            correction (dir_v[6], l_t, view_t, n_t; left out when the set has only 9)\n"
      "//   cpp      what the browser test compares with: the registry method, and phi (at the pixel's "
      "azimuth),\n"
      "//            samples (with the page's N), frame (at the pixel's own v and l), two_stage (pixel + "
      "light),\n"
      "//            texel (at the probed channels, l_t, n_t and view_t)\n"
      "// Pairs (the registry's D+S): { id, label, glsl_diffuse, glsl_specular, requires, lut, cpp } with "
      "each\n"
      "// lobe's expression the first GLSL form of its term, requires and lut lists, and cpp.diffuse,\n"
      "// cpp.specular per lobe; a pair whose term has no GLSL form is left out.\n"
      "export const MICRO_SHADOWING_METHODS = [\n";
  const auto find = [&](const std::string& name) -> const occlusion::MicroShadowingMethodInfo* {
    for (const auto& m : methods)
      if (m.name == name) return &m;
    return nullptr;
  };
  for (const auto& m : methods) {
    if (!m.is_pair()) {
      for (const auto& g : m.glsl) {
        J e = {{"id", m.form_id(g)}, {"label", m.label + g.label_suffix}, {"glsl", g.expr}};
        if (!g.requires_fn.empty()) e["requires"] = g.requires_fn;
        if (!g.lut.empty()) e["lut"] = g.lut;
        if (!g.area_cap.empty()) e["area_cap"] = g.area_cap;
        if (g.texel) e["texel"] = texel_key(m);
        e["cpp"] = cpp(m.name, g);
        out += "  " + e.dump() + ",\n";
      }
      continue;
    }
    const auto *d = find(m.diffuse), *s = find(m.specular);
    if (!d || !s || d->glsl.empty() || s->glsl.empty()) continue;
    const auto &gd = d->glsl.front(), &gs = s->glsl.front();
    J e = {{"id", m.name}, {"label", m.label}, {"glsl_diffuse", gd.expr}, {"glsl_specular", gs.expr}};
    J req = J::array(), lut = J::array();
    for (const auto* g : {&gd, &gs}) {
      if (!g->requires_fn.empty()) req.push_back(g->requires_fn);
      if (!g->lut.empty()) lut.push_back(g->lut);
    }
    e["requires"] = req, e["lut"] = lut;
    if (gd.texel || gs.texel) e["texel"] = texel_key(m);
    e["cpp"] = {{"method", m.name}, {"diffuse", cpp(d->name, gd)}, {"specular", cpp(s->name, gs)}};
    out += "  " + e.dump() + ",\n";
  }
  return out + "];\n";
}

std::map<std::string, std::string> viewer_data_files(const ViewerOptions& o) {
  Content c = build_content(o);
  std::map<std::string, std::string> files;
  for (auto& [path, blob] : c.data) files[path] = std::move(blob.bytes);
  files["data/manifest.json"] = c.manifest.dump(1) + "\n";
  return files;
}

void write_directory_atomically(const fs::path& out, const std::string& what,
                                const std::function<void(const fs::path& tmp)>& fill) {
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  const fs::path tmp = parent / fmt::format(".{}.tmp-{}", out.filename().string(), ::getpid());
  fs::remove_all(tmp, ec);
  try {
    fs::create_directories(tmp);
    fill(tmp);
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(tmp, ec);
    throw InputError(fmt::format("cannot write {} '{}': {}", what, out.string(), e.what()));
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  fs::remove_all(out, ec);
  fs::rename(tmp, out, ec);
  if (ec) {
    fs::remove_all(tmp, ec);
    throw InputError(fmt::format("cannot write {} '{}': {}", what, out.string(), ec.message()));
  }
}

void export_viewer(const ViewerOptions& o, const fs::path& out) {
  if (!o.root.empty())
    throw InputError("--export writes a static copy from the source files; not with --root");
  Content c = build_content(o);
  write_directory_atomically(out, "the viewer copy", [&](const fs::path& tmp) {
    fs::create_directories(tmp / "shaders" / "glsl");
    fs::create_directories(tmp / "data" / "material");
    for (const auto& e : fs::recursive_directory_iterator(o.assets / "web")) {
      const fs::path rel = fs::relative(e.path(), o.assets / "web");
      if (e.is_directory())
        fs::create_directories(tmp / rel);
      else if (e.is_regular_file())
        fs::copy_file(e.path(), tmp / rel, fs::copy_options::overwrite_existing);
    }
    // Every file through the checked writer: a full disk fails the export instead of leaving empty files.
    io::write_file_atomic(tmp / "methods.js", methods_js(occlusion::micro_shadowing_methods()));
    io::write_file_atomic(tmp / "bump_methods.js", bump_methods_js());
    nlohmann::json man = c.manifest;
    man["glsl"] = glsl_files(o.assets / "shaders" / "glsl");
    for (const auto& g : man["glsl"])  // with their includes expanded: WebGL2 has no #include
      io::write_file_atomic(tmp / "shaders" / "glsl" / g.get<std::string>(),
                            expand_shader_includes(o.assets / "shaders" / "glsl" / g.get<std::string>()));
    for (const auto& [path, blob] : c.data)
      io::write_file_atomic(tmp / path, std::string_view(blob.bytes.data(), blob.bytes.size()));
    io::write_file_atomic(tmp / "data" / "manifest.json", man.dump(1) + "\n");
    io::write_file_atomic(
        tmp / "README.txt",
        "microshadow viewer, static copy (docs/viewer.md). Serve it over HTTP on this machine, then open the "
        "URL:\n  microshadow view --root " +
            out.string() + "\n  or any static server, e.g. python3 -m http.server --bind 127.0.0.1 -d " +
            out.string() +
            " 8080\nOpening index.html from file:// does not work: browsers refuse fetch() of file URLs.\n");
  });
}

void block_stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

namespace {

// The viewer's routes: the generated method list and manifest and the baked data from memory (content,
// filled once the server is bound), the GLSL with its includes expanded, the page's files; or with
// --root, a static copy. Paths that leave their folder are not found.
void add_routes(GuardedServer& svr, const ViewerOptions& o, const Content& content) {
  const bool static_root = !o.root.empty();
  svr.Get("/(.*)", [&o, &content, static_root](const httplib::Request& req, httplib::Response& res) {
    std::string p = req.matches[1].str();
    if (p.empty() || p.back() == '/') p += "index.html";
    res.set_header("Cache-Control", "no-store");
    if (!safe_relative_path(p)) {
      res.status = 404;
      return;
    }
    if (!static_root && p == "methods.js") {
      res.set_content(methods_js(occlusion::micro_shadowing_methods()), mime_type(p).c_str());
      return;
    }
    if (!static_root && p == "bump_methods.js") {
      res.set_content(bump_methods_js(), mime_type(p).c_str());
      return;
    }
    if (!static_root && p == "data/manifest.json") {
      nlohmann::json man = content.manifest;
      man["glsl"] = glsl_files(o.assets / "shaders" / "glsl");
      res.set_content(man.dump(1), "application/json");
      return;
    }
    if (!static_root) {
      if (auto it = content.data.find(p); it != content.data.end()) {
        res.set_content(it->second.bytes, it->second.type.c_str());
        return;
      }
    }
    // Symbolic links resolved: a file whose real path leaves its folder (a link to /etc/passwd in --root) is
    // not found, as a missing one.
    const bool shader = !static_root && p.rfind("shaders/glsl/", 0) == 0;
    const std::optional<fs::path> found = static_root ? contained_file(o.root, p)
                                          : shader
                                              ? contained_file(o.assets / "shaders" / "glsl", p.substr(13))
                                              : contained_file(o.assets / "web", p);
    if (!found) {
      res.status = 404;
      res.set_content(fmt::format("not found: /{}\n", p), "text/plain");
      return;
    }
    const fs::path& file = *found;
    try {
      // The GLSL files with their includes expanded (WebGL2 has no #include; shader_source.h).
      if (shader)
        res.set_content(expand_shader_includes(file), mime_type(p).c_str());
      else
        res.set_content(read_bytes(file), mime_type(p).c_str());
    } catch (const InputError&) {
      res.status = 500;
    }
  });
}

// Binds host:port (0: any free port) and returns the port, or a clear error (in use, cannot listen).
int bind_port(GuardedServer& svr, const std::string& host, int requested) {
  errno = 0;
  int port = requested;
  bool bound = false;
  if (port == 0) {
    port = svr.bind_to_any_port(host);
    bound = port > 0;
  } else {
    bound = svr.bind_to_port(host, port);
  }
  if (!bound) {
    const int err = errno;
    if (err == EADDRINUSE)
      throw InputError(fmt::format(
          "port {} on {} is in use (choose another with --port, or 0 for any free port)", requested, host));
    throw InputError(fmt::format("cannot listen on {} port {}: {}", host, requested,
                                 err ? std::strerror(err) : "bind failed"));
  }
  return port;
}

// Serves until SIGINT or SIGTERM (blocked in every thread, taken here): a clean return.
void listen_until_signal(GuardedServer& svr) {
  std::atomic<bool> done{false};
  std::thread stopper([&] {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    int sig = 0;
    sigwait(&set, &sig);
    // stop() before listen_after_bind() has started would be lost: repeat until the server returned.
    while (!done.load()) {
      svr.stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  const bool ok = svr.listen_after_bind();
  done = true;
  pthread_kill(stopper.native_handle(), SIGTERM);  // wakes sigwait if no signal came (harmless otherwise)
  stopper.join();
  if (!ok) throw std::runtime_error("the HTTP server stopped with an error");
}

}  // namespace

void serve(const ViewerOptions& o, const std::function<void(const std::string& url)>& on_ready) {
  check_host(o.host);
  if (o.port < 0 || o.port > 65535)
    throw InputError(fmt::format("--port must be in [0, 65535], got {}", o.port));
  const std::string host = o.host == "localhost" ? "127.0.0.1" : o.host == "[::1]" ? "::1" : o.host;
  const bool static_root = !o.root.empty();
  Content content;
  GuardedServer svr;
  // Only SO_REUSEADDR: httplib's default SO_REUSEPORT would let a second server share a port in use.
  svr.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  // ServerLimits (viewer_server.h): the guard reads each request head with a deadline for the whole head, so
  // a slow client holds one of kWorkers workers for at most kHeadSeconds. Also what httplib itself enforces:
  // the keep-alive header it sends, each recv/send's timeout, no body (the guard refuses one before httplib
  // runs).
  svr.new_task_queue = [] { return new httplib::ThreadPool(ServerLimits::kWorkers); };
  svr.set_keep_alive_timeout(ServerLimits::kHeadSeconds);
  svr.set_keep_alive_max_count(ServerLimits::kKeepAliveRequests);
  svr.set_read_timeout(ServerLimits::kHeadSeconds);
  svr.set_write_timeout(ServerLimits::kAnswerSeconds);
  svr.set_payload_max_length(0);
  add_routes(svr, o, content);
  const int port = bind_port(svr, host, o.port);
  // DNS rebinding: a page of another site whose name now resolves to this address still sends its own name.
  svr.set_pre_routing_handler([port](const httplib::Request& req, httplib::Response& res) {
    if (is_allowed_host_header(req.get_header_value("Host"), port))
      return httplib::Server::HandlerResponse::Unhandled;
    res.status = 403;
    res.set_content(
        fmt::format("forbidden: the Host header must be 127.0.0.1:{0}, localhost:{0} or [::1]:{0}\n", port),
        "text/plain");
    return httplib::Server::HandlerResponse::Handled;
  });
  // Bound first (a port in use fails at once), then the content (the tables take a few seconds).
  if (static_root) {
    if (!o.material.empty() || !o.lut.empty())
      throw InputError("--root serves a static copy as is: --material and --lut do not apply");
    if (!fs::is_regular_file(o.root / "index.html") ||
        !fs::is_regular_file(o.root / "data" / "manifest.json"))
      throw InputError(
          fmt::format("'{}' is not a viewer copy (no index.html, data/manifest.json; write one with "
                      "microshadow view --export DIR)",
                      o.root.string()));
  } else {
    content = build_content(o);
  }

  const std::string url = host.find(':') != std::string::npos ? fmt::format("http://[{}]:{}/", host, port)
                                                              : fmt::format("http://{}:{}/", host, port);
  on_ready(url);

  listen_until_signal(svr);
}

}  // namespace msh::view
