// CLI for directional micro-occlusion (include/microshadow/render/directional_bake.h,
// docs/directional-occlusion.md):
//   microshadow bake directional HEIGHT.png|.exr --depth D --out DIR [--azimuths 32] [--distance 0] [--view]
// writes the 9 directional channels of a height map (21 with --view: the view correction's slope channels
// follow) and their box-filtered mip chain as float32 NPY (one file per level, directional_mip<L>.npy, shape
// (1, h, w, 9 or 21), io/texture.h's NPY layout) and directional.json (8-bit ranges).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/texture_gen.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "common.h"

namespace msh::cli {
namespace {

namespace fs = std::filesystem;
using render::Texture;

struct BakeArgs {
  std::string height, out;
  float depth = 0, distance = 0;
  int azimuths = 32, threads = 0;
  bool view = false;
};

void run_bake(const BakeArgs& a) {
  const auto limit = thread_limit(a.threads);
  require_range(a.depth, 1e-6, 1e4, "--depth");
  const Texture h = render::load_height_map(a.height);
  const Texture ch = a.view ? render::bake_directional_view_channels(h, a.depth, a.azimuths, a.distance)
                            : render::bake_directional_channels(h, a.depth, a.azimuths, a.distance);
  const fs::path dir = make_out_dir(a.out);
  const auto chain = render::box_mip_chain(ch);
  for (std::size_t lv = 0; lv < chain.size(); ++lv)
    io::write_volume(dir / fmt::format("directional_mip{}.npy", lv), render::texture_volume(chain[lv]),
                     io::FileFormat::Npy);
  // The 8-bit encoding's per-channel range (the fine level's min and max) and the conventions.
  nlohmann::json j;
  const render::ChannelRanges r = render::channel_ranges(ch);
  // The basis of each group (occlusion/directional.h): T, then with --view G_x and G_y.
  const std::vector<std::string> basis = {"1", "x", "y", "z", "xz", "yz", "xx-yy", "xy", "zz"};
  j["channels"] = basis;
  if (a.view)  // each slope group on the first kSlopeTerms functions: 9 + 6 + 6 = 21 names
    for (const char* g : {"gx:", "gy:"})
      for (int i = 0; i < directional::kSlopeTerms; ++i) j["channels"].push_back(g + basis[std::size_t(i)]);
  if (j["channels"].size() != std::size_t(ch.channels()))
    throw std::logic_error(
        fmt::format("directional.json: {} names for {} channels", j["channels"].size(), ch.channels()));
  j["range_lo"] = r.lo, j["range_hi"] = r.hi;
  j["tangent_space"] = "x = +u (columns), y = +v (rows, top to bottom), z = flat normal";
  j["azimuths"] = a.azimuths, j["max_distance"] = a.distance, j["depth_texels"] = a.depth;
  // The fit's azimuths as lattice steps (p, q) (empty above kMaxLatticeAzimuths: uniform azimuths).
  j["azimuth_steps"] = nlohmann::json::array();
  for (const render::LatticeStep& st : render::directional_bake_azimuths(a.azimuths).steps)
    j["azimuth_steps"].push_back({st.p, st.q});
  io::write_file_atomic(dir / "directional.json", j.dump(2) + "\n");
  std::cout << fmt::format("wrote {} levels of {} channels to {}\n", chain.size(), ch.channels(), a.out);
}

void add_directional(Groups& g) {
  const auto [b, ba] = add_command<BakeArgs>(
      g.bake, "directional",
      "Directional-occlusion channels (9, or 21 with --view; docs/directional-occlusion.md) of a height map "
      "and their box-filtered mip chain (float32 NPY per level) with directional.json (8-bit ranges, "
      "conventions)",
      run_bake);
  b->add_option("height", ba->height, "Height map (16-bit PNG or EXR, grey, [0, 1])")->required();
  b->add_option("--depth", ba->depth, "Depth of the full height range, texels")->required();
  add_out_dir_option(b, ba->out);
  b->add_option(
       "--azimuths", ba->azimuths,
       "Azimuths per texel, 5-4096 (up to 64: grid steps within 0.5 deg of uniform, horizons by exact "
       "sweeps; above: uniform, by walks)")
      ->capture_default_str();
  b->add_option("--distance", ba->distance, "Ray length, texels (0 = unlimited)")->capture_default_str();
  b->add_flag("--view", ba->view,
              "Also the view correction's 12 slope channels G_x, G_y (21 channels: what the "
              "directional-view method reads)");
  add_threads_option(b, ba->threads);
}

}  // namespace

MSH_CLI_REGISTER(add_directional, 62);

}  // namespace msh::cli
