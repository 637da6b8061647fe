// `microshadow render`, `microshadow gen-material`, `microshadow compare`: the reference renderer's commands.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/gltf_export.h>
#include <microshadow/render/image.h>
#include <microshadow/render/multiscale.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>

#include <atomic>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>

#include "common.h"

namespace msh::cli {
namespace {

// Mean of channel 0 (gen-material reports the mean baked V, the measure its default depths are chosen by).
double mean_channel(const render::Texture& t) {
  double s = 0;
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i) s += t.at(i, j, 0);
  return s / (double(t.width()) * t.height());
}

struct RenderArgs {
  std::string scene, out, method, bump, lut, assets, ms_normal, component, gt_intersector, area_ms;
  int width = 0, height = 0, spp = 0, threads = 0, vndf_samples = 0, area_samples = 0;
  double elevation = -1000, azimuth = -1000, exposure = -1000;
  bool hanika = false, no_hanika = false, area = false, quiet = false, std_error = false;
};

void render_one(const render::Scene& scene, const std::string& prefix, bool quiet, bool std_error);

void run_render(const RenderArgs& a) {
  using namespace msh::render;
  auto limit = thread_limit(a.threads);
  Scene scene = load_scene(a.scene, a.assets);
  Settings& s = scene.settings;
  if (a.width) s.width = a.width;
  if (a.height) s.height = a.height;
  if (a.spp) s.spp = a.spp;
  if (a.vndf_samples) s.vndf_samples = a.vndf_samples;
  if (a.area_samples) s.area_samples = a.area_samples;
  if (!a.bump.empty()) s.bump_terminator = bump_terminator_from_string(a.bump);
  if (!a.component.empty()) s.component = component_from_string(a.component);
  if (!a.gt_intersector.empty())
    s.gt_intersector = a.gt_intersector == "embree" ? GtIntersector::Embree : GtIntersector::HeightField;
  if (!a.ms_normal.empty()) s.ms_smooth_normal = a.ms_normal == "smooth";
  if (a.hanika) s.hanika_offset = true;
  if (a.no_hanika) s.hanika_offset = false;
  if (a.area) s.area_lights = true;
  if (!a.area_ms.empty()) s.area_ms = area_ms_from_string(a.area_ms);
  if (!a.lut.empty()) s.lut_path = a.lut;
  if (a.exposure > -1000) s.exposure = float(a.exposure);
  if (a.elevation > -1000 || a.azimuth > -1000) {
    for (Light& l : scene.lights) {
      if (l.type != LightType::Directional) continue;
      const float el = a.elevation > -1000 ? float(a.elevation)
                                           : std::asin(clamp(l.direction.z, -1.0f, 1.0f)) * 180 / kPi<float>;
      const float az =
          a.azimuth > -1000 ? float(a.azimuth) : std::atan2(l.direction.y, l.direction.x) * 180 / kPi<float>;
      l.direction = direction_from_angles(el, az);
    }
  }
  if (uint64_t(s.width) * s.height > (uint64_t(1) << 26))
    throw UsageError(fmt::format("image size {}x{} is too large (at most 2^26 pixels)", s.width, s.height));
  // --method a,b,c renders each method in turn (one process: the scene and the LUT load once) to
  // PREFIX_<method>.{exr,png}; a single method writes PREFIX.{exr,png}.
  std::vector<std::string> methods;
  for (const std::string& m : split_list(a.method)) methods.push_back(micro_shadowing_from_string(m));
  if (methods.empty()) methods.push_back(s.micro_shadowing);
  for (const std::string& method : methods) {
    s.micro_shadowing = method;
    const std::string prefix = methods.size() > 1 ? a.out + "_" + method : a.out;
    render_one(scene, prefix, a.quiet, a.std_error);
  }
}

void render_one(const render::Scene& scene, const std::string& prefix, bool quiet, bool std_error) {
  using namespace msh::render;
  const Settings& s = scene.settings;
  const Renderer renderer(scene);
  std::mutex mu;
  int last = -1;
  auto progress = [&](double f) {
    if (quiet) return;
    const int pct = int(f * 100);
    std::lock_guard<std::mutex> lock(mu);
    if (pct / 10 != last / 10 || pct == 100) {
      if (pct == last) return;
      last = pct;
      std::cerr << fmt::format("\rrender: {:3d}%", pct) << (pct == 100 ? "\n" : "") << std::flush;
    }
  };
  RenderStats st;
  Image img, se;
  if (std_error) {
    RenderResult res = renderer.render_with_error(progress);
    img = std::move(res.mean), se = std::move(res.std_error), st = res.stats;
  } else {
    img = renderer.render(progress, &st);
  }
  write_exr(prefix + ".exr", img);
  write_png(prefix + ".png", img, s.exposure);
  if (std_error) write_exr(prefix + "_stderr.exr", se);
  const double rays = double(st.camera_rays + st.shadow_rays);
  nlohmann::json j = {
      {"exr", prefix + ".exr"},
      {"png", prefix + ".png"},
      {"method", s.micro_shadowing},
      {"bump_terminator", to_string(s.bump_terminator)},
      {"component", to_string(s.component)},
      {"width", s.width},
      {"height", s.height},
      {"spp", s.spp},
      {"seconds", st.seconds},
      {"camera_rays", st.camera_rays},
      {"shadow_rays", st.shadow_rays},
      {"shaded_samples", st.shaded_samples},
      {"rays_per_second", st.seconds > 0 ? rays / st.seconds : 0.0},
      {"shaded_samples_per_second", st.seconds > 0 ? double(st.shaded_samples) / st.seconds : 0.0}};
  if (std_error) {
    // Image mean (of the RGB average) and its standard error: pixels are independent, and the channel
    // average's error is bounded by the average of the channels' errors.
    double sum = 0, var = 0;
    for (std::size_t i = 0; i < img.px.size(); ++i) {
      sum += (img.px[i].r + img.px[i].g + img.px[i].b) / 3.0;
      var += sqr((se.px[i].r + se.px[i].g + se.px[i].b) / 3.0);
    }
    const double n = double(img.px.size());
    j["stderr_exr"] = prefix + "_stderr.exr";
    j["mean_radiance"] = sum / n;
    j["mean_radiance_std_error"] = std::sqrt(var) / n;
  }
  print_json(j);
}

void add_gen_material(Groups& g);
void add_compare(Groups& g);

void add_render(Groups& g) {
  const auto [r, a] = add_command<RenderArgs>(
      g.root, "render", "Render a scene JSON file to PREFIX.exr (linear) and PREFIX.png (sRGB)", run_render);
  r->add_option("scene", a->scene, "Scene JSON file (see docs/renderer.md, examples/)")->required();
  r->add_option("--out", a->out, "Output prefix: writes PREFIX.exr and PREFIX.png")->required();
  r->add_option("--width", a->width, "Override settings.width")->check(CLI::Range(1, 16384));
  r->add_option("--height", a->height, "Override settings.height")->check(CLI::Range(1, 16384));
  r->add_option("--spp", a->spp, "Samples per pixel")->check(CLI::Range(1, 65536));
  add_threads_option(r, a->threads);
  r->add_option(
      "--method", a->method,
      "Micro-shadowing: a method of `microshadow methods` (D+S: a pair, D on the diffuse lobe and S on the "
      "specular lobe) or ground-truth; a comma-separated list renders each to PREFIX_<method>");
  r->add_option("--vndf-samples", a->vndf_samples,
                "Samples per light of the methods with a Sobol estimator (generic-vndf, diffuse-aware, ...)")
      ->check(CLI::Range(1, 1 << 20));
  r->add_option("--bump-terminator", a->bump,
                "Bump-terminator method (`microshadow methods --bump`): " + bump::method_names());
  r->add_option(
       "--ms-normal", a->ms_normal,
       "Normal for the micro-shadowing N·L, N·V: shading (normal-mapped, default) or smooth (unperturbed)")
      ->check(CLI::IsMember({"shading", "smooth"}));
  r->add_option("--component", a->component, "BRDF part to render: total (default), diffuse or specular")
      ->check(CLI::IsMember({"total", "diffuse", "specular"}));
  r->add_option("--ground-truth-intersector", a->gt_intersector,
                "Ground-truth planes: heightfield (DDA, default) or embree (same triangles)")
      ->check(CLI::IsMember({"heightfield", "embree"}));
  r->add_flag("--std-error", a->std_error,
              "Also write PREFIX_stderr.exr: each pixel's standard error (settings.error_batches batches)");
  r->add_flag("--hanika", a->hanika, "Hanika 2021 shadow-ray offset on meshes");
  r->add_flag("--no-hanika", a->no_hanika, "Disable the Hanika offset");
  r->add_flag("--area-lights", a->area,
              "Sphere lights by area sampling (reference) instead of a representative point");
  r->add_option("--area-samples", a->area_samples, "Samples per area-sampled sphere, disk or rect light")
      ->check(CLI::Range(1, 1 << 16));
  r->add_option("--area-ms", a->area_ms,
                "Micro-shadowing under area-sampled lights: sampled (per light sample), representative (once "
                "at Karis's representative point), integrated (averaged over the light)")
      ->check(CLI::IsMember({"sampled", "representative", "integrated"}));
  r->add_option("--lut", a->lut, "Micro-shadowing LUT file for lut3d/lut2d");
  r->add_option("--assets", a->assets,
                "Resolve relative texture/OBJ paths against DIR (default: the scene's directory)");
  r->add_option("--light-elevation", a->elevation, "Set every directional light's elevation (degrees)")
      ->check(CLI::Range(-90.0, 90.0));
  r->add_option("--light-azimuth", a->azimuth, "Set every directional light's azimuth (degrees from +x)")
      ->check(CLI::Range(-360.0, 360.0));
  r->add_option("--exposure", a->exposure, "PNG exposure in stops")->check(CLI::Range(-30.0, 30.0));
  add_quiet_flag(r, a->quiet);

  add_gen_material(g);
  add_compare(g);
}

// gen-material's options.
struct GenMaterialArgs {
  render::GenOptions gen;
  std::string dir, height, form;
  int threads = 0;
  bool no_mips = false, bc = false, gltf = false;
  CLI::Option *kind_opt = nullptr, *size_opt = nullptr;
};

// The glTF asset (docs/gltf.md): the extension's code is the compact form when one is written (the same
// fitted code as mips/), else the 21 channels of directional-view themselves.
void write_gen_gltf(const std::string& dir, const render::TextureSet& set,
                    const render::DirectionalCodec* codec) {
  std::optional<render::DirectionalCode> code;
  if (set.directional.channels() == directional::kViewChannels)
    code = codec ? render::compact_directional_code(set.directional, *codec)
                 : render::identity_directional_code(set.directional);
  render::write_texture_set_gltf(std::filesystem::path(dir) / "gltf", set, code ? &*code : nullptr);
}

// Mips and glTF from one set: the compact form fitted once.
void write_gen_extras(const GenMaterialArgs& a, const render::TextureSet& set) {
  std::optional<render::DirectionalCodec> codec;
  if (!a.form.empty()) codec = render::fit_directional_codec(set.directional, a.form);
  if (!a.no_mips) render::write_texture_set_mips(a.dir, set, a.bc, codec ? &*codec : nullptr);
  if (a.gltf) write_gen_gltf(a.dir, set, codec ? &*codec : nullptr);
}

void run_gen_material(const GenMaterialArgs& a) {
  auto limit = thread_limit(a.threads);
  if (!a.form.empty()) {
    if (a.no_mips || a.gen.directional_azimuths == 0)
      throw UsageError(
          "--directional-form writes into mips/ from the directional channels: not with --no-mips or "
          "--directional-azimuths 0");
    // Refused before the bake: a bad name, or a form gen-material does not write.
    const auto f = render::parse_directional_form(a.form, a.gen.directional_view
                                                              ? msh::directional::kViewChannels
                                                              : msh::directional::kDirectionalChannels);
    if (f.bits != 8) throw UsageError("--directional-form: gen-material writes the 8-bit forms, pca<K>");
  }
  if (a.bc && (a.no_mips || a.gen.directional_azimuths == 0))
    throw UsageError(
        "--directional-bc writes mips of the directional channels: not with --no-mips or "
        "--directional-azimuths 0");
  if (a.height.empty()) {
    const auto set = render::generate_texture_set(a.gen);
    io::OutputFolder folder(a.dir);
    render::write_texture_set(a.dir, set);
    write_gen_extras(a, set);
    print_json({{"dir", a.dir},
                {"kind", a.gen.kind},
                {"size", a.gen.size},
                {"height_texels", set.depth_texels},
                {"mean_visibility", mean_channel(set.visibility)},
                {"stale_removed", folder.finish()}});
    return;
  }
  if (a.kind_opt->count() > 0) throw UsageError("--kind and --height are exclusive");
  if (a.size_opt->count() > 0) throw UsageError("--size and --height are exclusive (the size is the map's)");
  if (!(a.gen.depth_texels > 0))
    throw UsageError("--height needs --depth D > 0 (the depth of the full [0,1] range in texels)");
  const render::Texture h = render::load_height_map(a.height);
  const auto set = render::texture_set_from_height(h, a.gen.depth_texels, a.gen);
  io::OutputFolder folder(a.dir);
  render::write_texture_set(a.dir, set);
  write_gen_extras(a, set);
  print_json({{"dir", a.dir},
              {"height", a.height},
              {"size", {h.width(), h.height()}},
              {"height_texels", set.depth_texels},
              {"mean_visibility", mean_channel(set.visibility)},
              {"stale_removed", folder.finish()}});
}

// gen-material: a texture set, procedural or from a height map, its mips, compact form and glTF asset.
void add_gen_material(Groups& g) {
  auto a = std::make_shared<GenMaterialArgs>();
  CLI::App* gm = g.root->add_subcommand("gen-material",
                                        "Generate a texture set (height, normal, roughness, metallic, base "
                                        "colour, baked micro-occlusion), procedural or from a height map");
  a->kind_opt =
      gm->add_option(
            "--kind", a->gen.kind,
            "plaster (damaged plaster: noise, cracks, pits), bark (furrowed ridges), gravel (packed stones "
            "on sand), rock (fractured rock: blocks, cracks, ridges), brick (running-bond paving, deep "
            "mortar joints) or cobble (rounded cobblestones)")
          ->check(CLI::IsMember(render::material_kinds()));
  a->size_opt = gm->add_option("--size", a->gen.size, "Texels per side")->check(CLI::Range(8, 8192));
  gm->add_option("--height", a->height,
                 "Bake this height map instead (16-bit PNG or EXR, grey, values in [0,1]; needs --depth)");
  add_out_dir_option(gm, a->dir);
  gm->add_option("--depth", a->gen.depth_texels,
                 "Depth of the full height range in texels (0 = kind default; required with --height)")
      ->check(Finite)
      ->check(CLI::Range(0.0, 1e4));
  gm->add_option("--ao-rays", a->gen.ao_rays,
                 "Micro-occlusion bake: azimuths per texel (each exact in elevation)")
      ->check(CLI::Range(1, 65536));
  gm->add_option("--ao-distance", a->gen.ao_max_distance, "Bake ray length in texels (0 = 8% of the size)")
      ->check(Finite)
      ->check(CLI::Range(0.0, 1e6));
  gm->add_option("--seed", a->gen.seed, "Noise seed");
  gm->add_option("--directional-azimuths", a->gen.directional_azimuths,
                 "Directional micro-occlusion bake (9 channels, docs/directional-occlusion.md): azimuths per "
                 "texel; 0 = not baked")
      ->capture_default_str();
  gm->add_flag("--directional-view", a->gen.directional_view,
               "Bake the view correction's 12 slope channels too (21 channels in directional.npy), what the "
               "directional-view method reads");
  gm->add_flag(
      "--directional-bc", a->bc,
      "Also write the directional channels block-compressed in mips/ (directional_bc_<f>: BC5 pairs, an odd "
      "last channel BC4; 4 bits per channel, the same ranges)");
  gm->add_option(
      "--directional-form", a->form,
      "Also write a compact form of the directional channels (docs/directional-occlusion.md, \"Compact "
      "forms\"): pca<K>, K coefficients per texel at 8 bits from a linear code fitted to this material "
      "(mips/directional_compact_<t>.ktx2/.dds, 4 per RGBA8 texture, level 0 as "
      "directional_compact_<t>.png; the code in mips/mips.json)");
  gm->add_flag(
      "--gltf", a->gltf,
      "Also write DIR/gltf/: a glTF 2.0 plane with the texture set (base colour, normal, ORM-packed "
      "occlusion/roughness/metallic) and, with --directional-view, the MSH_materials_directional_occlusion "
      "extension (docs/gltf.md)");
  gm->add_flag("--no-mips", a->no_mips,
               "Do not write mips/ (every map's mip chain as KTX2 and DDS, and each level as float32 NPY)");
  add_threads_option(gm, a->threads);
  gm->callback([a] { run_gen_material(*a); });
}

// compare: an image's error against a reference.
void add_compare(Groups& g) {
  struct CmpArgs {
    std::string a, b, diff;
    double exposure = 0;
    int down = 1;
  };
  auto c = std::make_shared<CmpArgs>();
  CLI::App* cmp =
      g.root->add_subcommand("compare", "Error of image A against reference B (linear EXR): RMSE, SSIM");
  cmp->add_option("a", c->a, "Image (EXR)")->required();
  cmp->add_option("b", c->b, "Reference image (EXR)")->required();
  cmp->add_option("--exposure", c->exposure, "Exposure of the display images used by SSIM and --diff")
      ->check(CLI::Range(-30.0, 30.0));
  cmp->add_option("--diff", c->diff, "Write a false-colour difference PNG (red: A brighter, blue: A darker)");
  cmp->add_option("--downsample", c->down, "Also compare after box-downsampling by this factor")
      ->check(CLI::Range(1, 64));
  cmp->callback([c] {
    const auto A = render::read_exr(c->a), B = render::read_exr(c->b);
    if (A.width != B.width || A.height != B.height)
      throw UsageError(
          fmt::format("{} is {}x{} but {} is {}x{}", c->a, A.width, A.height, c->b, B.width, B.height));
    nlohmann::json j = {{"rmse", render::rmse(A, B)}, {"ssim", render::ssim(A, B, float(c->exposure))}};
    if (c->down > 1) {
      const auto a2 = render::downsample(A, c->down), b2 = render::downsample(B, c->down);
      j["rmse_downsampled"] = render::rmse(a2, b2);
      j["ssim_downsampled"] = render::ssim(a2, b2, float(c->exposure));
      j["downsample"] = c->down;
    }
    if (!c->diff.empty())
      render::write_png_display(c->diff, render::difference_image(A, B, float(c->exposure)));
    print_json(j);
  });
}

}  // namespace

MSH_CLI_REGISTER(add_render, 90);

}  // namespace msh::cli
