// `microshadow view`: the interactive micro-shadowing viewer in the browser (docs/viewer.md).
//
//   microshadow view [--material DIR] [--lut FILE] [--port 8080] [--host 127.0.0.1]
//   microshadow view --root out/viewer            (serve a static copy as is)
//   microshadow view --export out/viewer          (write the static copy and exit)
//   microshadow view --three [--export DIR]       (the three.js example, docs/three.md)
//   microshadow view --three-module DIR           (write the three.js module's generated files and exit)
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "../view/three_example.h"
#include "../view/viewer_server.h"
#include "common.h"

namespace msh::cli {
namespace {

namespace fs = std::filesystem;

bool has_assets(const fs::path& d) {
  std::error_code ec;
  return fs::is_regular_file(d / "web" / "index.html", ec) && fs::is_directory(d / "shaders" / "glsl", ec);
}

// web/ and shaders/glsl/: the source tree the binary was built from (compile-time path), else the install
// share directory next to the binary (<prefix>/bin/microshadow -> <prefix>/share/microshadow).
fs::path find_assets() {
#ifdef MSH_VIEW_SOURCE_DIR
  if (has_assets(MSH_VIEW_SOURCE_DIR)) return MSH_VIEW_SOURCE_DIR;
#endif
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const fs::path& d : {exe.parent_path().parent_path() / "share" / "microshadow", exe.parent_path()})
      if (has_assets(d)) return d;
  }
  throw UsageError(
      "cannot find the viewer's files (web/index.html, shaders/glsl/): neither the source tree this binary "
      "was built from nor <prefix>/share/microshadow has them");
}

struct ViewArgs {
  view::ViewerOptions o;
  std::string material, lut, root, exp, cache, three_module;
  bool three = false;
};

void register_view(Groups& g) {
  auto a = std::make_shared<ViewArgs>();
  CLI::App* c = g.root->add_subcommand("view",
                                       "Interactive micro-shadowing viewer in the browser (WebGL2, the "
                                       "project's GLSL and tables): serves it on 127.0.0.1 and prints the "
                                       "URL; Ctrl-C stops it. See docs/viewer.md");
  c->add_option("--material", a->material,
                "Texture set: a gen-material folder (default: the built-in plaster, generated once into the "
                "cache directory)");
  c->add_option("--lut", a->lut,
                "A cone-layout table (bake micro-shadowing, with its .json sidecar) replacing the default "
                "of its kind (3D, 2D or azimuth-aware)");
  c->add_option("--port", a->o.port, "TCP port (0 = any free port)")->capture_default_str();
  c->add_option("--host", a->o.host, "Loopback address to bind (127.0.0.1, ::1 or localhost; nothing else)")
      ->capture_default_str();
  c->add_option("--root", a->root, "Serve this static copy (written by --export, e.g. out/viewer) as is");
  c->add_option("--export", a->exp,
                "Write a static copy of the page, GLSL files, textures and tables to DIR and exit (any "
                "static HTTP server can serve it)");
  c->add_option("--cache", a->cache,
                "Cache directory for the built-in plaster (default $XDG_CACHE_HOME/microshadow or "
                "~/.cache/microshadow)");
  c->add_flag("--three", a->three,
              "The three.js example (examples/three/, integrations/three/; docs/three.md) instead of the "
              "viewer: served, or with --export written as a static copy. Needs the source tree and `npm "
              "ci` in integrations/three");
  c->add_option("--three-module", a->three_module,
                "Write the three.js module's generated files (methods.js from the registry, glsl.js from "
                "shaders/glsl/) to DIR and exit, e.g. integrations/three/src/generated");
  c->callback([a] {
    // Before any thread starts (the table bake uses TBB): SIGINT/SIGTERM go to the server's stop thread.
    view::block_stop_signals();
    view::ViewerOptions o = a->o;
    o.material = a->material;
    o.lut = a->lut;
    o.root = a->root;
    o.cache = a->cache;
    if (!a->three_module.empty()) {
      if (!a->exp.empty() || !a->root.empty() || a->three)
        throw UsageError(
            "--three-module writes the module's files only: not with --export, --root or --three");
      view::write_three_module(find_assets(), a->three_module);
      print_json({{"dir", a->three_module}});
      return;
    }
    if (a->three && !a->root.empty())
      throw UsageError("--three and --root are exclusive (--root serves any copy)");
    if (!a->exp.empty()) {
      if (!a->root.empty()) throw UsageError("--export and --root are exclusive");
      o.assets = find_assets();
      if (a->three)
        view::export_three_example(o, a->exp);
      else
        view::export_viewer(o, a->exp);
      print_json({{"dir", a->exp}});
      return;
    }
    if (o.root.empty()) o.assets = find_assets();
    // The three.js example: its static copy in the cache directory, served as a root, removed on exit.
    fs::path three_copy;
    if (a->three) {
      const fs::path cache = o.cache.empty() ? view::default_cache_dir() : o.cache;
      three_copy = cache / fmt::format("three-example-{}", ::getpid());
      view::export_three_example(o, three_copy);
      o.root = three_copy;
      o.material.clear();
      o.lut.clear();
    }
    try {
      view::serve(o, [](const std::string& url) {
        fmt::print("microshadow view: serving {} (open it in a browser; Ctrl-C stops the server)\n", url);
        std::fflush(stdout);
      });
    } catch (...) {
      std::error_code ec;
      if (!three_copy.empty()) fs::remove_all(three_copy, ec);
      throw;
    }
    std::error_code ec;
    if (!three_copy.empty()) fs::remove_all(three_copy, ec);
  });
}

MSH_CLI_REGISTER(register_view, 95);

}  // namespace
}  // namespace msh::cli
