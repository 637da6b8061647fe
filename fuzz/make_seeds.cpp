// Writes the seed corpora of the fuzz targets with the project's own writers: small volumes in every pixel
// format of every format (BC4/BC5 in DDS and KTX2), mip chains, a baked table with its sidecar (both
// layouts), OBJ text, the example scenes, a gen-material material.json and HTTP request streams.
// Usage: msh_fuzz_seeds OUT_DIR   (creates OUT_DIR/<target>/...)
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/render/texture_gen.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using namespace msh;

namespace {
io::Volume ramp(int w, int h, int d, int c) {
  io::Volume v(w, h, d, c);
  for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = float(i % 17) / 16.0f;
  return v;
}
std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}
void put(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: msh_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  const struct {
    const char* target;
    io::FileFormat ff;
    const char* ext;
  } formats[] = {{"read_dds", io::FileFormat::Dds, ".dds"},
                 {"read_ktx2", io::FileFormat::Ktx2, ".ktx2"},
                 {"read_exr", io::FileFormat::Exr, ".exr"},
                 {"read_npy", io::FileFormat::Npy, ".npy"},
                 {"read_png", io::FileFormat::Png, ".png"}};
  const io::PixelFormat pfs[] = {io::PixelFormat::RGBA8Unorm,  io::PixelFormat::RGBA16Float,
                                 io::PixelFormat::RGBA32Float, io::PixelFormat::RG16Float,
                                 io::PixelFormat::R32Float,    io::PixelFormat::R8Unorm};
  for (const auto& f : formats) {
    fs::create_directories(out / f.target);
    for (const auto pf : pfs)
      for (const int d : {1, 2}) {
        if (f.ff == io::FileFormat::Png && d > 1) continue;  // PNG volumes are 2D
        const auto name = io::pixel_format_name(pf) + "_d" + std::to_string(d) + f.ext;
        io::write_volume(out / f.target / name, ramp(3, 2, d, io::pixel_format_channels(pf)), f.ff, pf);
      }
  }
  // BC4 and BC5 (2D only), 6 × 5 so that the right and bottom blocks are partial.
  for (const auto& f : formats) {
    if (f.ff != io::FileFormat::Dds && f.ff != io::FileFormat::Ktx2) continue;
    for (const auto pf : {io::PixelFormat::BC4Unorm, io::PixelFormat::BC5Unorm})
      io::write_volume(out / f.target / (io::pixel_format_name(pf) + "_d1" + f.ext),
                       ramp(6, 5, 1, io::pixel_format_channels(pf)), f.ff, pf);
  }
  // Mip chains (6 × 5, 3 × 2, 1 × 1) for the level readers, BC4 and BC5 included.
  for (const auto& [target, ext] : {std::pair{"level_dds", ".dds"}, std::pair{"level_ktx2", ".ktx2"}}) {
    fs::create_directories(out / target);
    for (const auto pf :
         {io::PixelFormat::RGBA8Unorm, io::PixelFormat::R8Unorm, io::PixelFormat::RG16Float,
          io::PixelFormat::RGBA16Float, io::PixelFormat::BC4Unorm, io::PixelFormat::BC5Unorm}) {
      const int c = io::pixel_format_channels(pf);
      io::write_texture_mips(out / target / (io::pixel_format_name(pf) + "_mips" + ext),
                             {ramp(6, 5, 1, c), ramp(3, 2, 1, c), ramp(1, 1, 1, c)}, pf);
    }
  }
  // material.json: what gen-material writes (8 × 8 plaster, 21 directional channels), and variants.
  {
    fs::create_directories(out / "material_json");
    const fs::path tmp = out / "material_json" / "tmp_set";
    render::GenOptions o;
    o.size = 8, o.ao_rays = 4, o.directional_azimuths = 8, o.directional_view = true;
    render::write_texture_set(tmp, render::generate_texture_set(o));
    put(out / "material_json" / "gen_material.json", slurp(tmp / "material.json"));
    fs::remove_all(tmp);
    put(out / "material_json" / "depth_only.json", R"({"height": "height.png", "height_texels": 6})");
    put(out / "material_json" / "no_directional.json",
        R"({"base_color": "basecolor.png", "normal": "normal.png", "roughness": "roughness.png",)"
        R"( "micro_occlusion": "micro_occlusion.png", "height": "height.png", "height_texels": 6})");
  }
  // HTTP request streams (fuzz/fuzz_http_head.cpp: 0xFF ends a recv() piece).
  {
    fs::create_directories(out / "http_head");
    const std::string get = "GET /index.html HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nAccept: */*\r\n\r\n";
    put(out / "http_head" / "get", get);
    put(out / "http_head" / "pipelined_pieces",
        get.substr(0, 10) + "\xff" + get.substr(10) + "HEAD / HTTP/1.1\r\nHost: localhost:8080\r\n\xff\r\n");
    put(out / "http_head" / "range",
        "GET /data/a.f16 HTTP/1.1\r\nHost: [::1]:8080\r\nRange: bytes=0-1,2-3\r\nIf-Range: x\r\n\r\n");
    put(out / "http_head" / "post",
        "POST / HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nContent-Length: 5\r\n\r\nhello");
    put(out / "http_head" / "chunked",
        "GET / HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n");
    put(out / "http_head" / "bare_lf", "GET / HTTP/1.1\nHost: 127.0.0.1\n\n");
  }
  // LUT: sidecar text, NUL, table (.npy); tiny bakes of both layouts.
  fs::create_directories(out / "lut");
  for (const auto layout : {lut::LutLayout::Seed, lut::LutLayout::Cone})
    for (const int harmonics : {0, 1}) {
      lut::BakeOptions o = lut::default_bake_options(layout, harmonics);
      o.n_vis = 3, o.n_nl = 3, o.n_nv = 2, o.n_rough = 2, o.samples = 16, o.phi_nodes = 2, o.threads = 1;
      const fs::path tmp = out / "lut" / "tmp.npy";
      io::write_volume(tmp, lut::bake_micro_shadowing_lut(o), io::FileFormat::Npy);
      const std::string name = std::string(lut::layout_name(layout)) + "_h" + std::to_string(harmonics);
      put(out / "lut" / name, lut::sidecar_json(o) + std::string(1, '\0') + slurp(tmp));
      if (layout == lut::LutLayout::Seed && harmonics == 0) put(out / "lut" / "no_sidecar", slurp(tmp));
      fs::remove(tmp);
    }
  fs::create_directories(out / "obj");
  put(out / "obj" / "quad.obj",
      "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4//1 -3//1 -2//1\n");
  put(out / "obj" / "cube.obj", slurp(fs::path(MSH_FUZZ_ASSET_DIR) / "assets" / "cube.obj"));
  fs::create_directories(out / "scene_json");
  for (const auto& e : fs::directory_iterator(MSH_FUZZ_ASSET_DIR))
    if (e.path().extension() == ".json")
      fs::copy_file(e.path(), out / "scene_json" / e.path().filename(), fs::copy_options::overwrite_existing);
  return 0;
}
