// The texture set as a glTF 2.0 asset with the MSH_materials_directional_occlusion extension (docs/gltf.md).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/gltf_export.h>
#include <microshadow/render/image.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

namespace msh::render {

namespace {
constexpr int kChannels = directional::kViewChannels;

// The plane: 1 m × 1 m in the xz plane at y = 0, normal +y, u along +x, v along +z (glTF's v runs down the
// image), tangent +x with w = +1: bitangent = cross(N, T) w = −z, toward −v (up the image), glTF's
// convention for a normal map whose green is +Y up.
constexpr float kPos[4][3] = {{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}};
constexpr float kUv[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
constexpr uint16_t kIndices[6] = {0, 2, 1, 1, 2, 3};
constexpr std::size_t kPosBytes = 48, kNrmBytes = 48, kTanBytes = 64, kUvBytes = 32, kIdxBytes = 12;

template <class T>
void append(std::vector<unsigned char>& b, const T& v) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
  b.insert(b.end(), raw, raw + sizeof(T));
}

io::Volume to_volume(const Texture& t, int channels, const auto& f) {
  io::Volume v(t.width(), t.height(), 1, channels);
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x)
      for (int c = 0; c < channels; ++c) v.at(x, y, 0, c) = std::clamp(f(x, y, c), 0.0f, 1.0f);
  return v;
}

std::vector<std::string> directional_images(const DirectionalCode* code) {
  std::vector<std::string> out;
  if (code)
    for (int t = 0; 4 * t < code->k(); ++t) out.push_back(fmt::format("directional_{}.png", t));
  return out;
}
}  // namespace

DirectionalCode identity_directional_code(const Texture& channels21) {
  if (channels21.channels() != kChannels)
    throw InputError(
        fmt::format("the glTF extension {} carries the {} channels of directional-view "
                    "(gen-material --directional-view); the texture set has {}",
                    kGltfDirectionalExtension, kChannels, channels21.channels()));
  DirectionalCode c;
  const ChannelRanges r = channel_ranges(channels21);
  c.lo = r.lo, c.hi = r.hi;
  c.mean.assign(kChannels, 0.0f);
  c.basis.assign(kChannels, std::vector<float>(kChannels, 0.0f));
  for (int i = 0; i < kChannels; ++i) c.basis[std::size_t(i)][std::size_t(i)] = 1;
  c.coefficients = channels21;
  return c;
}

DirectionalCode compact_directional_code(const Texture& channels21, const DirectionalCodec& codec) {
  if (channels21.channels() != kChannels || codec.channels != kChannels || codec.bits != 8)
    throw InputError(
        fmt::format("the glTF extension {} carries an 8-bit code of the {} channels of "
                    "directional-view; got {} channels and form '{}'",
                    kGltfDirectionalExtension, kChannels, channels21.channels(), codec.form));
  DirectionalCode c;
  c.form = codec.form;
  c.lo = codec.lo, c.hi = codec.hi, c.mean = codec.mean;
  c.basis = codec.basis_rows();
  c.coefficients = encode_directional(channels21, codec);
  return c;
}

void check_directional_code(const DirectionalCode& code, int width, int height) {
  const int K = code.k();
  const auto fail = [](const std::string& m) {
    throw InputError(fmt::format("{}: {}", kGltfDirectionalExtension, m));
  };
  if (K < 1 || K > 24) fail(fmt::format("K = {} coefficient channels (1 to 24)", K));
  if (code.coefficients.width() != width || code.coefficients.height() != height)
    fail(fmt::format("the coefficient texture is {}x{}, the texture set {}x{}", code.coefficients.width(),
                     code.coefficients.height(), width, height));
  if (int(code.lo.size()) != K || int(code.hi.size()) != K)
    fail(fmt::format("lo and hi need K = {} entries, got {} and {}", K, code.lo.size(), code.hi.size()));
  if (int(code.mean.size()) != kChannels)
    fail(fmt::format("mean needs {} entries, got {}", kChannels, code.mean.size()));
  if (int(code.basis.size()) != kChannels)
    fail(fmt::format("basis needs {} rows, got {}", kChannels, code.basis.size()));
  for (const auto& row : code.basis)
    if (int(row.size()) != K)
      fail(fmt::format("every basis row needs K = {} entries, one has {}", K, row.size()));
  const auto finite = [](float x) { return std::isfinite(x); };
  bool ok = std::all_of(code.lo.begin(), code.lo.end(), finite) &&
            std::all_of(code.hi.begin(), code.hi.end(), finite) &&
            std::all_of(code.mean.begin(), code.mean.end(), finite);
  for (const auto& row : code.basis) ok = ok && std::all_of(row.begin(), row.end(), finite);
  if (!ok) fail("non-finite lo, hi, mean or basis");
  for (int k = 0; k < K; ++k)
    if (!(code.hi[std::size_t(k)] > code.lo[std::size_t(k)]))
      fail(fmt::format("coefficient {}: hi {} is not above lo {}", k, code.hi[std::size_t(k)],
                       code.lo[std::size_t(k)]));
}

std::vector<unsigned char> texture_set_gltf_bin() {
  std::vector<unsigned char> b;
  for (const auto& p : kPos)
    for (float x : p) append(b, x);
  for (int i = 0; i < 4; ++i)
    for (float x : {0.0f, 1.0f, 0.0f}) append(b, x);
  for (int i = 0; i < 4; ++i)
    for (float x : {1.0f, 0.0f, 0.0f, 1.0f}) append(b, x);
  for (const auto& t : kUv)
    for (float x : t) append(b, x);
  for (uint16_t i : kIndices) append(b, i);
  return b;
}

std::string texture_set_gltf_json(const TextureSet& set, const DirectionalCode* code, const std::string& name,
                                  std::size_t* bin_bytes) {
  using nlohmann::json;
  const std::size_t total = kPosBytes + kNrmBytes + kTanBytes + kUvBytes + kIdxBytes;
  if (bin_bytes) *bin_bytes = total;
  json views = json::array();
  std::size_t off = 0;
  for (const auto& [len, target] : std::vector<std::pair<std::size_t, int>>{{kPosBytes, 34962},
                                                                            {kNrmBytes, 34962},
                                                                            {kTanBytes, 34962},
                                                                            {kUvBytes, 34962},
                                                                            {kIdxBytes, 34963}}) {
    views.push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", len}, {"target", target}});
    off += len;
  }
  json accessors = {{{"bufferView", 0},
                     {"componentType", 5126},
                     {"count", 4},
                     {"type", "VEC3"},
                     {"min", {-0.5, 0.0, -0.5}},
                     {"max", {0.5, 0.0, 0.5}}},
                    {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                    {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}},
                    {{"bufferView", 3}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                    {{"bufferView", 4}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}};
  std::vector<std::string> images = {"basecolor.png", "normal.png", "orm.png"};
  for (const auto& f : directional_images(code)) images.push_back(f);
  json jimages = json::array(), textures = json::array();
  for (std::size_t i = 0; i < images.size(); ++i) {
    jimages.push_back({{"uri", images[i]}, {"mimeType", "image/png"}});
    textures.push_back({{"source", i}, {"sampler", 0}});
  }
  json material = {{"name", name},
                   {"pbrMetallicRoughness",
                    {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 2}}}}},
                   {"normalTexture", {{"index", 1}}},
                   {"occlusionTexture", {{"index", 2}}}};
  json g = {{"asset", {{"version", "2.0"}, {"generator", "microshadow gen-material --gltf"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}, {"name", name}}}},
            {"meshes",
             {{{"name", name},
               {"primitives",
                {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TANGENT", 2}, {"TEXCOORD_0", 3}}},
                  {"indices", 4},
                  {"material", 0}}}}}}},
            {"buffers", {{{"uri", name + ".bin"}, {"byteLength", total}}}},
            {"bufferViews", views},
            {"accessors", accessors},
            {"samplers", {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}}},
            {"images", jimages},
            {"textures", textures}};
  if (code) {
    check_directional_code(*code, set.base_color.width(), set.base_color.height());
    json tex = json::array();
    for (std::size_t t = 0; t < directional_images(code).size(); ++t) tex.push_back({{"index", 3 + t}});
    material["extensions"][kGltfDirectionalExtension] = {{"form", code->form},    {"coefficients", code->k()},
                                                         {"channels", kChannels}, {"textures", tex},
                                                         {"lo", code->lo},        {"hi", code->hi},
                                                         {"mean", code->mean},    {"basis", code->basis}};
    g["extensionsUsed"] = {kGltfDirectionalExtension};
  }
  g["materials"] = {material};
  return g.dump(1) + "\n";
}

void write_texture_set_gltf(const std::filesystem::path& dir, const TextureSet& set,
                            const DirectionalCode* code, const std::string& name) {
  namespace fs = std::filesystem;
  const int w = set.base_color.width(), h = set.base_color.height();
  for (const Texture* t : {&set.normal, &set.roughness, &set.metallic, &set.visibility})
    if (t->width() != w || t->height() != h)
      throw InputError(fmt::format("glTF export: the texture set's maps differ in size ({}x{} and {}x{})", w,
                                   h, t->width(), t->height()));
  if (code) check_directional_code(*code, w, h);
  const std::string text = texture_set_gltf_json(set, code, name);  // before any file is written
  const fs::path target = fs::absolute(dir).lexically_normal();
  const fs::path tmp =
      target.parent_path() / fmt::format(".{}.tmp-{}", target.filename().string(), ::getpid());
  std::error_code ec;
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", tmp.string(), ec.message()));
  try {
    io::write_png(tmp / "basecolor.png", to_volume(set.base_color, 3, [&](int x, int y, int c) {
                    return srgb_encode(set.base_color.at(x, y, c));
                  }));
    // glTF's normal texture: green = +Y up the image, the texture set's runs down it (+v).
    io::write_png(tmp / "normal.png", to_volume(set.normal, 3, [&](int x, int y, int c) {
                    const float n = set.normal.at(x, y, c);
                    return c == 1 ? 1.0f - n : n;
                  }));
    io::write_png(tmp / "orm.png", to_volume(set.visibility, 3, [&](int x, int y, int c) {
                    const Texture& t = c == 0 ? set.visibility : c == 1 ? set.roughness : set.metallic;
                    return t.at(x, y, 0);
                  }));
    const auto dir_images = directional_images(code);
    for (std::size_t t = 0; t < dir_images.size(); ++t) {
      const int K = code->k();
      io::write_png(tmp / dir_images[t], to_volume(code->coefficients, 4, [&](int x, int y, int c) {
                      const int k = int(4 * t) + c;
                      if (k >= K) return c == 3 ? 1.0f : 0.0f;  // unused (alpha opaque)
                      const float lo = code->lo[std::size_t(k)], hi = code->hi[std::size_t(k)];
                      return (code->coefficients.at(x, y, k) - lo) / (hi - lo);
                    }));
    }
    const auto bin = texture_set_gltf_bin();
    io::write_file_atomic(
        tmp / (name + ".bin"),
        std::span<const std::byte>(reinterpret_cast<const std::byte*>(bin.data()), bin.size()));
    io::write_file_atomic(tmp / (name + ".gltf"), text);
    if (fs::exists(target)) fs::remove_all(target);
    io::rename_recorded_directory(tmp, target);
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
}

}  // namespace msh::render
