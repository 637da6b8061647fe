// CLI for normal/roughness filtering (include/microshadow/filter/, RTR4 §9.13.1):
//   microshadow filter --normal N.png|.exr (--roughness R.png|.exr | --roughness-value r) --out DIR|PREFIX
//       [--method toksvig|variance|lean] [--levels K] [--format png|exr] [--write-normals] [--json]
// Writes one roughness image per mip level (level 0 = input resolution), widened by the normal variance of
// each level's footprint. Output names: DIR/roughness_mip<k>.<ext> when --out is a directory (existing, or
// ending in
// '/'), else PREFIX_mip<k>.<ext>. Normal maps: PNG stores n = 2c − 1 (tangent space, any Y convention: the
// variance does not depend on it); EXR stores n as-is; 2-channel maps get n_z = sqrt(1 − x² − y²).
#include <fmt/format.h>
#include <microshadow/filter/runtime/mip_chain.h>
#include <microshadow/filter/variance_mapping.h>
#include <microshadow/io/texture.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "common.h"

namespace msh::cli {
namespace {

namespace fs = std::filesystem;

struct FilterOptions {
  std::string normal, roughness, out, method = "variance", format = "png", ggx_variance = "beckmann";
  std::optional<double> roughness_value;
  int levels = 0;
  bool write_normals = false, json = false;
};

std::vector<Vec3f> load_normals(const fs::path& p, int& w, int& h) {
  const io::Volume v = io::read_image(p);
  if (v.depth != 1 || v.width <= 0 || v.height <= 0)
    throw UsageError(fmt::format("'{}': not a 2D image", p.string()));
  if (v.channels < 2)
    throw UsageError(
        fmt::format("'{}': a normal map needs 2 (RG) or 3+ (RGB) channels, got {}", p.string(), v.channels));
  const bool png = fs::path(p).extension() == ".png" || fs::path(p).extension() == ".PNG";
  w = v.width, h = v.height;
  std::vector<Vec3f> n(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto c = [&](int k) {
        const float s = v.at(x, y, 0, k);
        return png ? 2.0f * s - 1.0f : s;
      };
      const float nx = c(0), ny = c(1);
      const float nz = v.channels >= 3 ? c(2) : std::sqrt(std::max(0.0f, 1.0f - nx * nx - ny * ny));
      const Vec3f val(nx, ny, nz);
      if (!is_finite(val))
        throw UsageError(fmt::format("'{}': non-finite normal at ({}, {})", p.string(), x, y));
      n[size_t(y) * size_t(w) + size_t(x)] = val;
    }
  return n;
}

std::vector<float> load_roughness(const fs::path& p, int w, int h) {
  const io::Volume v = io::read_image(p);
  const bool one = v.width == 1 && v.height == 1;
  if (v.depth != 1 || (!one && (v.width != w || v.height != h)))
    throw UsageError(
        fmt::format("'{}': roughness map is {}x{}, the normal map is {}x{} (sizes must match, or 1x1)",
                    p.string(), v.width, v.height, w, h));
  std::vector<float> r(size_t(v.width) * size_t(v.height));
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      const float s = v.at(x, y, 0, 0);
      if (!std::isfinite(s) || s < 0.0f || s > 1.0f)
        throw UsageError(
            fmt::format("'{}': roughness must be in [0,1], got {} at ({}, {})", p.string(), s, x, y));
      r[size_t(y) * size_t(v.width) + size_t(x)] = s;
    }
  return r;
}

fs::path output_path(const std::string& out, int level, const std::string& what, const std::string& ext) {
  const bool dir = (!out.empty() && (out.back() == '/' || out.back() == '\\')) || fs::is_directory(out);
  if (dir) return fs::path(out) / fmt::format("{}_mip{}.{}", what, level, ext);
  const std::string stem = what == "roughness" ? out : out + "_" + what;
  return fs::path(fmt::format("{}_mip{}.{}", stem, level, ext));
}

void run_filter(const FilterOptions& o) {
  const filter::FilterMethod method = filter::filter_method_from_name(o.method);
  if (o.format != "png" && o.format != "exr")
    throw UsageError(fmt::format("--format must be png or exr, got '{}'", o.format));
  if (o.roughness.empty() == !o.roughness_value)
    throw UsageError("give exactly one of --roughness FILE and --roughness-value R");
  if (o.roughness_value) require_range(*o.roughness_value, 0.0, 1.0, "--roughness-value");
  if (o.levels < 0) throw UsageError(fmt::format("--levels must be >= 0, got {}", o.levels));
  if (o.out.empty()) throw UsageError("--out must not be empty");
  double k = 0;
  if (o.ggx_variance == "beckmann")
    k = filter::kBeckmannEquivalent;
  else if (o.ggx_variance == "conty")
    k = filter::kConty2019;
  else
    throw UsageError(fmt::format("--ggx-variance must be beckmann or conty, got '{}'", o.ggx_variance));

  int w = 0, h = 0;
  const auto normals = load_normals(o.normal, w, h);
  const auto rough =
      o.roughness_value ? std::vector<float>{float(*o.roughness_value)} : load_roughness(o.roughness, w, h);
  const auto mips = filter::build_roughness_mips(w, h, normals, rough, method, o.levels, k);

  const bool dir_out = !o.out.empty() && (o.out.back() == '/' || o.out.back() == '\\');
  if (dir_out)
    make_out_dir(o.out);
  else
    require_parent_dir(o.out, "--out");

  nlohmann::json levels = nlohmann::json::array();
  for (size_t k = 0; k < mips.size(); ++k) {
    const auto& m = mips[k];
    // PNG: 1 channel (r) or 3 (r_x, r_y, 0) for lean; EXR needs RGB: r replicated, or (r_x, r_y, 0).
    const int ch = (o.format == "exr" || m.channels == 2) ? 3 : 1;
    io::Volume img(m.width, m.height, 1, ch);
    double mean = 0, mean_y = 0, mean_a2 = 0, mean_a2_y = 0;  // r and α² = r⁴
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) {
        const size_t i = size_t(y) * size_t(m.width) + size_t(x);
        const float rx = m.roughness[i * size_t(m.channels)];
        const float ry = m.channels == 2 ? m.roughness[i * 2 + 1] : rx;
        mean += rx, mean_y += ry;
        mean_a2 += std::pow(double(rx), 4.0), mean_a2_y += std::pow(double(ry), 4.0);
        img.at(x, y, 0, 0) = rx;
        if (ch == 3) {
          img.at(x, y, 0, 1) = m.channels == 2 ? ry : rx;
          img.at(x, y, 0, 2) = m.channels == 2 ? 0.0f : rx;
        }
      }
    const double n = double(m.width) * m.height;
    const fs::path p = output_path(o.out, int(k), "roughness", o.format);
    if (o.format == "png")
      io::write_png(p, img, 16);
    else
      io::write_exr(p, img, /*half=*/false);
    nlohmann::json j{{"level", k},
                     {"width", m.width},
                     {"height", m.height},
                     {"file", p.string()},
                     {"mean_roughness", mean / n},
                     {"mean_alpha2", mean_a2 / n},
                     {"mean_normal_slope_variance", m.mean_normal_variance}};
    if (m.channels == 2) j["mean_roughness_y"] = mean_y / n, j["mean_alpha2_y"] = mean_a2_y / n;
    if (o.write_normals) {
      io::Volume nimg(m.width, m.height, 1, 3);
      for (size_t i = 0; i < size_t(n); ++i)
        for (int c = 0; c < 3; ++c)
          nimg.data[i * 3 + size_t(c)] =
              o.format == "png" ? 0.5f * m.normal[i * 3 + size_t(c)] + 0.5f : m.normal[i * 3 + size_t(c)];
      const fs::path np = output_path(o.out, int(k), "normal", o.format);
      if (o.format == "png")
        io::write_png(np, nimg, 16);
      else
        io::write_exr(np, nimg, false);
      j["normal_file"] = np.string();
    }
    levels.push_back(j);
  }
  nlohmann::json out{
      {"method", filter::filter_method_name(method)}, {"width", w}, {"height", h}, {"levels", levels}};
  if (o.json) {
    print_json(out);
    return;
  }
  std::cout << fmt::format("filter ({}): {}x{} -> {} levels\n", filter::filter_method_name(method), w, h,
                           mips.size());
  for (const auto& j : levels)
    std::cout << fmt::format(
        "  mip {:2d} {:5d}x{:<5d} mean roughness {:.4f}  normal slope variance {:.5f}  {}\n",
        j["level"].get<int>(), j["width"].get<int>(), j["height"].get<int>(),
        j["mean_roughness"].get<double>(), j["mean_normal_slope_variance"].get<double>(),
        j["file"].get<std::string>());
}

void add_filter(Groups& g) {
  const auto [c, o] = add_command<FilterOptions>(
      g.root, "filter",
      "Roughness mip chain from a normal + roughness texture pair (Toksvig 9.76 / variance mapping / LEAN)",
      run_filter);
  c->add_option("--normal", o->normal, "Tangent-space normal map (.png: n = 2c - 1; .exr: as stored)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--roughness", o->roughness,
                "Perceptual roughness map (.png/.exr, channel 0, same size or 1x1)")
      ->check(CLI::ExistingFile);
  c->add_option("--roughness-value", o->roughness_value, "Constant perceptual roughness instead of a map")
      ->check(Finite);
  c->add_option("--out", o->out,
                "Output directory (existing, or ending in '/': roughness_mip<k>.<ext>) or prefix "
                "(<prefix>_mip<k>.<ext>)")
      ->required();
  c->add_option("--method", o->method, "toksvig | variance | lean (lean writes r_x, r_y in R, G)")
      ->capture_default_str();
  c->add_option(
       "--ggx-variance", o->ggx_variance,
       "GGX alpha <-> slope variance: beckmann (per-axis alpha^2/2, RTR4 9.13.1 practice) | conty (2 alpha^2 "
       "total, Conty 2019)")
      ->capture_default_str();
  c->add_option("--levels", o->levels, "Number of mip levels to write (0 = down to 1x1)")
      ->capture_default_str();
  c->add_option("--format", o->format, "png (16-bit) | exr (float)")->capture_default_str();
  c->add_flag("--write-normals", o->write_normals, "Also write the renormalized mean normal per level");
  add_json_flag(c, o->json, "Print one JSON object instead of the table");
}

}  // namespace

MSH_CLI_REGISTER(add_filter, 70);

}  // namespace msh::cli
