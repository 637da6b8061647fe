// The mip chain of a texture set and its files (render/multiscale.h): what gen-material writes, built by the
// same box filter as the study's coarse sets.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/npy.h>
#include <microshadow/io/texture.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/multiscale.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace msh::render {

std::vector<TextureSet> texture_set_mip_chain(const TextureSet& fine) {
  std::vector<TextureSet> chain{fine};
  for (int k = 2; fine.height.width() % k == 0 && fine.height.height() % k == 0; k *= 2)
    chain.push_back(downsample_texture_set(fine, k, CoarseRoughness::Base));
  return chain;
}

namespace {
// Channels [c0, c0 + n) of a texture as a volume (n ≤ 4; missing channels 0), mapped by f.
template <class F>
io::Volume channels(const Texture& t, int c0, int n, F f) {
  io::Volume v(t.width(), t.height(), 1, n);
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x)
      for (int c = 0; c < n; ++c)
        v.at(x, y, 0, c) = c0 + c < t.channels() ? f(t.at(x, y, c0 + c), c0 + c) : 0.0f;
  return v;
}
// The compact form's files (K coefficients, 4 per RGBA8 texture, each level the quantised code of that
// level's channels; the writer rounds saturate(u) · 255 as quantize_coefficients does) and its mips.json
// entry.
nlohmann::json write_compact_form(const std::filesystem::path& dir, const std::filesystem::path& m,
                                  const std::vector<const TextureSet*>& chain,
                                  const DirectionalCodec& codec) {
  const int K = codec.coefficients;
  std::vector<Texture> coef;
  for (const TextureSet* s : chain) coef.push_back(encode_directional(s->directional, codec));
  nlohmann::json tex = nlohmann::json::array(), dds = nlohmann::json::array(), png = nlohmann::json::array();
  for (int t = 0; 4 * t < K; ++t) {
    const auto unorm = [&](float a, int k) {
      return (a - codec.lo[std::size_t(k)]) / (codec.hi[std::size_t(k)] - codec.lo[std::size_t(k)]);
    };
    std::vector<io::Volume> levels;
    for (const Texture& a : coef) levels.push_back(channels(a, 4 * t, 4, unorm));
    const std::string name = fmt::format("directional_compact_{}", t);
    io::write_texture_mips(m / (name + ".ktx2"), levels, io::PixelFormat::RGBA8Unorm);
    io::write_texture_mips(m / (name + ".dds"), levels, io::PixelFormat::RGBA8Unorm);
    io::write_volume(dir / (name + ".png"), levels[0], io::FileFormat::Png, io::PixelFormat::RGBA8Unorm);
    tex.push_back(name + ".ktx2"), dds.push_back(name + ".dds"), png.push_back("../" + name + ".png");
  }
  return {{"form", codec.form},
          {"coefficients", K},
          {"channels", codec.channels},
          {"textures", tex},
          {"dds", dds},
          {"png", png},
          {"lo", codec.lo},
          {"hi", codec.hi},
          {"mean", codec.mean},
          {"basis", codec.basis_rows()},
          {"explained", codec.explained},
          {"folded_mean", codec.folded_mean()},
          {"folded_basis", codec.folded_basis_rows()},
          {"decode",
           "a_k = lo_k + (hi_k - lo_k) * unorm_k (coefficient 4t + c in channel c of texture t); channel_i = "
           "mean_i + sum_k basis[i][k] * a_k (equivalently folded_mean_i + sum_k folded_basis[i][k] * "
           "unorm_k); then "
           "the channels as directional.h evaluates them"}};
}

}  // namespace

void write_texture_set_mips(const std::filesystem::path& dir, const TextureSet& fine, bool directional_bc,
                            const std::string& directional_form) {
  // The compact form is fitted (and a bad form refused) before any file is written.
  std::optional<DirectionalCodec> codec;
  if (!directional_form.empty()) {
    if (fine.directional.empty())
      throw InputError("a directional form needs the directional channels (--directional-azimuths > 0)");
    codec = parse_directional_form(directional_form, fine.directional.channels());
    if (codec->bits != 8)
      throw InputError(fmt::format("directional form '{}': gen-material writes the 8-bit forms, pca<K>",
                                   directional_form));
    codec = fit_directional_codec(fine.directional, directional_form);
  }
  write_texture_set_mips(dir, fine, directional_bc, codec ? &*codec : nullptr);
}

void write_texture_set_mips(const std::filesystem::path& dir, const TextureSet& fine, bool directional_bc,
                            const DirectionalCodec* codec) {
  if (codec && (codec->bits != 8 || codec->channels != fine.directional.channels()))
    throw InputError(fmt::format("directional form '{}': an 8-bit code of the set's {} channels expected",
                                 codec->form, fine.directional.channels()));
  const std::filesystem::path m = dir / "mips";
  std::error_code ec;
  std::filesystem::create_directories(m, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", m.string(), ec.message()));
  // texture_set_mip_chain's levels, the fine one by reference (not copied).
  std::vector<TextureSet> coarse;
  for (int k = 2; fine.height.width() % k == 0 && fine.height.height() % k == 0; k *= 2)
    coarse.push_back(downsample_texture_set(fine, k, CoarseRoughness::Base));
  std::vector<const TextureSet*> chain{&fine};
  for (const TextureSet& s : coarse) chain.push_back(&s);
  nlohmann::json j = {{"levels", chain.size()}, {"maps", nlohmann::json::object()}};
  for (const TextureSet* s : chain) j["sizes"].push_back({s->height.width(), s->height.height()});
  const auto identity = [](float x, int) { return x; };
  // One map: its chain in both containers (engine format) and each level exact as NPY.
  const auto write = [&](const std::string& name, Texture TextureSet::*map, int c0, int n, io::PixelFormat pf,
                         const auto& encode, bool npy = true) {
    std::vector<io::Volume> levels;
    for (std::size_t L = 0; L < chain.size(); ++L) {
      const Texture& t = *chain[L].*map;
      levels.push_back(channels(t, c0, n, encode));
      const std::filesystem::path npy_path = m / fmt::format("{}_mip{}.npy", name, L);
      if (npy && c0 == 0 && n == t.channels())  // the texture as it is: written from its own values
        io::write_npy(npy_path, texture_values(t), t.width(), t.height(), 1, n);
      else if (npy)
        io::write_volume(npy_path, channels(t, c0, n, identity), io::FileFormat::Npy);
    }
    io::write_texture_mips(m / (name + ".ktx2"), levels, pf);
    io::write_texture_mips(m / (name + ".dds"), levels, pf);
    j["maps"][name] = {{"ktx2", name + ".ktx2"},
                       {"dds", name + ".dds"},
                       {"format", io::pixel_format_name(pf)},
                       {"channels", n}};
    if (npy) j["maps"][name]["npy"] = fmt::format("{}_mip<L>.npy", name);
  };
  write("normal", &TextureSet::normal, 0, 4, io::PixelFormat::RGBA8Unorm, identity);
  write("roughness", &TextureSet::roughness, 0, 1, io::PixelFormat::R8Unorm, identity);
  write("metallic", &TextureSet::metallic, 0, 1, io::PixelFormat::R8Unorm, identity);
  write("micro_occlusion", &TextureSet::visibility, 0, 1, io::PixelFormat::R8Unorm, identity);
  write("basecolor", &TextureSet::base_color, 0, 4, io::PixelFormat::RGBA16Float, identity);
  write("height", &TextureSet::height, 0, 1, io::PixelFormat::R16Float, identity);
  if (!fine.directional.empty()) {
    // 8-bit UNORM between the fine level's per-channel range: a box mean stays inside it, so every level
    // uses the same range (decode: lo + (hi − lo) · unorm, occlusion/directional.h decode_unorm8).
    const Texture& d = fine.directional;
    const ChannelRanges r = channel_ranges(d);
    const std::vector<float>&lo = r.lo, &hi = r.hi;
    const auto unorm = [&](float x, int c) {
      return (x - lo[std::size_t(c)]) / (hi[std::size_t(c)] - lo[std::size_t(c)]);
    };
    // Four channels per file (the 9: 0–3, 4–7, then 8 alone as R8; the 21 of the view correction: five
    // RGBA8 files, then 20 alone as R8), the packing the shaders take.
    for (int f = 0; 4 * f < d.channels(); ++f) {
      const bool single = d.channels() - 4 * f == 1;
      write(fmt::format("directional_{}", f), &TextureSet::directional, 4 * f, single ? 1 : 4,
            single ? io::PixelFormat::R8Unorm : io::PixelFormat::RGBA8Unorm, unorm);
    }
    // Block-compressed: BC5 pairs, an odd last channel as BC4 (the same ranges; NPY levels already written).
    if (directional_bc)
      for (int f = 0; 2 * f < d.channels(); ++f) {
        const bool single = d.channels() - 2 * f == 1;
        write(fmt::format("directional_bc_{}", f), &TextureSet::directional, 2 * f, single ? 1 : 2,
              single ? io::PixelFormat::BC4Unorm : io::PixelFormat::BC5Unorm, unorm, false);
      }
    j["directional"] = {{"channels", d.channels()},
                        {"lo", lo},
                        {"hi", hi},
                        {"decode", "channel = lo + (hi - lo) * unorm (per channel, every level)"}};
  }
  if (codec) j["directional_compact"] = write_compact_form(dir, m, chain, *codec);
  io::write_file_atomic(m / "mips.json", j.dump(2) + "\n");
}

}  // namespace msh::render
