// microshadow command-line tool. Subcommands are added by src/cli/cmd_*.cpp through MSH_CLI_REGISTER.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "registry.h"
#include "run_app.h"

namespace msh::cli {
namespace {
std::vector<std::pair<int, Registrar>>& registrars() {
  static std::vector<std::pair<int, Registrar>> r;
  return r;
}
}  // namespace

bool add_registrar(Registrar r, int order) {
  registrars().emplace_back(order, r);
  return true;
}

void run_registrars(Groups& g) {
  auto& r = registrars();
  std::stable_sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, fn] : r) fn(g);
}

}  // namespace msh::cli

int main(int argc, char** argv) {
  using namespace msh::cli;
  // SIGINT / SIGTERM / SIGHUP remove the temporary files in flight (`view` blocks them for its own stop).
  msh::io::install_temporary_cleanup();
#if defined(__GLIBC__)
  // The bakers allocate and free buffers of tens to hundreds of MB (horizon classes, channel textures, mip
  // levels, encoded copies). glibc maps each block above 32 MB afresh and unmaps it on free, so every reuse
  // page-faults and zero-fills anew; kept in the heap instead, a freed block is reused as it is. Peak memory
  // is unchanged (it is set by the largest live set); gen-material --directional-view on 1024² rock, one
  // thread: 0.91× the CPU time, system time 1.38 → 0.82 s (docs/directional-occlusion.md).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
  CLI::App app{
      "microshadow: microfacet BRDFs, micro-shadowing, the bump-terminator fix, their LUTs and a reference "
      "renderer.",
      "microshadow"};
  app.set_version_flag("--version", std::string("microshadow ") + MSH_VERSION);
  app.require_subcommand(1);
  Groups g;
  g.root = &app;
  g.eval = app.add_subcommand("eval", "Evaluate one term at one point and print JSON");
  g.eval->require_subcommand(1);
  g.bake = app.add_subcommand("bake", "Bake lookup tables");
  g.bake->require_subcommand(1);
  g.plot = app.add_subcommand("plot", "Write figure data (CSV) and figures (PNG)");
  g.plot->require_subcommand(1);
  g.verify = app.add_subcommand("verify", "Measure an approximation's accuracy as it is used");
  g.verify->require_subcommand(1);
  run_registrars(g);

  return parse_and_run(app, argc, argv, "microshadow");
}
