// CLI for the micro-shadowing LUT (include/microshadow/lut/):
//   microshadow bake micro-shadowing [--layout cone|seed] [--size-t 64 --size-nl 32 --size-nv 16
//       --roughness-slabs 16 | --size 64 --roughness 0.1,0.4,0.7,1.0] [--2d] [--samples N]
//       [--azimuth|--harmonics H] [--format dds|ktx2|exr|npy|h] [--pixel-format rgba16f] --out FILE
// Writes FILE (atomically) and its JSON sidecar FILE.json (roughness per channel, harmonics, bake settings).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/reference/micro_shadowing_ring.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

struct BakeLutOptions {
  TableOutput out;
  std::string pixel_format = "rgba16f", roughness, roughness_range, layout = "cone",
              symbol = "micro_shadowing_lut";
  int size = -1, size_vis = -1, size_nl = -1, size_nv = -1, size_t_ = -1, slabs = -1;  // -1: layout default
  bool two_d = false, azimuth = false, quiet = false;
  int harmonics = 0, samples = -1, phi_nodes = 16, threads = 0;
  const CLI::Option* harmonics_opt = nullptr;  // set when --harmonics was given
  uint32_t seed = 1;
};

// The pixel format with `channels` channels and the precision named by `name` (rgba8, rgba16f, rgba32f).
io::PixelFormat pixel_format_for(const std::string& name, int channels) {
  using PF = io::PixelFormat;
  const io::PixelFormat base = io::pixel_format_from_name(name);
  const int bits =
      base == PF::RGBA8Unorm ? 8 : (base == PF::RGBA16Float ? 16 : (base == PF::RGBA32Float ? 32 : 0));
  if (bits == 0)
    throw UsageError(fmt::format("--pixel-format must be rgba8, rgba16f or rgba32f, got '{}'", name));
  switch (channels) {
    case 1:
      return bits == 8 ? PF::R8Unorm : (bits == 16 ? PF::R16Float : PF::R32Float);
    case 2:
      return bits == 8 ? PF::RG8Unorm : (bits == 16 ? PF::RG16Float : PF::RG32Float);
    case 4:
      return base;
    default:
      throw UsageError(fmt::format(
          "{} roughness values: textures take 1, 2 or 4 channels (NPY and C header any)", channels));
  }
}

// The bake's options from the command line, each refused where its layout does not take it.
lut::BakeOptions bake_options(const BakeLutOptions& o) {
  const lut::LutLayout layout = lut::layout_from_name(o.layout);
  const bool cone = layout == lut::LutLayout::Cone;
  const int harmonics =
      o.harmonics_opt && o.harmonics_opt->count() > 0 ? o.harmonics : (o.azimuth ? (cone ? 3 : 2) : 0);
  lut::BakeOptions b = lut::default_bake_options(layout, std::max(harmonics, 0));
  auto size_ok = [](int n, const char* name) {
    if (n != -1 && n < 2) throw UsageError(fmt::format("{} must be ≥ 2, got {}", name, n));
    return n > 0;
  };
  size_ok(o.size, "--size"), size_ok(o.size_vis, "--size-visibility"), size_ok(o.size_nl, "--size-nl");
  size_ok(o.size_nv, "--size-nv"), size_ok(o.size_t_, "--size-t"), size_ok(o.slabs, "--roughness-slabs");
  if (cone) {
    if (o.size > 0 || o.size_vis > 0)
      throw UsageError(
          "--size / --size-visibility apply to --layout seed; the cone layout takes --size-t, --size-nl, "
          "--size-nv, --roughness-slabs");
    if (!o.roughness.empty())
      throw UsageError(
          "--roughness (one value per channel) applies to --layout seed; the cone layout takes "
          "--roughness-range MIN,MAX and --roughness-slabs N");
    if (o.size_t_ > 0) b.n_vis = o.size_t_;
    if (o.slabs > 0) b.n_rough = o.slabs;
    if (!o.roughness_range.empty()) {
      const auto rr = parse_list(o.roughness_range, "--roughness-range");
      if (rr.size() != 2) throw UsageError("--roughness-range takes two values MIN,MAX");
      b.cone.roughness_min = float(rr[0]), b.cone.roughness_max = float(rr[1]);
    }
  } else {
    if (o.size_t_ > 0 || o.slabs > 0 || !o.roughness_range.empty())
      throw UsageError("--size-t, --roughness-slabs and --roughness-range apply to the cone layout");
    if (o.size > 0) b.n_vis = b.n_nl = b.n_nv = o.size;
    if (o.size_vis > 0) b.n_vis = o.size_vis;
    if (!o.roughness.empty()) b.roughness = parse_list(o.roughness, "--roughness");
  }
  if (o.size_nl > 0) b.n_nl = o.size_nl;
  if (o.size_nv > 0) b.n_nv = o.size_nv;
  b.two_d = o.two_d;
  b.harmonics = harmonics;
  if (o.samples != -1) b.samples = o.samples;
  b.phi_nodes = o.phi_nodes;
  b.seed = o.seed;
  b.threads = o.threads;
  return b;
}

void run_bake(const BakeLutOptions& o) {
  namespace fs = std::filesystem;
  lut::BakeOptions b = bake_options(o);
  const bool cone = b.layout == lut::LutLayout::Cone;
  lut::validate(b);  // every domain error before any work or output

  const fs::path out(o.out.out);
  const io::FileFormat ff = table_output_format(o.out, "; figures: scripts/plot_lut.py");
  const int channels = cone ? (b.harmonics == 0 ? 1 : (b.harmonics == 1 ? 2 : 4)) : int(b.roughness.size());
  io::PixelFormat pf = io::PixelFormat::RGBA32Float;
  if (ff == io::FileFormat::Dds || ff == io::FileFormat::Ktx2 || ff == io::FileFormat::Exr) {
    pf = pixel_format_for(o.pixel_format, channels);
    if (b.harmonics > 0 && (pf == io::PixelFormat::RGBA8Unorm || pf == io::PixelFormat::RG8Unorm ||
                            pf == io::PixelFormat::R8Unorm))
      throw UsageError(
          "azimuth-aware tables hold signed coefficients: use --pixel-format rgba16f or rgba32f");
  } else {
    io::pixel_format_from_name(o.pixel_format);  // still reject unknown names
  }
  b.progress = progress_in_tenths("baking micro-shadowing LUT", o.quiet);
  const auto t0 = std::chrono::steady_clock::now();
  io::Volume vol = lut::bake_micro_shadowing_lut(b);
  if (vol.channels != channels) {  // cone layout, H = 2: a_0..a_2 in RGB, A = 0 (textures take 1, 2 or 4)
    io::Volume padded(vol.width, vol.height, vol.depth, channels);
    for (std::size_t i = 0; i < vol.texel_count(); ++i)
      for (int c = 0; c < vol.channels; ++c) padded.data[i * channels + c] = vol.data[i * vol.channels + c];
    vol = std::move(padded);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::write_volume(out, vol, ff, pf, o.symbol);
  io::write_file_atomic(lut::sidecar_path(out), lut::sidecar_json(b));
  nlohmann::json j;
  j["out"] = out.string();
  j["sidecar"] = lut::sidecar_path(out).string();
  j["size"] = {vol.width, vol.height, vol.depth};
  j["channels"] = vol.channels;
  j["layout"] = lut::layout_name(b.layout);
  if (cone)
    j["roughness_slabs"] = b.n_rough,
    j["roughness_range"] = {lut::short_float(b.cone.roughness_min), lut::short_float(b.cone.roughness_max)};
  else
    j["roughness"] = b.roughness;
  j["harmonics"] = b.harmonics;
  j["samples"] = b.samples;
  j["phi_nodes"] = b.phi_nodes;
  j["bake_seconds"] = seconds;
  print_json(j);
}

// ---------------------------------------------------------------------------------------------------------
// plot micro-shadowing-lut: the exact azimuth-mean term on N·V slices of a table's grid (the error maps'
// reference; scripts/plot_lut.py draws the figures), and error summaries of the 3D and 2D tables.

struct PlotLutOptions {
  std::string out, lut, lut2d, slices = "0,16,32,48,63";
};

void run_plot(const PlotLutOptions& o) {
  namespace fs = std::filesystem;
  const lut::MicroShadowingLut table = lut::load_micro_shadowing_lut(o.lut);
  const lut::MicroShadowingLutView view = table.view();
  if (view.layout != lut::LutLayout::Seed)
    throw UsageError(
        "plot micro-shadowing-lut draws seed-layout tables (bake micro-shadowing --layout seed); measure a "
        "cone-layout table with verify micro-shadowing-lut");
  std::vector<int> zs;
  for (double z : parse_list(o.slices, "--slices")) {
    if (!(z >= 0 && z < view.n_nv && z == std::floor(z)))
      throw UsageError(
          fmt::format("--slices must be N.V texel indices in [0, {}], got {}", view.n_nv - 1, z));
    zs.push_back(int(z));
  }
  std::optional<lut::MicroShadowingLut> table2d;
  if (!o.lut2d.empty()) {
    table2d = lut::load_micro_shadowing_lut(o.lut2d);
    const auto v2 = table2d->view();
    if (v2.layout != lut::LutLayout::Seed || v2.n_nv != 1 || v2.n_vis != view.n_vis || v2.n_nl != view.n_nl ||
        v2.channels != view.channels)
      throw UsageError("--lut2d must be the 2D LUT (depth 1) of the same size and channels as --lut");
  }
  const fs::path dir = make_out_dir(o.out);

  const int nx = view.n_vis, ny = view.n_nl, nc = view.channels, ns = int(zs.size());
  io::Volume exact(nx, ny, ns, nc);
  std::vector<double> vis(nx);
  for (int i = 0; i < nx; ++i) vis[i] = double(i) / (nx - 1);
  tbb::parallel_for(0, ns * ny * nc, [&](int row) {
    const int s = row / (ny * nc), y = (row / nc) % ny, c = row % nc;
    const double r = table.roughness[c], nv = view.n_nv > 1 ? double(zs[s]) / (view.n_nv - 1) : 1.0;
    std::vector<double> ex(nx);
    micro_shadowing::micro_shadowing_semi_analytic_row(r * r, double(y) / (ny - 1), nv, vis.data(), nx,
                                                       ex.data(), 2, 2);
    for (int x = 0; x < nx; ++x) exact.at(x, y, s, c) = float(ex[x]);
  });
  double max3 = 0, max2 = 0, sum2 = 0;
  long n = 0;
  for (int s = 0; s < ns; ++s)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        for (int c = 0; c < nc; ++c) {
          const double e = exact.at(x, y, s, c);
          max3 = std::max(max3, std::abs(table.volume.at(x, y, zs[s], c) - e));
          if (table2d) {
            const double d = table2d->volume.at(x, y, 0, c) - e;
            max2 = std::max(max2, std::abs(d)), sum2 += std::abs(d), ++n;
          }
        }
  io::write_volume(dir / "micro_shadowing_exact_slices.npy", exact, io::FileFormat::Npy,
                   io::PixelFormat::RGBA32Float);
  nlohmann::json j;
  j["exact"] = (dir / "micro_shadowing_exact_slices.npy").string();
  j["slices_z"] = zs;
  std::vector<double> nvs;
  for (int z : zs) nvs.push_back(view.n_nv > 1 ? double(z) / (view.n_nv - 1) : 1.0);
  j["slices_n_dot_v"] = nvs;
  j["roughness"] = table.roughness;
  j["lut3d_max_abs_error_on_slices"] = max3;
  if (table2d) {
    j["lut2d_max_abs_error_on_slices"] = max2;
    j["lut2d_mean_abs_error_on_slices"] = sum2 / double(std::max(1L, n));
  }
  io::write_file_atomic(dir / "micro_shadowing_exact_slices.json", j.dump(2) + "\n");
  print_json(j);
}

void add_lut(Groups& g) {
  const auto [c, o] = add_command<BakeLutOptions>(
      g.bake, "micro-shadowing",
      "Bake the micro-shadowing LUT (Zurita 2026, generic VNDF-based term, isotropic Smith-GGX): each texel "
      "is the mean over the relative azimuth of the exact term. Default cone layout (t relative to the cone "
      "x N.L x N.V x 16 roughness slabs, 1.5 MiB, 2 fetches); --layout seed: x = Visibility, y = N.L, z = "
      "N.V, one channel per roughness. Also writes OUT.json (layout, roughness, harmonics, settings). See "
      "docs/lut.md.",
      run_bake);
  add_table_output(c, o->out);
  c->add_option("--pixel-format", o->pixel_format,
                "Precision for dds/ktx2/exr: rgba8, rgba16f or rgba32f (NPY and C header are always float32)")
      ->capture_default_str();
  c->add_option("--layout", o->layout,
                "cone (default: t relative to the cone, 16 roughness slabs, docs/lut.md) or seed (x = V, y = "
                "N.L, z = N.V, RGBA = roughness 0.1/0.4/0.7/1.0, as in Zurita 2026)")
      ->capture_default_str();
  c->add_option("--size", o->size, "Seed layout: texels per axis (default 64)");
  c->add_option("--size-visibility", o->size_vis, "Seed layout: texels along Visibility (default: --size)");
  c->add_option("--size-t", o->size_t_, "Cone layout: texels along t (default 64; azimuth-aware 48)");
  c->add_option("--size-nl", o->size_nl, "Texels along N.L (seed: --size; cone: 48; azimuth-aware 40)");
  c->add_option("--size-nv", o->size_nv, "Texels along N.V (seed: --size; cone: 16)");
  c->add_option("--roughness-slabs", o->slabs, "Cone layout: roughness slabs (default 16)");
  c->add_option("--roughness-range", o->roughness_range, "Cone layout: MIN,MAX roughness (default 0.1,1)");
  c->add_flag("--2d", o->two_d, "The 2D LUT: the N.V = 1 slice only");
  c->add_option(
      "--roughness", o->roughness,
      "Seed layout: perceptual roughness per channel, strictly increasing (default 0.1,0.4,0.7,1.0)");
  c->add_flag("--azimuth", o->azimuth,
              "Azimuth-aware table: cone layout: channels a0..a3 of cos(h phi) (same as --harmonics 3); "
              "seed layout: cos(phi), cos(2 phi) slabs along z (--harmonics 2)");
  o->harmonics_opt = c->add_option("--harmonics", o->harmonics,
                                   "Number of cos(h phi) coefficients (0 = plain mean LUT; cone: at most 3)");
  c->add_option("--samples", o->samples,
                "VNDF samples per azimuth node and (roughness, N.V) pair (default: cone 4096, seed 16384)");
  c->add_option("--phi-nodes", o->phi_nodes, "Gauss-Legendre nodes over the relative azimuth [0, pi]")
      ->capture_default_str();
  c->add_option("--seed", o->seed, "Scrambling seed")->capture_default_str();
  add_threads_option(c, o->threads);
  c->add_option("--symbol", o->symbol, "C identifier for the .h output")->capture_default_str();
  add_quiet_flag(c, o->quiet);

  const auto [pc, p] = add_command<PlotLutOptions>(
      g.plot, "micro-shadowing-lut",
      "Exact azimuth-mean micro-shadowing on N.V slices of a baked LUT's grid (NPY + JSON with error "
      "summaries of the 3D LUT and, with --lut2d, of the 2D LUT); scripts/plot_lut.py draws the slice and "
      "error figures.",
      run_plot);
  pc->add_option("--lut", p->lut, "The baked 3D LUT (any format bake micro-shadowing writes)")->required();
  pc->add_option("--lut2d", p->lut2d, "The baked 2D LUT of the same size (optional)");
  pc->add_option("--slices", p->slices, "N.V texel indices of the slices")->capture_default_str();
  add_out_dir_option(pc, p->out);
}

}  // namespace

MSH_CLI_REGISTER(add_lut, 40);

}  // namespace msh::cli
