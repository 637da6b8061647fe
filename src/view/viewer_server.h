// The browser viewer's HTTP server (`microshadow view`, docs/viewer.md): serves the page (web/, with
// methods.js generated from the micro-shadowing registry), the GLSL files (shaders/glsl/*.glsl, read from
// disk on every request with their #include lines expanded: the page concatenates them at load time), a
// texture set (a gen-material folder) and the baked micro-shadowing tables as raw half floats with their
// sidecar JSON. Loopback only, and only to requests whose Host header names it. I/O and threads: not part of
// the embeddable core.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace msh::occlusion {
struct MicroShadowingMethodInfo;
}

namespace msh::view {

struct ViewerOptions {
  std::string host = "127.0.0.1";  // a loopback address only (is_loopback_host)
  int port = 8080;                 // 0: any free port
  std::filesystem::path assets;    // directory holding web/ and shaders/glsl/ (the source tree or share dir)
  std::filesystem::path material;  // gen-material folder; empty: the built-in plaster (cached, see below)
  std::filesystem::path lut;       // a cone-layout table (bake micro-shadowing) replacing its default
  std::filesystem::path root;      // serve this static copy (export_viewer output) as is; the rest unused
  std::filesystem::path cache;     // where the built-in plaster is generated on first use
};

// What serve() accepts (docs/viewer.md, "Limits"). The request head (request line and header lines) is read
// by the viewer's own code before cpp-httplib parses it, so each limit holds whatever the library version
// does: more than kMaxHeadBytes or kMaxHeaderLines gets 431; a method other than GET or HEAD gets 405 and a
// GET/HEAD announcing a body (Content-Length > 0, Transfer-Encoding) 413, both before any body byte is read;
// a head not complete kHeadSeconds after the connection opened (or the previous answer was sent) gets 408 and
// the connection is closed, however slowly its bytes trickle in; an answer not taken by the client within
// kAnswerSeconds is cut. kWorkers connections are served at once (a slow client holds one for at most
// kHeadSeconds), at most kKeepAliveRequests requests per connection. Range headers are ignored (200, the
// whole file).
struct ServerLimits {
  static constexpr int kWorkers = 32;
  static constexpr int kHeadSeconds = 3;
  static constexpr int kAnswerSeconds = 10;
  static constexpr std::size_t kMaxHeadBytes = 16 * 1024;
  static constexpr int kMaxHeaderLines = 100;
  static constexpr int kKeepAliveRequests = 100;
};

// 127.0.0.1 (any 127.x.y.z), ::1 and "localhost".
bool is_loopback_host(const std::string& host);

// Whether a request's Host header names this server: a loopback address or localhost with the server's port
// (127.0.0.1:PORT, localhost:PORT, [::1]:PORT; the port may be omitted only for port 80, as browsers do). A
// page of another site that reaches the server through DNS rebinding sends its own name and gets 403.
bool is_allowed_host_header(const std::string& host_header, int port);

// The page's methods.js, generated from a method list (the runtime registry,
// occlusion::micro_shadowing_methods()): one viewer entry per GLSL form of each single term, and one per pair
// whose two terms have a GLSL form (each lobe its term's first form). docs/viewer.md describes the entries.
std::string methods_js(const std::vector<occlusion::MicroShadowingMethodInfo>& methods);
// The page's bump_methods.js, generated from the bump-terminator registry (occlusion/bump_terminator.h
// bump::kMethods): export const BUMP_TERMINATOR_METHODS = [{ id, label, glsl, requires? }, ...].
std::string bump_methods_js();

// The default cache directory: $XDG_CACHE_HOME/microshadow, else $HOME/.cache/microshadow, else the
// system temporary directory.
std::filesystem::path default_cache_dir();

// Writes a static copy of the viewer (page, GLSL files, texture set, tables, manifest) to `out` (replaced
// atomically: written beside it, then renamed). Any static HTTP server can serve it. InputError on bad input.
void export_viewer(const ViewerOptions& o, const std::filesystem::path& out);

// Writes the directory `out` whole or not at all: fill(tmp) writes into a fresh temporary directory beside
// it, which then replaces `out` (renamed). On any failure the temporary directory is removed and InputError
// names `what` and `out` (a filesystem error) or the exception passes through.
void write_directory_atomically(const std::filesystem::path& out, const std::string& what,
                                const std::function<void(const std::filesystem::path& tmp)>& fill);

// The page's data files as the viewer serves them, path -> bytes: "data/manifest.json" (without its "glsl"
// list), "data/material/<map>.png" (the texture set) and "data/<table>.f16" with "data/<table>.json" (the
// cone-layout tables as raw half floats and their sidecars). The three.js example reuses them
// (three_example.h). InputError on bad input, as export_viewer.
std::map<std::string, std::string> viewer_data_files(const ViewerOptions& o);

// Prepares the content (InputError with one line on bad input: a non-loopback host, missing textures, a
// table the shaders cannot sample, a port in use), binds, calls on_ready(url) and serves until SIGINT or
// SIGTERM, then returns. The caller must have blocked SIGINT and SIGTERM in every thread
// (block_stop_signals() before any thread starts): a dedicated thread waits for them.
// Requests within ServerLimits only; a file is served only if its real path (links resolved) stays inside its
// folder (--root, web/, shaders/glsl/): else 404.
void serve(const ViewerOptions& o, const std::function<void(const std::string& url)>& on_ready);

// Blocks SIGINT and SIGTERM in the calling thread (inherited by the threads it starts later).
void block_stop_signals();

}  // namespace msh::view
